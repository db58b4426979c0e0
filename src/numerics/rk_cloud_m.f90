!> A particle cloud ready for moment-matrix work: particles packed in bin order with their
!! supports and volumes, the window and basis choices, and the bins. It evaluates det(M)
!! (contact detection, Section 2) and the RKPM shape functions and gradients (eq. 60) from
!! the same factorization, so detection and interpolation share one code path.
module rk_cloud_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use kernels_m, only: window_eval, window_1d, window_tensor, radial_norm, kernel_cubic
  use basis_m, only: mmax, basis_size, basis_eval, basis_eval_grad, basis_bilinear, &
    basis_linear_3d
  use moment_matrix_m, only: moment_add, chol_small, chol_det, chol_solve, moment_symmetrize, &
    singular_pivot
  use neighbour_bins_m, only: bins_t, bins_build, bins_cell_block, bins_candidates, &
    bins_block_runs, bins_block_run
  implicit none
  private
  public :: rk_cloud_t, cloud_init, cloud_det, cloud_moment, cloud_shape, cloud_count_cover, &
    cloud_shape_values
  public :: cloud_move, cloud_set_reference, cloud_det_excluding, cloud_clearance, &
    cloud_candidates

  !> The most particles covering one point that the shape routines take (cloud_shape,
  !! cloud_shape_values: the callers' ids hold at most this many, 2D's 512
  !! and 3D's 1024): their slot lists are fixed arrays of this size, not automatic arrays
  !! allocated on the heap at every point
  integer, parameter :: max_cover = 1024

  type :: rk_cloud_t
    integer :: ndim = 0, np = 0
    integer :: kid = kernel_cubic, wshape = window_tensor, bid = 0, m = 0
    real(wp) :: hinv(3) = 1.0_wp      !< 1/h: scaling of the basis argument z = (x_l - x)/h
    real(wp) :: cn = 1.0_wp           !< radial window normalisation
    real(wp) :: rmax(3) = 0.0_wp      !< largest support radius per direction (m)
    real(wp), allocatable :: x(:, :)     !< particle positions in bin order (ndim, np)
    real(wp), allocatable :: rho(:, :)   !< support radius per direction (ndim, np)
    real(wp), allocatable :: rinv(:, :)  !< 1/rho
    real(wp), allocatable :: vol(:)      !< particle volume (weight Delta V)
    integer, allocatable :: perm(:)      !< bin-order slot -> caller's particle index
    !> reference positions in bin order (ndim, np), when set (cloud_set_reference): which
    !! particles are neighbours of a point in the reference configuration (self-contact)
    real(wp), allocatable :: xr(:, :)
    !> with xr: particle I's own neighbour radius, squared, in bin order (np): self_radius
    !! times its largest support (cloud_set_reference); I is a neighbour of a point of
    !! radius rex when its reference distance is below the larger of the two (0: rex alone)
    real(wp), allocatable :: rn2(:)
    type(bins_t) :: bins
    ! work space of cloud_move, allocated at the first move and reused
    integer, allocatable :: wslot(:)
    real(wp), allocatable :: wrho(:, :), wvol(:), wxr(:, :), wrn2(:)
  end type rk_cloud_t

contains

  !> Pack a cloud. x(ndim,np) positions, rho(ndim,np) support radii, vol(np) weights,
  !! h(ndim) basis scale (normally the nominal support radius). Particles keep their own
  !! index through perm so callers never see the bin order. With grid_lo, grid_hi and
  !! rmax: the particles are part of a larger cloud whose extremes and largest supports
  !! these are (a rank's region of a body, rkpm_tl3d_m): the bins are that cloud's cells
  !! (bins_build's block), so a point whose covering particles are all here gets the
  !! larger cloud's sums in the same order, to the bit (as cloud_move's grid).
  subroutine cloud_init(c, x, rho, vol, kid, wshape, bid, h, err, grid_lo, grid_hi, rmax)
    type(rk_cloud_t), intent(out) :: c
    real(wp), intent(in) :: x(:, :), rho(:, :), vol(:), h(:)
    integer, intent(in) :: kid, wshape, bid
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: grid_lo(:), grid_hi(:), rmax(:)
    type(bins_t) :: b0
    integer :: i, q, ndim
    ndim = size(x, 1)
    c%ndim = ndim
    c%np = size(x, 2)
    c%kid = kid
    c%wshape = wshape
    c%bid = bid
    c%m = basis_size(bid)
    c%cn = radial_norm(kid, ndim)
    c%hinv = 1.0_wp
    c%hinv(1:ndim) = 1.0_wp/h(1:ndim)
    c%rmax = 0.0_wp
    if (c%np > 0) c%rmax(1:ndim) = maxval(rho, dim=2)
    if (present(rmax)) c%rmax(1:ndim) = rmax(1:ndim)
    ! 2D cells a third of the largest support: a query then scans 7 x 7 small cells instead
    ! of 3 x 3 large ones, about 27 candidates instead of 43 per hit set of 20 (bench/:
    ! 25% more det(M) queries per second); 1D and 3D keep cells of one support
    call bins_build(b0, x, max(c%rmax(1:ndim), tiny(1.0_wp))/merge(3.0_wp, 1.0_wp, ndim == 2), &
      err, grid_lo, grid_hi)
    if (allocated(err)) return
    allocate(c%x(ndim, c%np), c%rho(ndim, c%np), c%rinv(ndim, c%np), c%vol(c%np))
    allocate(c%perm(c%np))
    ! Repack in cell order so the bins index the packed arrays directly.
    do q = 1, c%np
      i = b0%idx(q)
      c%perm(q) = i
      c%x(:, q) = x(:, i)
      c%rho(:, q) = rho(:, i)
      c%rinv(:, q) = 1.0_wp/rho(:, i)
      c%vol(q) = vol(i)
    end do
    c%bins = b0
    do q = 1, c%np
      c%bins%idx(q) = q
    end do
    if (any(c%rho <= 0.0_wp)) call set_error(err, 'rk cloud: support radius must be positive')
  end subroutine cloud_init

  !> The same particles at new positions x (caller order): re-binned and re-packed in place,
  !! in the order cloud_init would give them (a deformable contact master moves every step;
  !! a rigid one is never moved). Allocates only at the first move, or when the grid grows
  !! beyond every earlier one. With grid_lo, grid_hi: the particles are part of a larger
  !! cloud whose extremes these are (and whose rmax c has): the bins are that cloud's cells
  !! (bins_build), so det(M) sums the same terms in the same order (distributed memory).
  subroutine cloud_move(c, x, err, grid_lo, grid_hi)
    type(rk_cloud_t), intent(inout) :: c
    real(wp), intent(in) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: grid_lo(:), grid_hi(:)
    integer :: q, i, o, nd
    nd = c%ndim
    if (.not. allocated(c%wslot)) allocate(c%wslot(c%np), c%wrho(nd, c%np), c%wvol(c%np))
    if (allocated(c%xr) .and. .not. allocated(c%wxr)) allocate(c%wxr(nd, c%np), c%wrn2(c%np))
    ! the old slot of each particle, before the new bins overwrite the order
    do q = 1, c%np
      c%wslot(c%perm(q)) = q
    end do
    call bins_build(c%bins, x, max(c%rmax(1:nd), tiny(1.0_wp))/merge(3.0_wp, 1.0_wp, &
      nd == 2), err, grid_lo, grid_hi)
    if (allocated(err)) return
    do q = 1, c%np
      i = c%bins%idx(q)
      o = c%wslot(i)
      c%wrho(:, q) = c%rho(:, o)
      c%wvol(q) = c%vol(o)
      if (allocated(c%xr)) then
        c%wxr(:, q) = c%xr(:, o)
        c%wrn2(q) = c%rn2(o)
      end if
    end do
    do q = 1, c%np
      i = c%bins%idx(q)
      c%x(:, q) = x(:, i)
      c%perm(q) = i
      c%rho(:, q) = c%wrho(:, q)
      c%rinv(:, q) = 1.0_wp/c%wrho(:, q)
      c%vol(q) = c%wvol(q)
      if (allocated(c%xr)) then
        c%xr(:, q) = c%wxr(:, q)
        c%rn2(q) = c%wrn2(q)
      end if
      c%bins%idx(q) = q
    end do
  end subroutine cloud_move

  !> Record the particles' reference positions xr (ndim, np; caller order), kept through
  !! cloud_move, for cloud_det_excluding. self_radius (default 0): particle I's neighbour
  !! radius is self_radius x its largest support, and I counts as a neighbour of a point
  !! of radius rex when its reference distance is below max(rex, I's radius): the relation
  !! is then symmetric, and a non-neighbour's own support never reaches the point in the
  !! reference configuration, whatever the supports' grading.
  subroutine cloud_set_reference(c, xr, self_radius)
    type(rk_cloud_t), intent(inout) :: c
    real(wp), intent(in) :: xr(:, :)
    real(wp), intent(in), optional :: self_radius
    integer :: q
    real(wp) :: sr
    if (allocated(c%xr)) deallocate(c%xr)
    if (allocated(c%rn2)) deallocate(c%rn2)
    allocate(c%xr(c%ndim, c%np), c%rn2(c%np))
    sr = 0.0_wp
    if (present(self_radius)) sr = self_radius
    do q = 1, c%np
      c%xr(:, q) = xr(:, c%perm(q))
      c%rn2(q) = (sr*maxval(c%rho(:, q)))**2
    end do
  end subroutine cloud_set_reference

  !> Moment matrix M(p) (full, symmetric) and the number of particles covering p. With xc
  !! and rex (the cloud's reference positions set), the particles whose reference position
  !! lies within rex (or their own radius, cloud_set_reference, the larger) of xc are left
  !! out.
  pure subroutine cloud_moment(c, p, mm, ncover, xc, rex)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    real(wp), intent(out) :: mm(:, :)
    integer, intent(out) :: ncover
    real(wp), intent(in), optional :: xc(:), rex
    integer :: clo(3), chi(3), i, j, k, cc, q, nd
    logical :: empty, excl
    real(wp) :: d(3), z(3), pv(mmax), phi, rex2
    nd = c%ndim
    excl = present(xc) .and. present(rex)
    rex2 = 0.0_wp
    if (excl) rex2 = rex*rex
    mm(1:c%m, 1:c%m) = 0.0_wp
    ncover = 0
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        cc = 1 + c%bins%nc(1)*(j + c%bins%nc(2)*k)
        do i = clo(1), chi(1)
          do q = c%bins%start(cc + i), c%bins%start(cc + i + 1) - 1
            d(1:nd) = c%x(:, q) - p(1:nd)
            if (any(abs(d(1:nd)) >= c%rho(:, q))) cycle
            if (excl) then
              if (sum((c%xr(:, q) - xc(1:nd))**2) < max(rex2, c%rn2(q))) cycle
            end if
            call window_eval(c%kid, c%wshape, nd, d(1:nd), c%rinv(:, q), c%cn, phi)
            if (phi <= 0.0_wp) cycle
            ncover = ncover + 1
            ! (the basis argument in a fixed array: an expression would be a temporary
            ! of unknown size, allocated on the heap at every particle)
            z(1:nd) = d(1:nd)*c%hinv(1:nd)
            call basis_eval(c%bid, z(1:nd), pv)
            call moment_add(c%m, pv, phi*c%vol(q), mm)
          end do
        end do
      end do
    end do
    call moment_symmetrize(c%m, mm)
  end subroutine cloud_moment

  !> Number of particles whose support covers p (Theorem 3.1's k).
  pure integer function cloud_count_cover(c, p) result(ncover)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    real(wp) :: mm(mmax, mmax)
    call cloud_moment(c, p, mm, ncover)
  end function cloud_count_cover

  !> det(M(p)); 0 when no particle covers p or the Cholesky factorization fails.
  pure real(wp) function cloud_det(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    real(wp) :: mm(mmax, mmax)
    integer :: ncover
    logical :: ok
    if (c%ndim == 2 .and. c%bid == basis_bilinear .and. c%wshape == window_tensor) then
      det = det_2d_bilinear_tensor(c, p)
      return
    end if
    if (c%ndim == 3 .and. c%bid == basis_linear_3d .and. c%wshape == window_tensor) then
      det = det_3d_linear_tensor(c, p)
      return
    end if
    call cloud_moment(c, p, mm, ncover)
    det = 0.0_wp
    if (ncover == 0) return
    call chol_small(c%m, mm, ok, singular_pivot)
    if (ok) det = chol_det(c%m, mm)
  end function cloud_det

  !> det(M(p)) assembled only from the particles that are not neighbours, in the reference
  !! configuration, of the material point at reference position xc: those whose reference
  !! position lies at rex, and at the particle's own radius (cloud_set_reference's
  !! self_radius), or more from xc (self-contact, Sections 1 and 7). 0 when fewer
  !! particles than basis functions remain or the Cholesky factorization fails. Needs the
  !! reference positions (cloud_set_reference).
  pure real(wp) function cloud_det_excluding(c, p, xc, rex) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:), xc(:), rex
    real(wp) :: mm(mmax, mmax)
    integer :: ncover
    logical :: ok
    if (c%ndim == 3 .and. c%bid == basis_linear_3d .and. c%wshape == window_tensor) then
      ! (3D self-contact's screen: the hot path with the exclusion, fewer than 4 left is 0)
      call det_3d_linear(c, p, det, ncover, xc, rex)
      if (ncover < c%m) det = 0.0_wp
      return
    end if
    call cloud_moment(c, p, mm, ncover, xc, rex)
    det = 0.0_wp
    if (ncover < c%m) return
    call chol_small(c%m, mm, ok, singular_pivot)
    if (ok) det = chol_det(c%m, mm)
  end function cloud_det_excluding

  !> How far p is from the support of every particle that is not a reference neighbour of
  !! xc (reference position at rex, and at its own radius, or more from xc, as in
  !! cloud_det_excluding): the smallest max_k (|x_Ik - p_k| -
  !! rho_Ik) over them (a support of half-widths rho_I, box or ellipse, lies inside the box
  !! of those half-widths), capped at reach (m). No such particle covers p until p and it
  !! have moved towards each other by this much in some direction (and so by at least this
  !! much in distance); <= 0 when one may cover p now. A particle whose reference distance
  !! from xc is within a relative 1e-12 of that radius counts as a non-neighbour here, whichever
  !! side of rex the rounding of det(M)'s own test puts it (its sums are written out
  !! otherwise in det_3d_linear): so clear > 0 always means that cloud_det_excluding finds
  !! no particle covering p, and det(M) 0.
  pure real(wp) function cloud_clearance(c, p, xc, rex, reach) result(clear)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:), xc(:), rex, reach
    integer :: clo(3), chi(3), i, j, k, cc, q, nd
    logical :: empty
    real(wp) :: r(3), rex2
    nd = c%ndim
    clear = reach
    r(1:nd) = reach + c%rmax(1:nd)
    rex2 = rex*rex
    call bins_cell_block(c%bins, p, r(1:nd), clo, chi, empty)
    if (empty) return
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        cc = 1 + c%bins%nc(1)*(j + c%bins%nc(2)*k)
        do i = clo(1), chi(1)
          do q = c%bins%start(cc + i), c%bins%start(cc + i + 1) - 1
            if (sum((c%xr(:, q) - xc(1:nd))**2) < (1.0_wp - 1.0e-12_wp)* &
              max(rex2, c%rn2(q))) cycle
            clear = min(clear, maxval(abs(c%x(:, q) - p(1:nd)) - c%rho(:, q)))
          end do
        end do
      end do
    end do
  end function cloud_clearance

  !> Hot path for the paper's default (2D, bilinear basis, tensor-product window):
  !! the ten distinct moments summed in registers, then a 4x4 Cholesky.
  pure real(wp) function det_2d_bilinear_tensor(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer :: clo(3), chi(3), j, cc, q
    logical :: empty
    real(wp) :: dx, dy, w, z1, z2, z12, h1, h2
    real(wp) :: m11, m12, m13, m14, m22, m24, m33, m34, m44
    logical :: cubic
    det = 0.0_wp
    cubic = c%kid == kernel_cubic
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    h1 = c%hinv(1)
    h2 = c%hinv(2)
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do j = clo(2), chi(2)
      cc = 1 + c%bins%nc(1)*j
      do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
        dx = c%x(1, q) - p(1)
        dy = c%x(2, q) - p(2)
        if (abs(dx) >= c%rho(1, q) .or. abs(dy) >= c%rho(2, q)) cycle
        if (cubic) then
          w = 4.0_wp*c%rinv(1, q)*c%rinv(2, q)*c%vol(q) &
            *cubic_w(2.0_wp*abs(dx)*c%rinv(1, q))*cubic_w(2.0_wp*abs(dy)*c%rinv(2, q))
        else
          w = 4.0_wp*c%rinv(1, q)*c%rinv(2, q)*c%vol(q) &
            *window_1d(c%kid, 2.0_wp*dx*c%rinv(1, q))*window_1d(c%kid, 2.0_wp*dy*c%rinv(2, q))
        end if
        z1 = dx*h1
        z2 = dy*h2
        z12 = z1*z2
        m11 = m11 + w
        m12 = m12 + w*z1
        m13 = m13 + w*z2
        m14 = m14 + w*z12
        m22 = m22 + w*z1*z1
        m33 = m33 + w*z2*z2
        m24 = m24 + w*z12*z1
        m34 = m34 + w*z12*z2
        m44 = m44 + w*z12*z12
      end do
    end do
    ! M23 = M14 (eq. 19)
    det = det4_chol(m11, m12, m13, m14, m22, m14, m24, m33, m34, m44)
  end function det_2d_bilinear_tensor

  !> Hot path for mfcd's 3D detection basis (linear, P = (1, x, y, z), tensor-product
  !! window; doc/examples.md, "Three dimensions"): the ten distinct moments summed in
  !! registers over the bins' rows (x fastest), then a 4x4 Cholesky.
  pure real(wp) function det_3d_linear_tensor(c, p) result(det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer :: ncover
    call det_3d_linear(c, p, det, ncover)
  end function det_3d_linear_tensor

  !> det_3d_linear_tensor's loop; with xc and rex (self-contact's cloud_det_excluding) the
  !! particles whose reference position lies within rex (or their own radius, the larger)
  !! of xc are left out, and ncover
  !! counts the particles that remain (0 without them)
  pure subroutine det_3d_linear(c, p, det, ncover, xc, rex)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    real(wp), intent(out) :: det
    integer, intent(out) :: ncover
    real(wp), intent(in), optional :: xc(:), rex
    integer :: clo(3), chi(3), j, k, cc, q, nc
    logical :: empty, cubic, excl
    real(wp) :: dx, dy, dz, w, z1, z2, z3, h1, h2, h3, r1, r2, r3, rex2, c1, c2, c3
    real(wp) :: m11, m12, m13, m14, m22, m23, m24, m33, m34, m44
    det = 0.0_wp
    nc = 0
    ncover = 0
    excl = present(xc) .and. present(rex)
    rex2 = 0.0_wp
    c1 = 0.0_wp; c2 = 0.0_wp; c3 = 0.0_wp
    if (excl) then
      rex2 = rex*rex
      c1 = xc(1); c2 = xc(2); c3 = xc(3)
    end if
    cubic = c%kid == kernel_cubic
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    h1 = c%hinv(1)
    h2 = c%hinv(2)
    h3 = c%hinv(3)
    m11 = 0.0_wp; m12 = 0.0_wp; m13 = 0.0_wp; m14 = 0.0_wp; m22 = 0.0_wp
    m23 = 0.0_wp; m24 = 0.0_wp; m33 = 0.0_wp; m34 = 0.0_wp; m44 = 0.0_wp
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        cc = 1 + c%bins%nc(1)*(j + c%bins%nc(2)*k)
        do q = c%bins%start(cc + clo(1)), c%bins%start(cc + chi(1) + 1) - 1
          dx = c%x(1, q) - p(1)
          dy = c%x(2, q) - p(2)
          dz = c%x(3, q) - p(3)
          if (abs(dx) >= c%rho(1, q) .or. abs(dy) >= c%rho(2, q) .or. &
            abs(dz) >= c%rho(3, q)) cycle
          if (excl) then
            if ((c%xr(1, q) - c1)**2 + (c%xr(2, q) - c2)**2 + (c%xr(3, q) - c3)**2 < &
              max(rex2, c%rn2(q))) cycle
            nc = nc + 1
          end if
          r1 = c%rinv(1, q)
          r2 = c%rinv(2, q)
          r3 = c%rinv(3, q)
          if (cubic) then
            w = 8.0_wp*r1*r2*r3*c%vol(q)*cubic_w(2.0_wp*abs(dx)*r1) &
              *cubic_w(2.0_wp*abs(dy)*r2)*cubic_w(2.0_wp*abs(dz)*r3)
          else
            w = 8.0_wp*r1*r2*r3*c%vol(q)*window_1d(c%kid, 2.0_wp*dx*r1) &
              *window_1d(c%kid, 2.0_wp*dy*r2)*window_1d(c%kid, 2.0_wp*dz*r3)
          end if
          z1 = dx*h1
          z2 = dy*h2
          z3 = dz*h3
          m11 = m11 + w
          m12 = m12 + w*z1
          m13 = m13 + w*z2
          m14 = m14 + w*z3
          m22 = m22 + w*z1*z1
          m23 = m23 + w*z1*z2
          m24 = m24 + w*z1*z3
          m33 = m33 + w*z2*z2
          m34 = m34 + w*z2*z3
          m44 = m44 + w*z3*z3
        end do
      end do
    end do
    ncover = nc
    det = det4_chol(m11, m12, m13, m14, m22, m23, m24, m33, m34, m44)
  end subroutine det_3d_linear

  !> det of the symmetric 4x4 moment matrix given by its upper triangle, by an unrolled
  !! Cholesky factorization, column by column (the hot paths'); 0 when a pivot falls to
  !! singular_pivot of its diagonal entry or below (M singular or not positive definite).
  pure real(wp) function det4_chol(m11, m12, m13, m14, m22, m23, m24, m33, m34, m44) &
    result(det)
    real(wp), intent(in) :: m11, m12, m13, m14, m22, m23, m24, m33, m34, m44
    real(wp) :: l11, l21, l31, l41, l22, l32, l42, l33, l43, l44, s, tol
    det = 0.0_wp
    if (m11 <= 0.0_wp) return
    tol = singular_pivot
    l11 = sqrt(m11)
    l21 = m12/l11
    l31 = m13/l11
    l41 = m14/l11
    s = m22 - l21*l21
    if (s <= tol*m22) return
    l22 = sqrt(s)
    l32 = (m23 - l31*l21)/l22
    l42 = (m24 - l41*l21)/l22
    s = m33 - l31*l31 - l32*l32
    if (s <= tol*m33) return
    l33 = sqrt(s)
    l43 = (m34 - l41*l31 - l42*l32)/l33
    s = m44 - l41*l41 - l42*l42 - l43*l43
    if (s <= tol*m44) return
    l44 = sqrt(s)
    det = (l11*l22*l33*l44)**2
  end function det4_chol

  !> The cubic spline of eq. (8) at a = |s| < 2 (the caller has checked the support); the
  !! hot loop calls it directly, which lets the compiler inline it (window_1d's select case
  !! over kernels does not).
  pure real(wp) function cubic_w(a) result(w)
    real(wp), intent(in) :: a
    if (a < 1.0_wp) then
      w = 2.0_wp/3.0_wp - a*a*(1.0_wp - 0.5_wp*a)
    else
      w = (2.0_wp - a)**3/6.0_wp
    end if
  end function cubic_w

  !> RKPM shape functions N_I(p) = P(0)^T M^-1 P(z_I) phi_I V_I and gradients dN(ndim, :)
  !! with respect to p, for every particle covering p. ids are caller indices (perm).
  !! ok is false when M(p) is singular (p outside the body or too few particles).
  pure subroutine cloud_shape(c, p, nnb, ids, n, dn, ok)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer, intent(out) :: nnb
    integer, intent(inout) :: ids(:)
    real(wp), intent(inout) :: n(:), dn(:, :)
    logical, intent(out) :: ok
    integer :: clo(3), chi(3), i, j, k, cc, q, nd, m, a, l
    logical :: empty
    real(wp) :: d(3), z(3), pv(mmax), dpz(mmax, 3), phi, dphi(3), vol
    real(wp) :: mm(mmax, mmax), dmm(mmax, mmax, 3), b(mmax), db(mmax, 3)
    integer :: slot(max_cover)
    nd = c%ndim
    m = c%m
    nnb = 0
    ok = .false.
    mm = 0.0_wp
    dmm = 0.0_wp
    call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
    if (empty) return
    do k = clo(3), chi(3)
      do j = clo(2), chi(2)
        cc = 1 + c%bins%nc(1)*(j + c%bins%nc(2)*k)
        do i = clo(1), chi(1)
          do q = c%bins%start(cc + i), c%bins%start(cc + i + 1) - 1
            d(1:nd) = c%x(:, q) - p(1:nd)
            if (any(abs(d(1:nd)) >= c%rho(:, q))) cycle
            call window_eval(c%kid, c%wshape, nd, d(1:nd), c%rinv(:, q), c%cn, phi, &
              dphi(1:nd))
            if (phi <= 0.0_wp) cycle
            if (nnb >= min(size(ids), max_cover)) return
            nnb = nnb + 1
            slot(nnb) = q
            z(1:nd) = d(1:nd)*c%hinv(1:nd)
            call basis_eval_grad(c%bid, z(1:nd), pv, dpz)
            vol = c%vol(q)
            call moment_add(m, pv, phi*vol, mm)
            ! dM/dp_a: d/dp of d is -1, of z is -hinv.
            do a = 1, nd
              call add_dm(m, pv, -dpz(:, a)*c%hinv(a), phi*vol, -dphi(a)*vol, dmm(:, :, a))
            end do
          end do
        end do
      end do
    end do
    if (nnb == 0) return
    call moment_symmetrize(m, mm)
    do a = 1, nd
      call moment_symmetrize(m, dmm(:, :, a))
    end do
    call chol_small(m, mm, ok)
    if (.not. ok) return
    b = 0.0_wp
    b(1) = 1.0_wp
    call chol_solve(m, mm, b)
    do a = 1, nd
      db(1:m, a) = -matmul(dmm(1:m, 1:m, a), b(1:m))
      call chol_solve(m, mm, db(:, a))
    end do
    do l = 1, nnb
      q = slot(l)
      ids(l) = c%perm(q)
      d(1:nd) = c%x(:, q) - p(1:nd)
      z(1:nd) = d(1:nd)*c%hinv(1:nd)
      call window_eval(c%kid, c%wshape, nd, d(1:nd), c%rinv(:, q), c%cn, phi, dphi(1:nd))
      call basis_eval_grad(c%bid, z(1:nd), pv, dpz)
      vol = c%vol(q)
      n(l) = dot_product(b(1:m), pv(1:m))*phi*vol
      do a = 1, nd
        dn(a, l) = (dot_product(db(1:m, a), pv(1:m))*phi &
          - dot_product(b(1:m), dpz(1:m, a))*c%hinv(a)*phi &
          - dot_product(b(1:m), pv(1:m))*dphi(a))*vol
      end do
    end do
  end subroutine cloud_shape

  !> The RK shape functions' values at p (cloud_shape without the derivatives): N_I(p) =
  !! b^T P(z_I) phi_I V_I with M(p) b = e_1, for the nnb particles ids(1:nnb) (original
  !! numbers) whose supports cover p; ok false where M(p) is singular or more particles
  !! cover p than ids holds. A quarter of cloud_shape's work in 3D (no moment-matrix
  !! derivatives, one window evaluation per particle): what integration tables need where
  !! only N enters (the face and volume integrals of the 3D SCNI builder). With cand: the
  !! particles scanned are cand(1:size(cand)) (packed cloud indices in the bins' order,
  !! e.g. cloud_candidates' for a region holding p) instead of the bins' block around p:
  !! every particle covering p among them, in the same order, so the same sums to the bit.
  !! With apart: n_I = ((b^T P(z_I)) phi_I) V_I, each the same number as cloud_shape's to
  !! the bit (its order of the products): the 2D tables that take only N at their points
  !! (SCNI's boundary and area integrals, the position rows; measured 2026-12-07,
  !! doc/benchmarks.md); else (b^T P(z_I)) (phi_I V_I), the 3D builder's.
  subroutine cloud_shape_values(c, p, nnb, ids, n, ok, cand, apart)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:)
    integer, intent(out) :: nnb
    integer, intent(inout) :: ids(:)
    real(wp), intent(inout) :: n(:)
    logical, intent(out) :: ok
    integer, intent(in), optional :: cand(:)
    logical, intent(in), optional :: apart
    integer :: clo(3), chi(3), q, nd, m, l, r, nrun, qa, qb, cap
    logical :: empty, vapart
    real(wp) :: d(3), z(3), pv(mmax), phi, mm(mmax, mmax), b(mmax)
    integer :: slot(max_cover)
    nd = c%ndim
    m = c%m
    nnb = 0
    ok = .false.
    vapart = .false.
    if (present(apart)) vapart = apart
    cap = min(size(ids), max_cover)
    mm = 0.0_wp
    ! the particles scanned as runs of packed indices: each of cand alone, or each row of
    ! the bins' block around p (its cells are consecutive in the bins' order), so that one
    ! loop body serves both, inline
    if (present(cand)) then
      nrun = size(cand)
    else
      call bins_cell_block(c%bins, p, c%rmax, clo, chi, empty)
      if (empty) return
      nrun = bins_block_runs(clo, chi)
    end if
    do r = 1, nrun
      if (present(cand)) then
        qa = cand(r)
        qb = qa
      else
        call bins_block_run(c%bins, clo, chi, r, qa, qb)
      end if
      do q = qa, qb
        d(1:nd) = c%x(:, q) - p(1:nd)
        if (any(abs(d(1:nd)) >= c%rho(:, q))) cycle
        call window_eval(c%kid, c%wshape, nd, d(1:nd), c%rinv(:, q), c%cn, phi)
        if (phi <= 0.0_wp) cycle
        if (nnb >= cap) return
        nnb = nnb + 1
        slot(nnb) = q
        ! (n holds phi V, or phi with apart, until the coefficients are known)
        n(nnb) = phi*c%vol(q)
        z(1:nd) = d(1:nd)*c%hinv(1:nd)
        call basis_eval(c%bid, z(1:nd), pv)
        call moment_add(m, pv, n(nnb), mm)
        if (vapart) n(nnb) = phi
      end do
    end do
    if (nnb == 0) return
    call moment_symmetrize(m, mm)
    call chol_small(m, mm, ok)
    if (.not. ok) return
    b = 0.0_wp
    b(1) = 1.0_wp
    call chol_solve(m, mm, b)
    do l = 1, nnb
      q = slot(l)
      ids(l) = c%perm(q)
      d(1:nd) = c%x(:, q) - p(1:nd)
      z(1:nd) = d(1:nd)*c%hinv(1:nd)
      call basis_eval(c%bid, z(1:nd), pv)
      if (vapart) then
        n(l) = dot_product(b(1:m), pv(1:m))*n(l)*c%vol(q)
      else
        n(l) = dot_product(b(1:m), pv(1:m))*n(l)
      end if
    end do
  end subroutine cloud_shape_values

  !> The particles of cloud c (packed indices, in the bins' order) whose supports may
  !! cover a point of the box [p - r, p + r]: |x_q - p| < rho_q + r in every direction;
  !! cand must hold them (c%np is enough).
  pure subroutine cloud_candidates(c, p, r, cand, ncand)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:), r(:)
    integer, intent(inout) :: cand(:)
    integer, intent(out) :: ncand
    integer :: k, q, n, nd
    nd = c%ndim
    call bins_candidates(c%bins, p, c%rmax(1:nd) + r(1:nd), cand, n)
    ncand = 0
    do k = 1, n
      q = cand(k)
      if (any(abs(c%x(:, q) - p(1:nd)) >= c%rho(:, q) + r(1:nd))) cycle
      ncand = ncand + 1
      cand(ncand) = q
    end do
  end subroutine cloud_candidates

  !> Upper triangle of dm += (dp p^T + p dp^T) w + p p^T dw.
  pure subroutine add_dm(m, p, dp, w, dw, dm)
    integer, intent(in) :: m
    real(wp), intent(in) :: p(:), dp(:), w, dw
    real(wp), intent(inout) :: dm(:, :)
    integer :: i, j
    do j = 1, m
      do i = 1, j
        dm(i, j) = dm(i, j) + (dp(i)*p(j) + p(i)*dp(j))*w + p(i)*p(j)*dw
      end do
    end do
  end subroutine add_dm
end module rk_cloud_m
