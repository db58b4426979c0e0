!> Contact pairs of a dynamic run (deck group &contact): a rigid master body, whose
!! det(M) cloud, bins and surface are built once (it does not move), and a deformable
!! slave body. Each step, between the prediction (64) and the force evaluation (62):
!! screen the slave particles by the master's grown bounding box, evaluate det(M_master)
!! at the predicted physical positions of the survivors, measure the gap of the detected
!! ones, compute eq. (93)-(96) forces at the particles, redistribute them to the RK
!! coefficients by eq. (98), correct a_n and the prediction (Section 5).
module contact_pair_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use deck_m, only: deck_t
  use body_m, only: body_t
  use rk_cloud_m, only: rk_cloud_t, cloud_det, cloud_init
  use bodies_m, only: body_cloud
  use detection_m, only: body_plateau, detection_threshold
  use contact_m, only: master_surface_t, surface_build, surface_gap, contact_point_force, &
    contact_counters_t
  use tl_body_m, only: tl_body_t
  use tl_kinematics_m, only: physical_positions
  implicit none
  private
  public :: contact_pair_t, contact_pairs_init, contact_correct, contact_stats_t
  public :: contact_det_fields

  !> What one step's contact did (for the log, history and summary).
  type :: contact_stats_t
    integer :: n_contact = 0            !< slave particles with a force this step
    !> Mean normal contact force over the step (N, N/m in plane strain): half the sum of the
    !! eq. (93) forces, since a force added to a_n gives the velocity the impulse dt/2 f
    !! (eq. 63) and is absent at n+1.
    real(wp) :: force_normal = 0.0_wp
    real(wp) :: radius = 0.0_wp         !< largest x1 of a contacting particle (m)
    real(wp) :: pen_before = 0.0_wp     !< deepest predicted penetration (m, >= 0)
    real(wp) :: pen_after = 0.0_wp      !< deepest penetration left after the correction (m)
    logical :: edge_in_contact = .false.
  end type contact_stats_t

  type :: contact_pair_t
    integer :: master = 0                !< deck body index of the (rigid) master
    integer :: slave = 0                 !< index of the slave among the deformable bodies
    real(wp) :: eps_cr = 0.0_wp, eps_rel = 0.0_wp, mu = 0.0_wp
    real(wp) :: plateau = 0.0_wp, threshold = 0.0_wp
    type(rk_cloud_t) :: cloud            !< master particles for det(M)
    type(master_surface_t) :: surface
    real(wp) :: lo(2) = 0.0_wp, hi(2) = 0.0_wp   !< master box grown by its largest support
    integer :: edge = 0                  !< slave particle tracked for separation (0: none)
    type(contact_counters_t) :: count
    type(contact_stats_t) :: step
    ! work arrays, allocated once
    real(wp), allocatable :: x_old(:, :), x_pred(:, :), fc(:, :)
    logical, allocatable :: active(:)
    real(wp), allocatable :: gap(:), rho_s(:, :)
  end type contact_pair_t

contains

  !> Build the pairs of the deck: master clouds, surfaces, thresholds and work arrays.
  subroutine contact_pairs_init(deck, bodies, tbs, axisym, pairs, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(tl_body_t), intent(in) :: tbs(:)
    logical, intent(in) :: axisym
    type(contact_pair_t), allocatable, intent(out) :: pairs(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, m, s, j, np
    real(wp) :: best
    allocate(pairs(deck%ncontacts))
    do k = 1, deck%ncontacts
      associate (p => pairs(k), cs => deck%contacts(k))
        m = cs%imaster
        p%master = m
        p%slave = 0
        do j = 1, size(tbs)
          if (tbs(j)%ibody == cs%islave) p%slave = j
        end do
        s = p%slave
        p%eps_cr = cs%eps_cr
        p%eps_rel = cs%eps_rel
        p%mu = cs%mu
        call body_cloud(bodies(m), p%cloud, err)
        if (allocated(err)) return
        p%plateau = body_plateau(bodies(m), p%cloud)
        p%threshold = detection_threshold(p%eps_cr, p%eps_rel, p%plateau)
        call surface_build(p%surface, bodies(m)%x, bodies(m)%loop_ptr, bodies(m)%loop_idx, &
          bodies(m)%loop_closed, axisym, 1.0e-9_wp*minval(bodies(m)%spacing(1:2)), err)
        if (allocated(err)) return
        if (p%surface%nseg == 0) then
          call set_error(err, "deck '"//deck%path//"', group &contact (contact "//itoa(k)// &
            "): master body '"//trim(bodies(m)%name)//"' has no surface polyline")
          return
        end if
        p%lo = minval(bodies(m)%x, dim=2) - p%cloud%rmax(1:2)
        p%hi = maxval(bodies(m)%x, dim=2) + p%cloud%rmax(1:2)
        np = tbs(s)%np
        allocate(p%x_old(2, np), p%x_pred(2, np), p%fc(2, np), p%active(np), p%gap(np))
        p%rho_s = bodies(cs%islave)%rho
        p%edge = 0
        if (cs%edge_point(1) > -huge(1.0_wp)) then
          best = huge(1.0_wp)
          do j = 1, np
            if (norm2(tbs(s)%x0(:, j) - cs%edge_point(1:2)) < best) then
              best = norm2(tbs(s)%x0(:, j) - cs%edge_point(1:2))
              p%edge = j
            end if
          end do
        end if
      end associate
    end do
  end subroutine contact_pairs_init

  !> Contact correction of one pair for the step dt: the slave's coefficients d (already
  !! predicted by eq. 64 from d_old) and accelerations a_n are corrected in place; the
  !! redistributed contact forces are added to tb%fcon (N).
  subroutine contact_correct(p, tb, dt)
    type(contact_pair_t), intent(inout) :: p
    type(tl_body_t), intent(inout) :: tb
    real(wp), intent(in) :: dt
    integer :: j, e, i, c
    integer(i64) :: nscreen, neval, ndet, ncon
    real(wp) :: det, g, nrm(2), tng(2), slip, fj(2), pen, rad, fnsum
    logical :: found, stick
    call physical_positions(tb%t, tb%x0, tb%d_old, p%x_old)
    call physical_positions(tb%t, tb%x0, tb%d, p%x_pred)
    nscreen = tb%np
    neval = 0
    ndet = 0
    ncon = 0
    pen = 0.0_wp
    rad = 0.0_wp
    fnsum = 0.0_wp
    !$omp parallel do default(none) shared(p, tb, dt) &
    !$omp private(det, found, g, nrm, tng, slip, fj, stick) &
    !$omp reduction(+: neval, ndet, ncon, fnsum) reduction(max: pen, rad) schedule(static)
    do j = 1, tb%np
      p%active(j) = .false.
      p%fc(:, j) = 0.0_wp
      p%gap(j) = 0.0_wp
      if (any(p%x_pred(:, j) < p%lo) .or. any(p%x_pred(:, j) > p%hi)) cycle
      neval = neval + 1
      det = cloud_det(p%cloud, p%x_pred(:, j))
      if (.not. (det > p%threshold)) cycle
      ndet = ndet + 1
      call surface_gap(p%surface, p%x_pred(:, j), p%rho_s(:, j), found, g, nrm, tng)
      if (.not. found .or. .not. (g < 0.0_wp)) cycle
      slip = dot_product(p%x_pred(:, j) - p%x_old(:, j), tng)
      call contact_point_force(g, nrm, tng, slip, tb%t%mass(j), dt, p%mu, fj, stick)
      p%active(j) = .true.
      p%fc(:, j) = fj
      p%gap(j) = g
      ncon = ncon + 1
      fnsum = fnsum + dot_product(fj, nrm)
      pen = max(pen, -g)
      rad = max(rad, p%x_pred(1, j))
    end do
    !$omp end parallel do
    p%count%screened = p%count%screened + nscreen
    p%count%evaluated = p%count%evaluated + neval
    p%count%detected = p%count%detected + ndet
    p%count%contacts = p%count%contacts + ncon
    p%step%n_contact = int(ncon)
    p%step%force_normal = 0.5_wp*fnsum
    p%step%radius = rad
    p%step%pen_before = pen
    p%step%pen_after = 0.0_wp
    p%step%edge_in_contact = .false.
    if (p%edge > 0) p%step%edge_in_contact = p%active(p%edge)
    if (ncon == 0) return
    ! eq. (98): f_I = sum_J N_I(X_J) f_J, component by component (few particles: serial)
    do j = 1, tb%np
      if (.not. p%active(j)) cycle
      do e = tb%t%pptr(j), tb%t%pptr(j + 1) - 1
        i = tb%t%pnbr(e)
        do c = 1, 2
          tb%fcon(c, i) = tb%fcon(c, i) + tb%t%pn(c, e)*p%fc(c, j)
        end do
      end do
    end do
    ! corrected a_n and prediction (eq. 64 again)
    tb%a(1, :) = tb%a_old(1, :) + tb%fcon(1, :)/tb%t%mass
    tb%a(2, :) = tb%a_old(2, :) + tb%fcon(2, :)/tb%t%mass
    where (tb%pres) tb%a = 0.0_wp
    tb%d = tb%d_old + dt*tb%v + 0.5_wp*dt*dt*tb%a
    ! penetration left after the correction (redistribution spreads the forces)
    call physical_positions(tb%t, tb%x0, tb%d, p%x_pred)
    do j = 1, tb%np
      if (.not. p%active(j)) cycle
      call surface_gap(p%surface, p%x_pred(:, j), p%rho_s(:, j), found, g, nrm, tng)
      if (found) p%step%pen_after = max(p%step%pen_after, -g)
    end do
  end subroutine contact_correct

  !> det(M) of the master and of the slave (built from the slave's current physical
  !! positions with its reference volumes and supports: the Lagrangian body) on the grid
  !! lo..hi with n points (x fastest), and det(M_master) at the slave particles
  !! (Figs. 9-10). Work for output only, done at snapshots when the deck asks.
  subroutine contact_det_fields(p, tb, slave, lo, hi, n, det_m, det_s, det_m_at_slave, err)
    type(contact_pair_t), intent(in) :: p
    type(tl_body_t), intent(inout) :: tb
    type(body_t), intent(in) :: slave
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: n(2)
    real(wp), intent(out) :: det_m(:), det_s(:), det_m_at_slave(:)
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: cs
    integer :: i, j, q
    real(wp) :: x(2)
    call physical_positions(tb%t, tb%x0, tb%d, tb%x)
    call cloud_init(cs, tb%x, slave%rho, slave%vol, slave%kid, slave%wshape, slave%bid, &
      slave%h(1:2), err)
    if (allocated(err)) return
    !$omp parallel do default(none) shared(p, cs, lo, hi, n, det_m, det_s) private(i, q, x)
    do j = 1, n(2)
      do i = 1, n(1)
        q = i + (j - 1)*n(1)
        x = lo + (hi - lo)*[real(i - 1, wp)/real(n(1) - 1, wp), real(j - 1, wp)/real(n(2) - 1, wp)]
        det_m(q) = cloud_det(p%cloud, x)
        det_s(q) = cloud_det(cs, x)
      end do
    end do
    !$omp end parallel do
    do j = 1, tb%np
      det_m_at_slave(j) = 0.0_wp
      if (all(tb%x(:, j) >= p%lo) .and. all(tb%x(:, j) <= p%hi)) &
        det_m_at_slave(j) = cloud_det(p%cloud, tb%x(:, j))
    end do
  end subroutine contact_det_fields
end module contact_pair_m
