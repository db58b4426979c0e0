!> Contact pairs of a dynamic run (deck group &contact), Sections 2 and 5.
!!
!! Each side of a pair is a body with its det(M) cloud and its surface. A rigid side never
!! moves: its cloud, bins and surface are built once. A deformable side is re-binned at its
!! predicted positions every step. Each step, between the prediction (64) and the force
!! evaluation (62), a pass from side A (slave) to side B (master) screens A's particles by
!! B's grown bounding box, evaluates det(M_B) at their predicted physical positions, measures
!! the gap of the detected ones to B's closest segment, computes the eq. (93)-(96) force at
!! each penetrating particle (with the reduced mass when B moves), applies the reaction to
!! the ends of B's segment, redistributes the particle forces to the RK coefficients by
!! eq. (98), and corrects a_n and the prediction. With a rigid master one pass is made (the
!! first condition of eq. 28); when both bodies deform, a second pass swaps the roles (both
!! conditions of eq. 28).
module contact_pair_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use deck_m, only: deck_t
  use body_m, only: body_t
  use rk_cloud_m, only: rk_cloud_t, cloud_det, cloud_init, cloud_move
  use bodies_m, only: body_cloud
  use detection_m, only: body_plateau, detection_threshold
  use contact_m, only: master_surface_t, surface_build, surface_update, surface_gap, &
    contact_point_force, contact_counters_t
  use tl_body_m, only: tl_body_t
  use tl_kinematics_m, only: physical_positions
  implicit none
  private
  public :: contact_pair_t, contact_pairs_init, contact_correct, contact_stats_t
  public :: contact_det_fields

  !> What one step's contact did (for the log, history and summary).
  type :: contact_stats_t
    integer :: n_contact = 0            !< particles with a force this step
    !> Mean normal contact force over the step (N, N/m in plane strain): half the sum of the
    !! eq. (93) forces, since a force added to a_n gives the velocity the impulse dt/2 f
    !! (eq. 63) and is absent at n+1.
    real(wp) :: force_normal = 0.0_wp
    real(wp) :: radius = 0.0_wp         !< largest x1 of a contacting particle (m)
    real(wp) :: pen_before = 0.0_wp     !< deepest predicted penetration (m, >= 0)
    real(wp) :: pen_after = 0.0_wp      !< deepest penetration left after the correction (m)
    logical :: edge_in_contact = .false.
  end type contact_stats_t

  !> One body of a pair as contact sees it.
  type :: side_t
    integer :: ibody = 0                 !< deck body index
    integer :: itb = 0                   !< index among the deformable bodies; 0 if rigid
    integer :: np = 0
    type(rk_cloud_t) :: cloud            !< det(M) of this body (current positions)
    type(master_surface_t) :: surface
    real(wp) :: plateau = 0.0_wp, threshold = 0.0_wp
    real(wp) :: surface_det = 0.0_wp     !< median det(M) at the body's own boundary particles
    real(wp) :: lo(2) = 0.0_wp, hi(2) = 0.0_wp   !< box grown by the largest support
    real(wp), allocatable :: x_old(:, :), x_pred(:, :)  !< physical positions (2, np)
    real(wp), allocatable :: rho(:, :)   !< supports (2, np): reach of the segment search
    real(wp), allocatable :: fphys(:, :) !< contact forces at the particles this pass (N)
    logical, allocatable :: active(:)    !< particle carries a force this pass
    integer, allocatable :: seg(:)       !< the segment each penetrating particle hit
    real(wp), allocatable :: xi(:)       !< where on it
    real(wp), allocatable :: mass(:)     !< particle masses (kg); 0 for a rigid side
  end type side_t

  type :: contact_pair_t
    type(side_t) :: side(2)              !< 1: slave, 2: master
    real(wp) :: eps_cr = 0.0_wp, eps_rel = 0.0_wp, mu = 0.0_wp
    integer :: edge = 0                  !< slave particle tracked for separation (0: none)
    logical :: both_ways = .false.       !< both bodies deform: eq. (28) both conditions
    type(contact_counters_t) :: count
    type(contact_stats_t) :: step
  end type contact_pair_t

contains

  !> Build the pairs of the deck: clouds, surfaces, thresholds and work arrays.
  subroutine contact_pairs_init(deck, bodies, tbs, axisym, pairs, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(tl_body_t), intent(in) :: tbs(:)
    logical, intent(in) :: axisym
    type(contact_pair_t), allocatable, intent(out) :: pairs(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, j, sd, ib
    real(wp) :: best
    allocate(pairs(deck%ncontacts))
    do k = 1, deck%ncontacts
      associate (p => pairs(k), cs => deck%contacts(k))
        p%eps_cr = cs%eps_cr
        p%eps_rel = cs%eps_rel
        p%mu = cs%mu
        do sd = 1, 2
          ib = merge(cs%islave, cs%imaster, sd == 1)
          call side_init(p%side(sd), bodies(ib), ib, tbs, axisym, p%eps_cr, p%eps_rel, err)
          if (allocated(err)) return
          if (p%side(sd)%surface%nseg == 0 .and. (sd == 2 .or. p%side(2)%itb > 0)) then
            call set_error(err, "deck '"//deck%path//"', group &contact (contact "// &
              itoa(k)//"): body '"//trim(bodies(ib)%name)//"' has no surface polyline")
            return
          end if
        end do
        p%both_ways = p%side(2)%itb > 0
        ! a threshold at or above the master's interior plateau detects nothing: the bar
        ! would pass through the target silently (bench/sweeps.py, eps_cr = 1e-4)
        if (.not. (p%side(2)%threshold < p%side(2)%plateau)) then
          call set_error(err, "deck '"//deck%path//"', group &contact (contact "//itoa(k)// &
            "), variable "//trim(merge('eps_rel', 'eps_cr ', cs%eps_rel > 0.0_wp))// &
            ": the threshold "//rtoa(p%side(2)%threshold)//" is not below the interior "// &
            "plateau of det(M) of '"//trim(bodies(cs%imaster)%name)//"', "// &
            rtoa(p%side(2)%plateau)//", so no penetration could be detected; give a "// &
            "threshold well below the plateau (paper: eps_cr = 5e-10)")
          return
        end if
        p%edge = 0
        if (cs%edge_point(1) > -huge(1.0_wp)) then
          best = huge(1.0_wp)
          do j = 1, bodies(cs%islave)%np
            if (norm2(bodies(cs%islave)%x(:, j) - cs%edge_point(1:2)) < best) then
              best = norm2(bodies(cs%islave)%x(:, j) - cs%edge_point(1:2))
              p%edge = j
            end if
          end do
        end if
      end associate
    end do
  end subroutine contact_pairs_init

  subroutine side_init(s, b, ib, tbs, axisym, eps_cr, eps_rel, err)
    type(side_t), intent(out) :: s
    type(body_t), intent(in) :: b
    integer, intent(in) :: ib
    type(tl_body_t), intent(in) :: tbs(:)
    logical, intent(in) :: axisym
    real(wp), intent(in) :: eps_cr, eps_rel
    type(error_t), allocatable, intent(inout) :: err
    integer :: j
    s%ibody = ib
    s%np = b%np
    s%itb = 0
    do j = 1, size(tbs)
      if (tbs(j)%ibody == ib) s%itb = j
    end do
    call body_cloud(b, s%cloud, err)
    if (allocated(err)) return
    s%plateau = body_plateau(b, s%cloud)
    s%threshold = detection_threshold(eps_cr, eps_rel, s%plateau)
    s%surface_det = surface_det_median(b, s%cloud)
    call surface_build(s%surface, b%x, b%loop_ptr, b%loop_idx, b%loop_closed, axisym, &
      1.0e-9_wp*minval(b%spacing(1:2)), err)
    if (allocated(err)) return
    s%lo = minval(b%x, dim=2) - s%cloud%rmax(1:2)
    s%hi = maxval(b%x, dim=2) + s%cloud%rmax(1:2)
    allocate(s%x_old(2, b%np), s%x_pred(2, b%np), s%fphys(2, b%np), s%active(b%np), &
      s%seg(b%np), s%xi(b%np), s%mass(b%np))
    s%x_old = b%x
    s%x_pred = b%x
    s%rho = b%rho
    s%mass = 0.0_wp
    if (s%itb > 0) s%mass = tbs(s%itb)%t%mass
  end subroutine side_init

  !> Median det(M) of a body at its own boundary particles (off the symmetry axis): about
  !! what a particle touching the surface sees; a threshold above it misses shallow
  !! penetrations.
  function surface_det_median(b, c) result(dmed)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    real(wp) :: dmed
    real(wp), allocatable :: dets(:)
    integer :: i, n
    allocate(dets(count(b%boundary)))
    n = 0
    do i = 1, b%np
      if (.not. b%boundary(i)) cycle
      n = n + 1
      dets(n) = cloud_det(c, b%x(:, i))
    end do
    dmed = 0.0_wp
    if (n == 0) return
    call sort_in_place(dets(1:n))
    dmed = dets((n + 1)/2)
  end function surface_det_median

  pure subroutine sort_in_place(a)
    real(wp), intent(inout) :: a(:)
    integer :: i, j
    real(wp) :: v
    do i = 2, size(a)
      v = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= v) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = v
    end do
  end subroutine sort_in_place

  !> Contact corrections of pair p for the step dt: the coefficients d (predicted by eq. 64
  !! from d_old) and a_n of the deformable bodies in tbs are corrected in place; their
  !! redistributed contact forces are added to tb%fcon (N).
  subroutine contact_correct(p, tbs, dt, err)
    type(contact_pair_t), intent(inout) :: p
    type(tl_body_t), intent(inout) :: tbs(:)
    real(wp), intent(in) :: dt
    type(error_t), allocatable, intent(inout) :: err
    integer :: sd
    p%step = contact_stats_t()
    ! the slave's det(M) and surface are needed only when both bodies deform
    do sd = 1, 2
      call side_positions(p%side(sd), tbs, sd == 2 .or. p%both_ways, err)
      if (allocated(err)) return
    end do
    call contact_pass(p, p%side(1), p%side(2), tbs, dt, .true., err)
    if (allocated(err)) return
    if (p%both_ways) then
      ! eq. (28), second condition: the master's particles against the slave
      do sd = 1, 2
        call side_positions(p%side(sd), tbs, .true., err)
        if (allocated(err)) return
      end do
      call contact_pass(p, p%side(2), p%side(1), tbs, dt, .false., err)
    end if
  end subroutine contact_correct

  !> Old and predicted physical positions of a side; a deformable side is re-binned and its
  !! surface moved to the prediction.
  subroutine side_positions(s, tbs, move, err)
    type(side_t), intent(inout) :: s
    type(tl_body_t), intent(in) :: tbs(:)
    logical, intent(in) :: move      !< the side acts as a master: move its cloud and surface
    type(error_t), allocatable, intent(inout) :: err
    if (s%itb == 0) return
    associate (tb => tbs(s%itb))
      call physical_positions(tb%t, tb%x0, tb%d_old, s%x_old)
      call physical_positions(tb%t, tb%x0, tb%d, s%x_pred)
    end associate
    if (.not. move) return
    call cloud_move(s%cloud, s%x_pred, err)
    if (allocated(err)) return
    call surface_update(s%surface, s%x_pred, err)
    s%lo = minval(s%x_pred, dim=2) - s%cloud%rmax(1:2)
    s%hi = maxval(s%x_pred, dim=2) + s%cloud%rmax(1:2)
  end subroutine side_positions

  !> One detection-and-force pass of side a's particles against side b (det(M_b), b's
  !! surface). count_stats: this pass feeds the step's statistics and counters.
  subroutine contact_pass(p, a, b, tbs, dt, count_stats, err)
    type(contact_pair_t), intent(inout) :: p
    type(side_t), intent(inout) :: a, b
    type(tl_body_t), intent(inout) :: tbs(:)
    real(wp), intent(in) :: dt
    logical, intent(in) :: count_stats
    type(error_t), allocatable, intent(inout) :: err
    integer :: j, jseg, i0, i1
    integer(i64) :: neval, ndet, ncon
    real(wp) :: det, g, nrm(2), tng(2), slip, fj(2), pen, rad, fnsum, xi, invmb, meff
    real(wp) :: dxb(2)
    logical :: found, stick
    neval = 0
    ndet = 0
    ncon = 0
    pen = 0.0_wp
    rad = 0.0_wp
    fnsum = 0.0_wp
    !$omp parallel do default(none) shared(a, b, dt, p) &
    !$omp private(det, found, g, nrm, tng, slip, fj, stick, jseg, xi, i0, i1, invmb, meff, dxb) &
    !$omp reduction(+: neval, ndet, ncon, fnsum) reduction(max: pen, rad) schedule(static)
    do j = 1, a%np
      a%active(j) = .false.
      a%fphys(:, j) = 0.0_wp
      if (any(a%x_pred(:, j) < b%lo) .or. any(a%x_pred(:, j) > b%hi)) cycle
      neval = neval + 1
      det = cloud_det(b%cloud, a%x_pred(:, j))
      if (.not. (det > b%threshold)) cycle
      ndet = ndet + 1
      call surface_gap(b%surface, a%x_pred(:, j), a%rho(:, j), found, g, nrm, tng, jseg, xi)
      if (.not. found .or. .not. (g < 0.0_wp)) cycle
      ! the master point's motion over the step and its inverse mass (0 when rigid)
      i0 = b%surface%i0(jseg)
      i1 = b%surface%i1(jseg)
      dxb = (1.0_wp - xi)*(b%x_pred(:, i0) - b%x_old(:, i0)) + xi*(b%x_pred(:, i1) - &
        b%x_old(:, i1))
      invmb = 0.0_wp
      if (b%itb > 0) invmb = (1.0_wp - xi)**2/b%mass(i0) + xi**2/b%mass(i1)
      meff = 1.0_wp/(1.0_wp/a%mass(j) + invmb)
      slip = dot_product(a%x_pred(:, j) - a%x_old(:, j) - dxb, tng)
      call contact_point_force(g, nrm, tng, slip, meff, dt, p%mu, fj, stick)
      a%active(j) = .true.
      a%fphys(:, j) = fj
      a%seg(j) = jseg
      a%xi(j) = xi
      ncon = ncon + 1
      fnsum = fnsum + dot_product(fj, nrm)
      pen = max(pen, -g)
      rad = max(rad, a%x_pred(1, j))
    end do
    !$omp end parallel do
    p%count%screened = p%count%screened + a%np
    p%count%evaluated = p%count%evaluated + neval
    p%count%detected = p%count%detected + ndet
    p%count%contacts = p%count%contacts + ncon
    if (count_stats) then
      p%step%n_contact = int(ncon)
      p%step%force_normal = 0.5_wp*fnsum
      p%step%radius = rad
      p%step%pen_before = pen
      if (p%edge > 0) p%step%edge_in_contact = a%active(p%edge)
    else
      p%step%n_contact = p%step%n_contact + int(ncon)
      p%step%force_normal = p%step%force_normal + 0.5_wp*fnsum
      p%step%radius = max(p%step%radius, rad)
      p%step%pen_before = max(p%step%pen_before, pen)
    end if
    if (ncon == 0) return
    ! reactions on b at the ends of the segments hit (serial: few particles)
    if (b%itb > 0) then
      b%fphys = 0.0_wp
      do j = 1, a%np
        if (.not. a%active(j)) cycle
        i0 = b%surface%i0(a%seg(j))
        i1 = b%surface%i1(a%seg(j))
        b%fphys(:, i0) = b%fphys(:, i0) - (1.0_wp - a%xi(j))*a%fphys(:, j)
        b%fphys(:, i1) = b%fphys(:, i1) - a%xi(j)*a%fphys(:, j)
      end do
      call redistribute_and_correct(tbs(b%itb), b%fphys, dt)
    end if
    call redistribute_and_correct(tbs(a%itb), a%fphys, dt)
    ! penetration left after the correction (redistribution spreads the forces): the
    ! corrected positions of the particles that had a force (and of b when it moves)
    if (b%itb > 0) call side_positions(b, tbs, .true., err)
    if (allocated(err)) return
    associate (ta => tbs(a%itb))
      do j = 1, a%np
        if (.not. a%active(j)) cycle
        a%x_pred(:, j) = position_of(ta, j)
        call surface_gap(b%surface, a%x_pred(:, j), a%rho(:, j), found, g, nrm, tng)
        if (found) p%step%pen_after = max(p%step%pen_after, -g)
      end do
    end associate
  end subroutine contact_pass

  !> Physical position of particle j of a body from its current coefficients.
  pure function position_of(tb, j) result(x)
    type(tl_body_t), intent(in) :: tb
    integer, intent(in) :: j
    real(wp) :: x(2)
    integer :: e
    x = tb%x0(:, j)
    do e = tb%t%pptr(j), tb%t%pptr(j + 1) - 1
      x = x + tb%t%pn(:, e)*tb%d(:, tb%t%pnbr(e))
    end do
  end function position_of

  !> eq. (98): f_I = sum_J N_I(X_J) f_J component by component, added to tb%fcon; then the
  !! corrected a_n and prediction of eq. (64).
  subroutine redistribute_and_correct(tb, fphys, dt)
    type(tl_body_t), intent(inout) :: tb
    real(wp), intent(in) :: fphys(:, :), dt
    integer :: j, e, i
    do j = 1, tb%np
      if (all(fphys(:, j) == 0.0_wp)) cycle
      do e = tb%t%pptr(j), tb%t%pptr(j + 1) - 1
        i = tb%t%pnbr(e)
        tb%fcon(:, i) = tb%fcon(:, i) + tb%t%pn(:, e)*fphys(:, j)
      end do
    end do
    tb%a(1, :) = tb%a_old(1, :) + tb%fcon(1, :)/tb%t%mass
    tb%a(2, :) = tb%a_old(2, :) + tb%fcon(2, :)/tb%t%mass
    where (tb%pres) tb%a = 0.0_wp
    tb%d = tb%d_old + dt*tb%v + 0.5_wp*dt*dt*tb%a
  end subroutine redistribute_and_correct

  !> det(M) of the master and of the slave (built from the slave's current physical
  !! positions with its reference volumes and supports: the Lagrangian body) on the grid
  !! lo..hi with n points (x fastest), and det(M_master) at the slave particles
  !! (Figs. 9-10). Work for output only, done at snapshots when the deck asks.
  subroutine contact_det_fields(p, tbs, bodies, lo, hi, n, det_m, det_s, det_m_at_slave, err)
    type(contact_pair_t), intent(in) :: p
    type(tl_body_t), intent(inout) :: tbs(:)
    type(body_t), intent(in) :: bodies(:)
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: n(2)
    real(wp), intent(out) :: det_m(:), det_s(:), det_m_at_slave(:)
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: cs, cm
    integer :: i, j, q
    real(wp) :: x(2)
    call current_cloud(p%side(1), cs)
    if (allocated(err)) return
    call current_cloud(p%side(2), cm)
    if (allocated(err)) return
    !$omp parallel do default(none) shared(cm, cs, lo, hi, n, det_m, det_s) private(i, q, x)
    do j = 1, n(2)
      do i = 1, n(1)
        q = i + (j - 1)*n(1)
        x = lo + (hi - lo)*[real(i - 1, wp)/real(n(1) - 1, wp), real(j - 1, wp)/real(n(2) - 1, wp)]
        det_m(q) = cloud_det(cm, x)
        det_s(q) = cloud_det(cs, x)
      end do
    end do
    !$omp end parallel do
    associate (tb => tbs(p%side(1)%itb))
      call physical_positions(tb%t, tb%x0, tb%d, tb%x)
      do j = 1, tb%np
        det_m_at_slave(j) = cloud_det(cm, tb%x(:, j))
      end do
    end associate
  contains
    subroutine current_cloud(s, c)
      type(side_t), intent(in) :: s
      type(rk_cloud_t), intent(out) :: c
      associate (b => bodies(s%ibody))
        if (s%itb == 0) then
          call cloud_init(c, b%x, b%rho, b%vol, b%kid, b%wshape, b%bid, b%h(1:2), err)
        else
          call physical_positions(tbs(s%itb)%t, tbs(s%itb)%x0, tbs(s%itb)%d, tbs(s%itb)%x)
          call cloud_init(c, tbs(s%itb)%x, b%rho, b%vol, b%kid, b%wshape, b%bid, b%h(1:2), err)
        end if
      end associate
    end subroutine current_cloud
  end subroutine contact_det_fields
end module contact_pair_m
