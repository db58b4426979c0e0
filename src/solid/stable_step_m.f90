!> The time step of the central-difference scheme.
!!
!! Critical step of a body, dt_crit = 2/omega_max, with omega_max^2 the largest eigenvalue
!! of M^-1 K (lumped M, small-strain elastic K built from the solver's own tables) found by
!! power iteration in the reference configuration; the simple estimate h_min/c_d for the log.
!!
!! During the run the critical step follows the deformation: each solid tracks
!! kappa = max_L tr(C_L^-1 G_L) + H_L/F33^2 over its integration points (solid_m,
!! step_metric), whose square root scales like omega_max, so
!!   dt_crit(t) = dt_crit(0) sqrt(kappa(0)/kappa(t))
!! calibrated once by the power iteration. With dt = 0 in the deck the step is
!! dt_{n+1} = cfl x min over solids of dt_crit(t_{n+1}), clipped to land on the snapshot
!! times and t_end (step_control_next). The scheme (64), (63) uses a_n computed at d_n
!! whatever dt_n is, so each step is the same second-order velocity-Verlet map with its
!! own dt: local error O(dt_n^3), global error O(max dt^2), no start-up or history terms
!! to correct when dt changes.
module stable_step_m
  use kinds_m, only: wp
  use strings_m, only: itoa, rtoa
  use solid_m, only: solid_t, solid_step_estimate
  use tl_kinematics_m, only: linear_elastic_piola, deformation_gradient_list, &
    internal_force_list, jacobian
  use exact_sum_m, only: exact_sum_t, exact_add, exact_value, exact_allsum
  use rank_comm_m, only: rank_comm_t
  implicit none
  private
  public :: critical_step, spacing_step
  public :: step_control_t, step_control_calibrate, step_control_update, step_control_next
  public :: step_limit_text, step_smallest

  !> A run whose critical step falls below this fraction of its initial value is stopped:
  !! some cell or element is collapsing (J -> 0 or a sliver), and stepping on would take
  !! a thousand times the planned number of steps to go nowhere.
  real(wp), parameter, public :: dt_collapse = 1.0e-3_wp
  !> A step whose planned size reaches within this relative amount of the rest of the way to
  !! the next stop lands on it: the rest is a difference of times of a few ulps' error, and
  !! a step of 1 + 1e-9 times the planned one is no stability risk (cfl <= 1).
  real(wp), parameter, public :: landing_slack = 1.0e-9_wp

  !> The time-step policy of a run and what it has done.
  type :: step_control_t
    logical :: adaptive = .true.          !< dt follows the deformation (deck dt = 0)
    real(wp) :: cfl = 0.5_wp              !< fraction of the critical step (adaptive)
    real(wp) :: dt_fixed = 0.0_wp         !< the deck's fixed step (s), when not adaptive
    real(wp) :: dtc0 = 0.0_wp             !< critical step at t = 0 (power iteration) (s)
    real(wp) :: dtc = 0.0_wp              !< current critical step estimate (s)
    integer :: solid = 0, point = 0       !< where the current estimate is set
    real(wp) :: dt_min = huge(1.0_wp), dt_max = 0.0_wp   !< steps taken (s)
    real(wp) :: t_dt_min = 0.0_wp         !< time at the end of the smallest step (s)
    !> the smallest step taken, landing steps included, and the time at its end (s): what
    !! the record reports when every step was shortened to land on an output time
    real(wp) :: dt_min_taken = huge(1.0_wp), t_dt_min_taken = 0.0_wp
    real(wp) :: dtc_min = huge(1.0_wp)    !< smallest critical step estimate (s)
    integer :: solid_min = 0, point_min = 0   !< where it was set
    integer :: n_over = 0                 !< steps where a fixed dt exceeded the estimate
  end type step_control_t

contains

  !> h_min / c_d (s).
  pure real(wp) function spacing_step(tb) result(dt)
    type(solid_t), intent(in) :: tb
    dt = tb%t%hmin/tb%mat%dilatational_speed()
  end function spacing_step

  !> 2/omega_max by power iteration on M^-1 K (60 iterations from a saw-tooth start, which
  !! is close to the highest mode of a lattice); prescribed components are held at zero.
  !! The Rayleigh quotient converges from below, so the step is padded by 2% (the result
  !! of 60 iterations is within 1% of a converged value on lattice bodies).
  !!
  !! On a rank's part (tb%part%on; comm its ranks, collective) each rank iterates on its own
  !! nodes and points: the ghost nodes' x and the ghost points' P (and SCNI stabilization
  !! stresses) come from their owners, so K x at the owned nodes is the serial one to the bit
  !! (as the time loop's forces are), and the two dot products of an iteration are exact
  !! sums (exact_sum_m) over the owned nodes: the step is the same bits on any number of
  !! ranks, and no rank needs the whole solid's tables. The start is a function of the
  !! global node number (tb%part%nglob).
  function critical_step(tb, comm) result(dt)
    type(solid_t), intent(in) :: tb
    class(rank_comm_t), intent(inout), optional :: comm
    real(wp) :: dt
    real(wp), allocatable :: x(:, :), y(:, :), f(:, :), p(:, :), sw(:, :)
    integer, allocatable :: own_n(:), own_q(:)
    type(exact_sum_t) :: acc
    real(wp) :: lam, mu, omega2, nrm, es
    integer :: it, q, i, c, nd, k, ig, nn, nq, free(1)
    logical :: stab
    nd = tb%t%dims%ndim
    stab = tb%opt%stab_normal > 0.0_wp
    allocate(x(nd, tb%np), y(nd, tb%np), f(tb%t%dims%nf, tb%nq), p(tb%t%dims%nf, tb%nq), &
      sw(tb%t%dims%nstab, tb%nq))
    if (tb%part%on) then
      own_n = tb%part%own_n
      own_q = tb%part%own_q
    else
      own_n = [(i, i = 1, tb%np)]
      own_q = [(q, q = 1, tb%nq)]
    end if
    nn = size(own_n)
    nq = size(own_q)
    lam = tb%mat%lambda
    mu = tb%mat%g
    do i = 1, tb%np
      ig = i
      if (tb%part%on) ig = tb%part%nglob(i)
      x(:, i) = real(1 - 2*mod(ig, 2), wp)*[(real(1 - 2*mod(c + 1, 2), wp), c = 1, nd)] &
        + 0.1_wp*real(mod(ig, 7), wp)
    end do
    where (tb%pres) x = 0.0_wp
    y = 0.0_wp
    f = 0.0_wp
    p = 0.0_wp
    sw = 0.0_wp
    omega2 = 0.0_wp
    ! every component prescribed (a driven plate): no free mode limits the step
    dt = huge(1.0_wp)
    free = 0
    do k = 1, nn
      if (.not. all(tb%pres(:, own_n(k)))) free = 1
    end do
    if (present(comm)) then
      free = -free
      call comm%min_int(free)
      free = -free
    end if
    if (free(1) == 0) return
    do it = 1, 60
      acc = exact_sum_t()
      do k = 1, nn
        i = own_n(k)
        do c = 1, nd
          call exact_add(acc, tb%t%mass(i)*x(c, i)*x(c, i))
        end do
      end do
      nrm = sqrt(total(acc))
      x = x/nrm
      if (associated(tb%part%halo)) call tb%part%halo%nodes(x)
      if (stab) then
        call deformation_gradient_list(tb%t, x, f, own_q, nq, &
          [tb%opt%stab_normal, tb%opt%stab_shear], sw, es)
      else
        call deformation_gradient_list(tb%t, x, f, own_q, nq)
      end if
      do k = 1, nq
        q = own_q(k)
        call linear_elastic_piola(lam, mu, f(:, q), p(:, q))
      end do
      if (associated(tb%part%halo)) then
        call tb%part%halo%points(p)
        if (stab) call tb%part%halo%points(sw)
      end if
      if (stab) then
        call internal_force_list(tb%t, p, y, own_n, nn, sw)
      else
        call internal_force_list(tb%t, p, y, own_n, nn)
      end if
      where (tb%pres) y = 0.0_wp
      acc = exact_sum_t()
      do k = 1, nn
        i = own_n(k)
        do c = 1, nd
          call exact_add(acc, x(c, i)*y(c, i))
        end do
      end do
      omega2 = total(acc)
      do k = 1, nn
        i = own_n(k)
        x(:, i) = y(:, i)/tb%t%mass(i)
      end do
    end do
    dt = 2.0_wp/sqrt(1.02_wp*omega2)
  contains
    real(wp) function total(a)
      type(exact_sum_t), intent(in) :: a
      if (present(comm)) then
        total = exact_allsum(a, comm)
      else
        total = exact_value(a)
      end if
    end function total
  end function critical_step

  !> Calibrate each solid's estimate against its power-iteration critical step and set the
  !! starting values of c: dt_cal = dt_crit(0) sqrt(kappa(0)). On ranks' parts (comm
  !! present; collective) kappa(0) is the largest over the owned points of all the ranks.
  subroutine step_control_calibrate(c, solids, comm)
    type(step_control_t), intent(inout) :: c
    type(solid_t), intent(inout) :: solids(:)
    class(rank_comm_t), intent(inout), optional :: comm
    integer :: k
    real(wp) :: dtk
    do k = 1, size(solids)
      if (present(comm)) then
        dtk = critical_step(solids(k), comm)
        if (solids(k)%part%on) call kappa0_parts(solids(k), comm)
      else
        dtk = critical_step(solids(k))
      end if
      solids(k)%dt_cal = huge(1.0_wp)
      if (dtk < huge(1.0_wp)) solids(k)%dt_cal = dtk*sqrt(solids(k)%kappa0)
    end do
    call step_control_update(c, solids)
    c%dtc0 = c%dtc
  end subroutine step_control_calibrate

  !> A part's kappa(0) and where it is: the largest over the owned points of all the ranks
  !! and, among equals, the lowest number in the whole solid (the serial point). Collective.
  subroutine kappa0_parts(s, comm)
    type(solid_t), intent(inout) :: s
    class(rank_comm_t), intent(inout) :: comm
    integer :: j, q, qb, g(1)
    real(wp) :: v(1), vb
    vb = 0.0_wp
    qb = 0
    do j = 1, size(s%part%own_q)
      q = s%part%own_q(j)
      if (qb == 0) then
        qb = q
        vb = s%kap0(q)
      else if (s%kap0(q) > vb .or. (s%kap0(q) == vb .and. &
        s%part%qglob(q) < s%part%qglob(qb))) then
        qb = q
        vb = s%kap0(q)
      end if
    end do
    v = vb
    call comm%max_real(v)
    s%kappa0 = v(1)
    s%kappa = v(1)
    if (qb > 0) s%kappa_q = qb
    g = huge(1)
    if (qb > 0 .and. vb == v(1)) g = s%part%qglob(qb)
    call comm%min_int(g)
    s%kappa_g = g(1)
  end subroutine kappa0_parts

  !> The current critical step estimate (min over solids) and where it is set; after the
  !! internal forces of a step.
  subroutine step_control_update(c, solids)
    type(step_control_t), intent(inout) :: c
    type(solid_t), intent(in) :: solids(:)
    integer :: k
    real(wp) :: e
    c%dtc = huge(1.0_wp)
    do k = 1, size(solids)
      e = solid_step_estimate(solids(k))
      if (e < c%dtc) then
        c%dtc = e
        c%solid = k
        c%point = solids(k)%kappa_g
      end if
    end do
    if (c%dtc < c%dtc_min) then
      c%dtc_min = c%dtc
      c%solid_min = c%solid
      c%point_min = c%point
    end if
  end subroutine step_control_update

  !> The next step from time t: the fixed step, or cfl x the current critical step; clipped
  !! so that it lands on t_target (the next snapshot time or t_end) without leaving a sliver:
  !! when less than two steps remain, the remainder is split evenly.
  function step_control_next(c, t, t_target) result(dt)
    type(step_control_t), intent(inout) :: c
    real(wp), intent(in) :: t, t_target
    real(wp) :: dt, rest
    if (.not. c%adaptive) then
      dt = c%dt_fixed
      if (dt > c%dtc) c%n_over = c%n_over + 1
    else
      dt = c%cfl*c%dtc
      rest = t_target - t
      if (rest <= dt*(1.0_wp + landing_slack)) then
        dt = rest
      else if (rest < 2.0_wp*dt) then
        dt = 0.5_wp*rest
      end if
    end if
    ! the record leaves out the steps shortened to land on a snapshot time or t_end
    c%dt_max = max(c%dt_max, dt)
    if (dt < c%dt_min .and. (dt == c%dt_fixed .or. dt == c%cfl*c%dtc)) then
      c%dt_min = dt
      c%t_dt_min = t + dt
    end if
    if (dt < c%dt_min_taken) then
      c%dt_min_taken = dt
      c%t_dt_min_taken = t + dt
    end if
  end function step_control_next

  !> The smallest step of the record and the time at its end (s): the smallest step not
  !! shortened to land on an output time, or, when every step was (output times closer
  !! than two steps), the smallest step taken; landed: it is the latter.
  pure subroutine step_smallest(c, dt, t, landed)
    type(step_control_t), intent(in) :: c
    real(wp), intent(out) :: dt, t
    logical, intent(out) :: landed
    landed = .not. (c%dt_min < huge(1.0_wp))
    dt = merge(c%dt_min_taken, c%dt_min, landed)
    t = merge(c%t_dt_min_taken, c%t_dt_min, landed)
    if (.not. (dt < huge(1.0_wp))) dt = 0.0_wp
  end subroutine step_smallest

  !> 'body 'B', integration point L (particle I), J = .., min stretch ..': where the critical
  !! step estimate (current, or the smallest when smallest) is set.
  function step_limit_text(c, solids, smallest) result(txt)
    type(step_control_t), intent(in) :: c
    type(solid_t), intent(in) :: solids(:)
    logical, intent(in) :: smallest
    character(len=:), allocatable :: txt
    integer :: k, q
    k = merge(c%solid_min, c%solid, smallest)
    q = merge(c%point_min, c%point, smallest)
    if (k < 1 .or. q < 1) then
      txt = 'nothing'
      return
    end if
    txt = 'body '''//trim(solids(k)%name)//''', integration point '//itoa(q)
    ! (an MPI run's rank 0 may hold only the whole solid's sizes, or its part, whose
    ! numbers are not the whole solid's: then the point alone)
    if (solids(k)%part%on) return
    if (.not. allocated(solids(k)%t%owner)) return
    if (q > size(solids(k)%t%owner)) return
    if (solids(k)%t%owner(q) > 0) txt = txt//' (particle '//itoa(solids(k)%t%owner(q))//')'
    if (.not. smallest) txt = txt//', J = '//rtoa(jacobian(solids(k)%state%f(:, q)))
  end function step_limit_text
end module stable_step_m
