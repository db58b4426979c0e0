!> Subcycling (&solver subcycle): a step in which each node advances at the rate its stiffest
!! point needs while the rest of the body takes the step once. The nodal partition of
!! Belytschko, Yen and Mullen (CMAME 17/18, 1979, "mixed methods for time integration"),
!! with rates in powers of two, in the central-difference form of eqs. (62)-(64):
!!   - a point's level l is the largest with 2^l dref <= its critical-step estimate (dref:
!!     the smallest estimate, so that dref cfl is the plain step; with a fixed step, its
!!     share); a node takes the lowest level of its points, a point the lowest of its nodes;
!!   - a step of levels L (dt = 2^L cfl dref) moves a node of level l over 2^r sub-steps
!!     dt/2^r, its rate r = max(0, L - l), and updates a point at the rate of its fastest
!!     node, so no point is ever stepped beyond its own critical step;
!!   - a node's step starts with its prediction (64) and contact's corrections (93)-(98);
!!     a point's step ends with its nodes where they are at that time: at the end of their
!!     own step, or (a slower node in the middle of its step) on that step's trajectory
!!     d_n + tau v_n + tau^2/2 a_n; then the force of eq. (62) at the nodes whose step ends
!!     there, and their velocities (63) over their own step.
!! The step's prediction and first contact pass (the driver's) move the nodes of rate 0,
!! and its internal force and update (the driver's) end every rate's step together. L
!! minimises the estimated work per unit time (point updates, plus a fixed cost for each
!! rate's step and each step), with a fixed step the smallest L that brings the finest
!! sub-step under cfl x the critical step. Only element meshes (interpolating nodes, so a
!! contact force on a node moves that node only) against rigid masters subcycle; the deck
!! reader refuses other scenes.
module subcycle_m
  use omp_lib, only: omp_get_wtime
  use kinds_m, only: wp, i64
  use errors_m, only: error_t
  use solid_m, only: solid_t, solid_sub_levels, solid_sub_select, solid_sub_begin, &
    solid_rate_predict, solid_rates_force, solid_rates_update, solid_sub_end
  use contact_pair_m, only: contact_pair_t, contact_step, contact_stats_t
  use stable_step_m, only: step_control_t, step_control_next, landing_slack
  implicit none
  private
  public :: subcycle_record_t, subcycle_next, subcycle_rates, subcycle_end, sub_levels_max

  !> At most 2^sub_levels_max sub-steps in a step.
  integer, parameter :: sub_levels_max = 10
  !> Fixed costs in point updates per point of the bodies: each rate's step (its contact
  !! pass and the loops' start) and each step (the levels, the lists, the first contact
  !! pass over every slave node); measured on the FEM Taylor bar (doc/benchmarks.md,
  !! "Subcycling").
  real(wp), parameter :: cost_rate_step = 0.01_wp, cost_step = 0.1_wp

  !> What subcycling did over the run (summary, log, checkpoint).
  type :: subcycle_record_t
    integer(i64) :: steps = 0        !< steps that subcycled
    integer(i64) :: substeps = 0     !< their finest sub-steps
    integer(i64) :: fine_evals = 0   !< point updates inside the steps (not at their ends)
    integer(i64) :: uniform_evals = 0   !< the same, had every point taken the finest step
    integer :: m_max = 1             !< most finest sub-steps in a step
  end type subcycle_record_t

contains

  !> The next step from time t towards t_target (step_control_next's rules), and, with on,
  !! its levels and each solid's rates and lists (solid_sub_select; levels 0: a plain
  !! step). Solids that skip quiet points do not subcycle until every point is active.
  function subcycle_next(c, solids, t, t_target, on, rec) result(dt)
    type(step_control_t), intent(inout) :: c
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: t, t_target
    logical, intent(in) :: on
    type(subcycle_record_t), intent(inout) :: rec
    real(wp) :: dt
    integer :: k, l, v, r, lbest, lfix
    integer :: npt(0:sub_levels_max), nnd(0:sub_levels_max)
    integer :: spt(0:sub_levels_max), snd(0:sub_levels_max)
    real(wp) :: dref, cost, cbest, nqt, rest, work, events
    logical :: ready
    ready = on .and. size(solids) > 0
    do k = 1, size(solids)
      ready = ready .and. solids(k)%sub%on .and. solids(k)%all_awake
    end do
    lfix = 0
    if (ready .and. .not. c%adaptive) then
      ! the fixed step: the fewest levels that bring the finest sub-step under cfl x dt_crit
      do while (c%dt_fixed/2.0_wp**lfix > c%cfl*c%dtc .and. lfix < sub_levels_max)
        lfix = lfix + 1
      end do
      ready = lfix > 0
    end if
    if (.not. ready) then
      dt = step_control_next(c, t, t_target)
      return
    end if
    if (c%adaptive) then
      dref = c%dtc
    else
      dref = c%dt_fixed/(c%cfl*2.0_wp**lfix)
    end if
    spt = 0
    snd = 0
    nqt = 0.0_wp
    do k = 1, size(solids)
      call solid_sub_levels(solids(k), dref, sub_levels_max, npt, nnd)
      spt = spt + npt
      snd = snd + nnd
      nqt = nqt + real(solids(k)%nq, wp)
    end do
    if (c%adaptive) then
      ! work per unit time (in units of point updates per plain step) of L levels: a
      ! point of level v updates 2^max(0, L - v) times a step, each nonempty rate r steps
      ! 2^r times, and the step has its own cost; the step is 2^L plain steps long
      ! (no more levels than the slowest points have: the step is then theirs, and the
      ! history, log and guards still come every such step)
      lbest = 0
      cbest = huge(1.0_wp)
      do l = 0, findloc(spt > 0, .true., dim=1, back=.true.) - 1
        work = 0.0_wp
        do v = 0, sub_levels_max
          work = work + real(spt(v), wp)*2.0_wp**max(0, l - v)
        end do
        events = 0.0_wp
        do r = 1, l
          if (snd(l - r) > 0) events = events + 2.0_wp**r
        end do
        cost = (work + nqt*(cost_rate_step*events + cost_step))/2.0_wp**l
        if (cost < cbest) then
          cbest = cost
          lbest = l
        end if
      end do
      if (lbest == 0) then
        dt = step_control_next(c, t, t_target)
        return
      end if
      dt = 2.0_wp**lbest*c%cfl*c%dtc
      rest = t_target - t
      if (rest <= dt*(1.0_wp + landing_slack)) then
        dt = rest
      else if (rest < 2.0_wp*dt) then
        dt = 0.5_wp*rest
      end if
      c%dt_max = max(c%dt_max, dt)
    else
      lbest = lfix
      dt = c%dt_fixed
      ! the finest sub-step above the estimate: only when sub_levels_max levels fall short
      if (dt/2.0_wp**lbest > c%dtc) c%n_over = c%n_over + 1
    end if
    do k = 1, size(solids)
      call solid_sub_select(solids(k), lbest, dt)
    end do
    rec%steps = rec%steps + 1
    rec%substeps = rec%substeps + 2**lbest
    rec%m_max = max(rec%m_max, 2**lbest)
  end function subcycle_next

  !> The rates' steps inside a subcycled step dt (after the step's prediction and first
  !! contact pass, which moved the nodes of rate 0): at each finest sub-step k of 2^L, the
  !! rates whose step starts at (k-1) dt/2^L predict and are corrected by contact, and (but
  !! at k = 2^L, which the driver's internal force and update end) the rates whose step ends
  !! at k dt/2^L update their points, forces and velocities. cstep: the step's contact
  !! statistics, to which the rates' are added (the largest counts and values over each
  !! rate's steps, the mean normal force over the step). A health problem ends the step
  !! early with bad_q > 0 in solid k_bad (0: none). t: the time at the step's start (s).
  subroutine subcycle_rates(pairs, solids, t, dt, cstep, rec, t_contact, k_bad, bad_q, &
    bad_j, err)
    type(contact_pair_t), intent(inout) :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    real(wp), intent(in) :: t, dt
    type(contact_stats_t), intent(inout) :: cstep
    type(subcycle_record_t), intent(inout) :: rec
    real(wp), intent(inout) :: t_contact   !< wall time in contact (s), added to
    integer, intent(out) :: k_bad, bad_q
    real(wp), intent(out) :: bad_j
    type(error_t), allocatable, intent(inout) :: err
    type(contact_stats_t) :: cs
    type(contact_stats_t) :: acc(sub_levels_max)
    integer :: lv, n, k, r, j, rstart, smin
    real(wp) :: t0
    logical :: any_nodes
    k_bad = 0
    bad_q = 0
    bad_j = 1.0_wp
    if (size(solids) == 0) return
    lv = solids(1)%sub%levels
    if (lv == 0) return
    do j = 1, size(solids)
      call solid_sub_begin(solids(j), 0)
    end do
    n = 2**lv
    do k = 1, n
      ! the rates whose step starts at (k - 1) dt/2^L: all at k = 1, then those of at
      ! least L - (trailing zero bits of k - 1)
      rstart = 1
      if (k > 1) rstart = max(1, lv - trailz(k - 1))
      do r = rstart, lv
        any_nodes = .false.
        do j = 1, size(solids)
          call solid_rate_predict(solids(j), r)
          any_nodes = any_nodes .or. solids(j)%sub%nptr(r + 1) > solids(j)%sub%nptr(r)
        end do
        if (any_nodes) then
          t0 = omp_get_wtime()
          ! (the sub-step of rate r from (k - 1) dt/2^L to that + dt/2^r)
          call contact_step(pairs, solids, dt/2.0_wp**r, t + real(k - 1, wp)*dt/2.0_wp**lv + &
            dt/2.0_wp**r, cs, err)
          t_contact = t_contact + (omp_get_wtime() - t0)
          if (allocated(err)) return
          call stats_max(acc(r), cs, 2.0_wp**(-r))
        end if
        do j = 1, size(solids)
          call solid_sub_begin(solids(j), r)
        end do
      end do
      if (k == n) exit
      ! the rates whose step ends at k dt/2^L
      smin = lv - trailz(k)
      do j = 1, size(solids)
        call solid_rates_force(solids(j), smin, k, bad_q, bad_j)
        rec%fine_evals = rec%fine_evals + (solids(j)%sub%qptr(lv + 1) - solids(j)%sub%qptr(smin))
        rec%uniform_evals = rec%uniform_evals + solids(j)%nq
        if (bad_q > 0) then
          k_bad = j
          exit
        end if
        call solid_rates_update(solids(j), smin)
      end do
      if (k_bad > 0) exit
    end do
    do j = 1, size(solids)
      solids(j)%sub%rate = -1
    end do
    ! the step's first pass acted on the nodes of rate 0, each rate's passes on its own
    do r = 1, lv
      cstep%n_contact = cstep%n_contact + acc(r)%n_contact
      cstep%n_flagged = cstep%n_flagged + acc(r)%n_flagged
      cstep%n_cmp_det = cstep%n_cmp_det + acc(r)%n_cmp_det
      cstep%n_cmp_gap = cstep%n_cmp_gap + acc(r)%n_cmp_gap
      cstep%force_normal = cstep%force_normal + acc(r)%force_normal
      cstep%radius = max(cstep%radius, acc(r)%radius)
      cstep%pen_before = max(cstep%pen_before, acc(r)%pen_before)
      cstep%pen_after = max(cstep%pen_after, acc(r)%pen_after)
      cstep%edge_in_contact = cstep%edge_in_contact .or. acc(r)%edge_in_contact
    end do
  end subroutine subcycle_rates

  !> Keep in a the largest counts and values of c, and add the share w of c's mean force.
  pure subroutine stats_max(a, c, w)
    type(contact_stats_t), intent(inout) :: a
    type(contact_stats_t), intent(in) :: c
    real(wp), intent(in) :: w
    a%n_contact = max(a%n_contact, c%n_contact)
    a%n_flagged = max(a%n_flagged, c%n_flagged)
    a%n_cmp_det = max(a%n_cmp_det, c%n_cmp_det)
    a%n_cmp_gap = max(a%n_cmp_gap, c%n_cmp_gap)
    a%force_normal = a%force_normal + w*c%force_normal
    a%radius = max(a%radius, c%radius)
    a%pen_before = max(a%pen_before, c%pen_before)
    a%pen_after = max(a%pen_after, c%pen_after)
    a%edge_in_contact = a%edge_in_contact .or. c%edge_in_contact
  end subroutine stats_max

  !> The step is over (after the driver's internal force and update).
  subroutine subcycle_end(solids)
    type(solid_t), intent(inout) :: solids(:)
    integer :: k
    do k = 1, size(solids)
      if (solids(k)%sub%levels > 0) call solid_sub_end(solids(k))
    end do
  end subroutine subcycle_end
end module subcycle_m
