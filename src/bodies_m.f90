!> Builds the bodies a deck describes (generators or particle files), then checks that each
!! is an admissible discretization for its window and basis (Theorem 3.1): the moment matrix
!! must be non-singular everywhere in the body. On a lattice the smallest working
!! support_factor is found by scanning a lattice patch, so the error can name it.
module bodies_m
  use kinds_m, only: wp, pi
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use body_m, only: body_t
  use deck_m, only: deck_t, body_spec_t
  use basis_m, only: mmax, basis_size
  use generators_m, only: make_segment, make_rectangle, make_polygon, make_annulus, &
    make_from_arrays, set_supports
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_moment
  use moment_matrix_m, only: chol_small
  use hdf5_io_m, only: read_particle_file_h5
  use detection_m, only: body_cloud
  use cst4_m, only: cst4_mesh_t, cst4_rectangle
  implicit none
  private
  public :: build_bodies, build_body, lattice_admissible, min_support_factor
  public :: read_particle_columns

  !> Relative pivot below which M counts as singular in the admissibility checks: far above
  !! round-off (1e-16) and far below the weakest genuine pivot of an admissible lattice
  !! (about 1e-6 for a support factor 1% above the Theorem 3.1 limit).
  real(wp), parameter :: pivot_tol = 1.0e-10_wp

contains

  !> Build and check every body of the deck.
  subroutine build_bodies(deck, bodies, err)
    type(deck_t), intent(in) :: deck
    type(body_t), allocatable, intent(out) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    allocate(bodies(deck%nbodies))
    do k = 1, deck%nbodies
      call build_body(deck, deck%bodies(k), k, bodies(k), err)
      if (allocated(err)) return
    end do
  end subroutine build_bodies

  !> One body from its spec; err names deck, group and variable on failure.
  subroutine build_body(deck, s, k, b, err)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: s
    integer, intent(in) :: k
    type(body_t), intent(out) :: b
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: where
    real(wp), allocatable :: local(:), xs(:, :), vols(:)
    integer, allocatable :: loop(:), order(:)
    real(wp) :: dr, dt, fmin
    integer :: nd, i
    type(error_t), allocatable :: e2
    type(cst4_mesh_t) :: mesh
    nd = deck%run%ndim
    where = "deck '"//deck%path//"', group &body (body "//itoa(k)//", '"//trim(s%name)//"')"
    select case (s%shape)
    case ('segment')
      call make_segment(b, s%lo(1), s%hi(1), s%n(1), e2)
    case ('rectangle')
      if (s%discretization == 'fem') then
        ! CST4 elements on the boxes of the n(1) x n(2) lattice; nodes carry the det(M)
        ! cloud with supports from the element sizes (Section 6)
        call cst4_rectangle(s%lo(1:2), s%hi(1:2), s%n(1:2) - 1, s%support_factor(1:2), b, &
          mesh, e2)
        if (.not. allocated(e2)) call move_alloc(mesh%tri, b%cells)
      else
        call make_rectangle(b, s%lo(1:2), s%hi(1:2), s%n(1:2), e2)
      end if
    case ('polygon')
      call make_polygon(b, s%vertices(:, 1:s%nvert), s%spacing(1:2), s%origin, e2)
    case ('annulus_sector')
      call make_annulus(b, s%center, s%r_inner, s%r_outer, s%theta_start*pi/180.0_wp, &
        s%theta_end*pi/180.0_wp, s%n(1), s%n(2), e2)
    case ('file')
      call read_particles(trim(s%file), nd, xs, vols, loop, order, e2)
      if (.not. allocated(e2)) call make_from_arrays(b, xs, vols, loop, order, e2)
      if (.not. allocated(e2) .and. s%spacing(1) > 0.0_wp) b%spacing(1:nd) = s%spacing(1:nd)
    end select
    if (allocated(e2)) then
      call set_error(err, where//': '//e2%message)
      return
    end if
    b%name = s%name
    b%shape = s%shape
    b%kid = s%kid
    b%wshape = s%wshape
    b%bid = s%bid
    if (s%shape == 'annulus_sector') then
      dr = (s%r_outer - s%r_inner)/real(s%n(1) - 1, wp)
      dt = (s%theta_end - s%theta_start)*pi/180.0_wp
      if (s%theta_end - s%theta_start >= 360.0_wp - 1.0e-9_wp) then
        dt = dt/real(s%n(2), wp)
      else
        dt = dt/real(s%n(2) - 1, wp)
      end if
      allocate(local(b%np))
      do i = 1, b%np
        local(i) = max(dr, norm2(b%x(:, i) - s%center)*dt)
      end do
      call set_supports(b, s%support_factor, local)
    else if (.not. allocated(b%cells)) then
      call set_supports(b, s%support_factor)
    end if
    ! Theorem 3.1 on the generating lattice: name the smallest support factor that works.
    if (any(s%shape == ['segment  ', 'rectangle', 'polygon  ']) .and. &
      .not. allocated(b%cells)) then
      if (.not. lattice_admissible(b%kid, b%wshape, b%bid, nd, b%spacing(1:nd), &
        s%support_factor(1:nd))) then
        fmin = min_support_factor(b%kid, b%wshape, b%bid, nd, b%spacing(1:nd))
        call set_error(err, where//', variable support_factor = '// &
          rtoa(minval(s%support_factor(1:nd)))//': too small for basis '''// &
          trim(s%basis)//''' with the '//trim(s%window)//' window (Theorem 3.1: some '// &
          'points are covered by fewer than '//itoa(basis_size(b%bid))// &
          ' non-degenerate particles, so M is singular); use support_factor >= '// &
          rtoa(fmin)//' (a margin above it, e.g. '//rtoa(max(2.0_wp, &
          real(ceiling(2.0_wp*fmin), wp)/2.0_wp))//', is typical)')
        return
      end if
    end if
    call check_particles(b, where, err)
  end subroutine build_body

  !> det(M) > 0 at every particle of the body (Theorem 3.1 for any distribution).
  subroutine check_particles(b, where, err)
    type(body_t), intent(in) :: b
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: c
    real(wp) :: mm(mmax, mmax)
    integer :: i, ncover, bad_i, bad_n
    logical :: ok
    call body_cloud(b, c, err)
    if (allocated(err)) return
    bad_i = 0
    bad_n = 0
    !$omp parallel do default(none) shared(b, c) private(mm, ncover, ok) &
    !$omp reduction(max: bad_i) reduction(max: bad_n)
    do i = 1, b%np
      call cloud_moment(c, b%x(:, i), mm, ncover)
      call chol_small(c%m, mm, ok, pivot_tol)
      if (.not. ok .and. i > bad_i) then
        bad_i = i
        bad_n = ncover
      end if
    end do
    !$omp end parallel do
    if (bad_i > 0) then
      call set_error(err, where//', variable support_factor: moment matrix singular at '// &
        'particle '//itoa(bad_i)//' (covered by '//itoa(bad_n)//' particles, basis needs '// &
        'at least '//itoa(basis_size(b%bid))//' in general position): increase support_factor')
    end if
  end subroutine check_particles

  !> True when M is non-singular at every probe of a lattice patch with these supports.
  !! The patch is a corner of a lattice (indices 0 .. 2K per direction), the worst place on
  !! a convex lattice body: probes are a 5^ndim sub-grid of the corner cell and of the
  !! central cell (particles, mid-edges, centres).
  function lattice_admissible(kid, wshape, bid, ndim, spacing, factor) result(ok)
    integer, intent(in) :: kid, wshape, bid, ndim
    real(wp), intent(in) :: spacing(:), factor(:)
    logical :: ok
    integer, parameter :: nsub = 5
    type(rk_cloud_t) :: c
    type(error_t), allocatable :: err
    real(wp), allocatable :: x(:, :), rho(:, :), vol(:)
    real(wp) :: p(3), mm(mmax, mmax)
    integer :: kpatch, nside, np, i, j, ijk(3), ncover, nprobe, cell
    kpatch = ceiling(maxval(factor(1:ndim))) + 2
    nside = 2*kpatch + 1
    np = nside**ndim
    allocate(x(ndim, np), rho(ndim, np), vol(np))
    do i = 1, np
      call unflatten(i - 1, nside, ndim, ijk)
      x(:, i) = real(ijk(1:ndim), wp)*spacing(1:ndim)
      rho(:, i) = factor(1:ndim)*spacing(1:ndim)
    end do
    vol = product(spacing(1:ndim))
    call cloud_init(c, x, rho, vol, kid, wshape, bid, factor(1:ndim)*spacing(1:ndim), err)
    ok = .not. allocated(err)
    nprobe = nsub**ndim
    do cell = 0, kpatch, kpatch
      do j = 1, nprobe
        if (.not. ok) return
        call unflatten(j - 1, nsub, ndim, ijk)
        p = 0.0_wp
        p(1:ndim) = (real(cell, wp) + real(ijk(1:ndim), wp)/real(nsub - 1, wp)) &
          *spacing(1:ndim)
        call cloud_moment(c, p(1:ndim), mm, ncover)
        call chol_small(c%m, mm, ok, pivot_tol)
      end do
    end do
  end function lattice_admissible

  !> Smallest isotropic support factor (0.01 steps, 0.5 .. 8) that is admissible; -1 if none.
  function min_support_factor(kid, wshape, bid, ndim, spacing) result(fmin)
    integer, intent(in) :: kid, wshape, bid, ndim
    real(wp), intent(in) :: spacing(:)
    real(wp) :: fmin
    integer :: k
    real(wp) :: f(3)
    fmin = -1.0_wp
    do k = 50, 800
      f = real(k, wp)/100.0_wp
      if (lattice_admissible(kid, wshape, bid, ndim, spacing, f)) then
        fmin = f(1)
        return
      end if
    end do
  end function min_support_factor

  pure subroutine unflatten(i, n, ndim, ijk)
    integer, intent(in) :: i, n, ndim
    integer, intent(out) :: ijk(3)
    ijk = 0
    ijk(1) = mod(i, n)
    if (ndim > 1) ijk(2) = mod(i/n, n)
    if (ndim > 2) ijk(3) = i/(n*n)
  end subroutine unflatten

  !> Particle file: HDF5 (.h5, .hdf5) or plain columns.
  subroutine read_particles(path, ndim, x, vol, loop, order, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ndim
    real(wp), allocatable, intent(out) :: x(:, :), vol(:)
    integer, allocatable, intent(out) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: l
    l = len_trim(path)
    if (l > 3 .and. (path(max(1, l - 2):l) == '.h5' .or. path(max(1, l - 4):l) == '.hdf5')) then
      call read_particle_file_h5(path, ndim, x, vol, loop, order, err)
    else
      call read_particle_columns(path, ndim, x, vol, loop, order, err)
    end if
  end subroutine read_particles

  !> Plain columns, one particle a line: x [y [z]] volume [loop order]; '#' starts a comment.
  !! loop = 0 for interior particles, k > 0 for particles on boundary polyline k, with order
  !! their position along it (counter-clockwise around the material).
  subroutine read_particle_columns(path, ndim, x, vol, loop, order, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ndim
    real(wp), allocatable, intent(out) :: x(:, :), vol(:)
    integer, allocatable, intent(out) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: u, ios, n, lineno, i
    character(len=1024) :: line
    character(len=512) :: msg
    real(wp) :: vals(5)
    integer :: lo_or(2)
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(err, "particle file '"//path//"': "//trim(msg))
      return
    end if
    n = 0
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (is_data(line)) n = n + 1
    end do
    allocate(x(ndim, n), vol(n), loop(n), order(n))
    rewind(u)
    i = 0
    lineno = 0
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      lineno = lineno + 1
      if (.not. is_data(line)) cycle
      i = i + 1
      read(line, *, iostat=ios) vals(1:ndim + 1)
      if (ios /= 0) then
        call set_error(err, "particle file '"//path//"' line "//itoa(lineno)// &
          ": expected "//itoa(ndim)//" coordinates and a volume")
        close(u)
        return
      end if
      x(:, i) = vals(1:ndim)
      vol(i) = vals(ndim + 1)
      read(line, *, iostat=ios) vals(1:ndim + 1), lo_or
      if (ios /= 0) lo_or = 0
      loop(i) = lo_or(1)
      order(i) = lo_or(2)
    end do
    close(u)
  contains
    pure logical function is_data(l)
      character(len=*), intent(in) :: l
      character(len=len(l)) :: t
      t = adjustl(l)
      is_data = len_trim(t) > 0 .and. t(1:1) /= '#'
    end function is_data
  end subroutine read_particle_columns
end module bodies_m
