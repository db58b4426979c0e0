!> Total-Lagrangian RKPM tables (Section 4; mfcd's choices: doc/solver.md): everything that
!! depends only on the reference configuration, computed once before the time loop.
!!
!! For each integration point L the tables hold the particles I whose shape functions touch
!! it (CSR: ptr, nbr) with the reference gradients g of their shape functions, the hoop term
!! h (axisymmetry), the weight W_L, plus the lumped masses (eq. 70), the table N_I(X_J) that
!! turns coefficients into physical positions, and the transpose that lets the internal
!! force be gathered per particle without write races.
!!
!! Integration schemes:
!!  - SCNI (default; Chen, Wu, Yoon, You 2001): one point per particle, its lattice cell
!!    clipped by the body, plus the clipped lattice cells merged into it along the outline
!!    (make_polygon: cells whose point lies outside the body), so the cells tile the body
!!    and their weights sum to its area (axisymmetry: volume); each piece is integrated
!!    and the pieces added, so the lines they share cancel; smoothed gradients
!!    b_I = (1/A_L) \oint N_I n dGamma with two Gauss points per cell edge. In axisymmetry
!!    the smoothing is weighted with r:
!!    V_L = \int_L r dA, b_Ia = (1/V_L)[\oint N_I n_a r dGamma - delta_a1 \int_L N_I dA],
!!    h_I = (1/V_L) \int_L N_I dA (the hoop term u_r/r), W_L = 2 pi V_L. For linear fields
!!    b and h are exact and the interior forces of a uniform state vanish: the patch test
!!    holds to round-off in plane strain and in axisymmetry.
!!  - Gauss: background quadrature, three points per triangle of each cell (fan).
!!  - Direct nodal integration: gradients at the particles, W = volume. A negative control
!!    only (spurious zero-energy modes), plane strain only.
!!
!! Symmetry axis (axisymmetry, r = X1 = 0): particles whose support crosses the axis get a
!! mirrored ghost at -r that carries (-u_r, u_z) of its twin. Folding the ghost onto the twin
!! gives component-wise shape functions N^r_I = N_I - N_I', N^z_I = N_I + N_I', so
!! u_r(0, z) = 0 exactly by symmetry; particles on the axis have their u_r coefficient fixed
!! at 0 (their own mirror image).
module rkpm_tl_m
  use kinds_m, only: wp, pi
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use body_m, only: body_t, max_cell_vertices
  use dims_m, only: dims_plane
  use solid_tables_m, only: solid_tables_t, tables_transpose
  use geometry_m, only: geom_polygon, clip_polygon_box
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_shape, cloud_shape_values, cloud_count_cover
  use neighbour_bins_m, only: bins_candidates
  use generators_m, only: lattice_pick
  implicit none
  private
  public :: solid_tables_t, tl_build, scheme_scni, scheme_gauss, scheme_direct, scheme_names
  public :: scheme_id, tl_region_2d, axis_images
  ! (the 3D builder rkpm_tl3d_m integrates its cells' x-y sections with it)
  public :: cell_area_points

  integer, parameter :: scheme_scni = 1, scheme_gauss = 2, scheme_direct = 3
  character(len=*), parameter :: scheme_names(3) = [character(len=6) :: &
    'scni', 'gauss', 'direct']
  integer, parameter :: max_nb = 512    !< particles covering one evaluation point
  integer, parameter :: max_cv = max_cell_vertices   !< vertices of one cell
  !> An axisymmetric body may reach this fraction of its spacing below r = 0 (round-off of
  !! a coordinate on the axis; far below any particle's distance from it).
  real(wp), parameter :: axis_fraction = 1.0e-9_wp
  !> A sub-cell half holding less than this fraction of its cell's volume is empty (a
  !! particle on the boundary) and gets no stabilization: far above the round-off of the
  !! clipped areas, far below any genuine half (about a half).
  real(wp), parameter :: empty_half = 1.0e-9_wp

contains

  !> Scheme id from its deck name, 0 if unknown.
  pure integer function scheme_id(name)
    character(len=*), intent(in) :: name
    integer :: k
    scheme_id = 0
    do k = 1, size(scheme_names)
      if (trim(adjustl(name)) == trim(scheme_names(k))) scheme_id = k
    end do
  end function scheme_id

  !> Build the tables of body b (reference configuration). rho0: density (kg/m^3).
  !!
  !! box (3, 2), a rank's box of the decomposition (lower, upper corner; the first two rows used;
  !! doc/parallel.md): the rows of the integration points are kept, and their shape functions
  !! computed, only where a particle of the box can be in them: a point whose cell (SCNI: the
  !! bounding box of its pieces and its particle; Gauss and direct: the point) lies within the
  !! largest support of the box, so every point the rank's part owns and every point touching a node
  !! it owns (decomposition_m local_part_build takes no other rows); the position rows of the
  !! particles within the largest support and cell extent of the box (the nodes of those rows). Only
  !! the particles near enough to touch those rows enter the cloud (region_cloud). The others' rows
  !! are empty, their weights and positions whole (a few flops). The masses of the particles in the
  !! box are then whole (the same sums in the same order), the others' partial: dynamic_setup_m
  !! whole_masses completes them over the ranks. The tables are not transposed (the split transposes
  !! the part's).
  subroutine tl_build(b, axisym, scheme, rho0, t, err, box)
    type(body_t), intent(in) :: b
    logical, intent(in) :: axisym
    integer, intent(in) :: scheme
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(out) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: box(3, 2)
    type(rk_cloud_t) :: c
    real(wp), allocatable :: xe(:, :), rhoe(:, :), vole(:)
    integer, allocatable :: twin(:)
    real(wp) :: tol, reg(2, 2), ext(2), lo(2), hi(2)
    integer :: np, ng, i, k
    np = b%np
    t%np = np
    t%axisym = axisym
    t%dims = dims_plane   ! these builders make the plane tables
    t%scheme = scheme
    if (b%ndim /= 2) then
      call set_error(err, 'the RKPM solver needs ndim = 2 (plane strain or axisymmetric)')
      return
    end if
    if (b%geom%kind /= geom_polygon .and. .not. allocated(b%cell_ptr) .and. &
      scheme /= scheme_direct) then
      call set_error(err, "body '"//trim(b%name)//"': SCNI and Gauss integration need "// &
        "the cells of a 'rectangle' or 'polygon' body or of a particle file with /cells "// &
        "(shape = '"//trim(b%shape)//"')")
      return
    end if
    if (axisym .and. scheme == scheme_direct) then
      call set_error(err, "direct nodal integration is a negative control for plane strain "// &
        "only; use integration = 'scni' or 'gauss' in axisymmetry")
      return
    end if
    tol = axis_fraction*minval(b%spacing(1:2))
    if (axisym .and. minval(b%x(1, :)) < -tol) then
      call set_error(err, "body '"//trim(b%name)//"': axisymmetric bodies must lie in r >= 0 "// &
        "(x = r is the first coordinate)")
      return
    end if
    ! ghosts mirrored about the axis
    ng = 0
    if (axisym) ng = count(b%x(1, :) > tol .and. b%x(1, :) < b%rho(1, :))
    allocate(xe(2, np + ng), rhoe(2, np + ng), vole(np + ng), twin(np + ng))
    xe(:, 1:np) = b%x
    rhoe(:, 1:np) = b%rho
    vole(1:np) = b%vol
    twin = [(i, i = 1, np + ng)]
    k = np
    if (axisym) then
      do i = 1, np
        if (b%x(1, i) > tol .and. b%x(1, i) < b%rho(1, i)) then
          k = k + 1
          xe(:, k) = [-b%x(1, i), b%x(2, i)]
          rhoe(:, k) = b%rho(:, i)
          vole(k) = b%vol(i)
          twin(k) = -i
        end if
      end do
    end if
    allocate(t%fix1(np))
    t%fix1 = axisym .and. abs(b%x(1, :)) <= tol
    ! the region whose rows are kept: the whole plane, or the box
    reg(:, 1) = -huge(1.0_wp)
    reg(:, 2) = huge(1.0_wp)
    ext = 0.0_wp
    if (present(box)) then
      reg = box(1:2, :)
      ext = largest_cell(b, scheme)
      if (allocated(b%glob) .and. allocated(b%mfile)) then
        ! (b holds some nodes of a plane mesh file, a rank's region read from it: the
        ! whole cloud's extremes are the mesh's, placed, and its largest supports the
        ! factors times the mesh's longest edge, as each node's is the factors times its
        ! own)
        lo = b%mfile%lo(1:2) + b%mfile%shift(1:2)
        hi = b%mfile%hi(1:2) + b%mfile%shift(1:2)
        ! (in axisymmetry the images' too, which rank 0 took of the whole body: mfcd_mpi)
        if (axisym) then
          lo(1) = min(lo(1), b%mfile%image(1))
          hi(1) = max(hi(1), b%mfile%image(2))
        end if
        call region_cloud(b, ext, reg, xe, rhoe, vole, twin, c, err, lo, hi, &
          b%support_factor(1:2)*b%mfile%lmax)
      else if (allocated(b%glob)) then
        ! (b holds some particles of a rectangle, a rank's region made from its recipe:
        ! the whole cloud's extremes are those of its outermost ring and their images)
        call whole_extremes(b, axisym, tol, lo, hi)
        call region_cloud(b, ext, reg, xe, rhoe, vole, twin, c, err, lo, hi)
      else
        call region_cloud(b, ext, reg, xe, rhoe, vole, twin, c, err)
      end if
    else
      call cloud_init(c, xe, rhoe, vole, b%kid, b%wshape, b%bid, b%h(1:2), err)
    end if
    if (allocated(err)) return
    t%hmin = minval(b%spacing(1:2))
    select case (scheme)
    case (scheme_scni)
      call build_scni(b, c, twin, np, rho0, reg, t, err)
    case (scheme_gauss)
      call build_gauss(b, c, twin, np, rho0, reg, t, err)
    case (scheme_direct)
      call build_direct(b, c, twin, np, rho0, reg, t, err)
    end select
    if (allocated(err)) return
    call build_positions(b, c, twin, np, reg, ext, t, err)
    if (allocated(err)) return
    if (.not. present(box)) call tables_transpose(t)
    t%total_mass = sum(t%mass)
    t%total_volume = sum(t%wgt)
  end subroutine tl_build

  !> The largest extent of a cell of body b (per axis, m): a point of a row lies within it
  !! of the row's particle (cell_extent); 0 for direct nodal integration (the point is
  !! the particle).
  function largest_cell(b, scheme) result(ext)
    type(body_t), intent(in) :: b
    integer, intent(in) :: scheme
    real(wp) :: ext(2), lo(2), hi(2)
    integer :: i
    ext = 0.0_wp
    if (scheme == scheme_direct) return
    do i = 1, b%np
      call cell_extent(b, i, lo, hi)
      ext = max(ext, hi - lo)
    end do
  end function largest_cell

  !> The cloud of a rank's region reg of body b (tl_build's box): of the particles and
  !! images xe, rhoe, vole, twin (the whole cloud's), those within reach of reg of a
  !! point a kept row integrates or a kept position row is taken at (twice the largest
  !! support and the largest cell extent ext, one spacing more for rounding), in the same
  !! order, with the whole cloud's extremes and largest supports (cloud_init's grid): the
  !! same shape functions there, to the bit. twin is cut to the region cloud's.
  subroutine region_cloud(b, ext, reg, xe, rhoe, vole, twin, c, err, wlo, whi, wrmax)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: ext(2), reg(2, 2), xe(:, :), rhoe(:, :), vole(:)
    integer, allocatable, intent(inout) :: twin(:)
    type(rk_cloud_t), intent(out) :: c
    type(error_t), allocatable, intent(inout) :: err
    !> the whole cloud's extremes when xe is a region's cloud (whole_extremes)
    real(wp), intent(in), optional :: wlo(2), whi(2)
    !> and its largest supports, when the region's may be smaller (a graded mesh's)
    real(wp), intent(in), optional :: wrmax(2)
    real(wp) :: rmax(2), grow(2), lo(2), hi(2)
    logical, allocatable :: near(:)
    integer :: i
    rmax = maxval(rhoe, dim=2)
    if (present(wrmax)) rmax = wrmax
    grow = 2.0_wp*rmax + ext + b%spacing(1:2)
    allocate(near(size(xe, 2)))
    do i = 1, size(xe, 2)
      near(i) = all(xe(:, i) >= reg(:, 1) - grow) .and. all(xe(:, i) <= reg(:, 2) + grow)
    end do
    if (present(wlo)) then
      lo = wlo
      hi = whi
    else
      lo = minval(xe, dim=2)
      hi = maxval(xe, dim=2)
    end if
    call cloud_init(c, reshape(pack(xe, spread(near, 1, 2)), [2, count(near)]), &
      reshape(pack(rhoe, spread(near, 1, 2)), [2, count(near)]), pack(vole, near), b%kid, &
      b%wshape, b%bid, b%h(1:2), err, lo, hi, rmax)
    twin = pack(twin, near)
  end subroutine region_cloud

  !> The extremes [lo, hi] of the whole cloud of rectangle b (particles and their mirror
  !! images about the axis in axisymmetry, as tl_build makes them; tol its axis
  !! tolerance) when b holds a rank's region only (made from the recipe: generators_m
  !! lattice_pick): those of the lattice's outermost ring, whose rows and columns take
  !! every coordinate a particle or image has (min and max are exact: the same bits).
  subroutine whole_extremes(b, axisym, tol, lo, hi)
    type(body_t), intent(in) :: b
    logical, intent(in) :: axisym
    real(wp), intent(in) :: tol
    real(wp), intent(out) :: lo(2), hi(2)
    type(body_t) :: ring
    integer :: none(1)
    real(wp) :: nowhere(1)
    none = 0
    nowhere = 0.0_wp
    call lattice_pick(b, 1, huge(1), [-huge(1.0_wp), -huge(1.0_wp)], &
      [huge(1.0_wp), huge(1.0_wp)], 0, none, nowhere, ring, ends=.true.)
    lo = minval(ring%x, dim=2)
    hi = maxval(ring%x, dim=2)
    if (.not. axisym) return
    call axis_images(ring, lo(1), hi(1), tol)
  end subroutine whole_extremes

  !> The least and largest first coordinate, lo and hi (given, then lowered and raised), of
  !! the mirror images about the axis that tl_build makes of body b's particles in
  !! axisymmetry (those with tol < x < rho(1), tol = axis_fraction x b's smaller spacing
  !! unless given): the whole cloud's extremes take them. (mfcd_mpi takes them of a whole
  !! plane mesh body for the ranks that read it per part: tri_file_m.)
  pure subroutine axis_images(b, lo, hi, tol_given)
    type(body_t), intent(in) :: b
    real(wp), intent(inout) :: lo, hi
    real(wp), intent(in), optional :: tol_given
    real(wp) :: tol
    integer :: i
    tol = axis_fraction*minval(b%spacing(1:2))
    if (present(tol_given)) tol = tol_given
    do i = 1, size(b%x, 2)
      if (b%x(1, i) > tol .and. b%x(1, i) < b%rho(1, i)) then
        lo = min(lo, -b%x(1, i))
        hi = max(hi, -b%x(1, i))
      end if
    end do
  end subroutine axis_images

  !> The particles of rectangle b (made from its recipe, generators_m lattice_pick: the
  !! whole body need not exist) that tl_build's tables for box read: those whose position
  !! or mirror image about the axis (axisymmetry) lies within the box grown by what
  !! region_cloud takes (twice the supports, a cell, a spacing) and one spacing more; as
  !! body r numbered over them (r%glob: their numbers in b), in b's order. tl_build(r, ...,
  !! box) then makes the same rows as tl_build(b, ..., box), over r's numbers.
  subroutine tl_region_2d(b, axisym, box, r)
    type(body_t), intent(in) :: b
    logical, intent(in) :: axisym
    real(wp), intent(in) :: box(3, 2)
    type(body_t), intent(out) :: r
    real(wp) :: grow(2), pos(1)
    integer :: normal(1), n
    grow = 2.0_wp*b%lat%rho + 3.0_wp*b%spacing(1:2)
    n = 0
    normal = 1
    pos = 0.0_wp
    if (axisym) n = 1
    call lattice_pick(b, 1, b%np, box(1:2, 1) - grow, box(1:2, 2) + grow, n, normal, pos, r)
  end subroutine tl_region_2d

  !> Piece k of particle i's cell, clipped by the body polygon: vertices cv(2, ncv). Piece 0
  !! is the particle's own lattice cell, pieces 1 .. cell_pieces(b, i) the lattice cells
  !! merged into it (b%merged_centre).
  pure subroutine particle_cell(b, i, k, cv, ncv)
    type(body_t), intent(in) :: b
    integer, intent(in) :: i, k
    real(wp), intent(out) :: cv(2, max_cv)
    integer, intent(out) :: ncv
    real(wp) :: half(2), o(2)
    if (allocated(b%cell_ptr)) then
      ! the particle file's own cell (one piece)
      ncv = min(b%cell_ptr(i + 1) - b%cell_ptr(i), max_cv)
      cv(:, 1:ncv) = b%cell_xy(:, b%cell_ptr(i):b%cell_ptr(i) + ncv - 1)
      return
    end if
    half = 0.5_wp*b%spacing(1:2)
    if (k == 0) then
      o = cell_centre_of(b, i)
    else
      o = b%merged_centre(:, b%merged_ptr(i) + k - 1)
    end if
    call clip_polygon_box(b%geom%v, o - half, o + half, cv, ncv)
  end subroutine particle_cell

  !> Number of lattice cells merged into particle i's cell (besides its own).
  pure integer function cell_pieces(b, i) result(n)
    type(body_t), intent(in) :: b
    integer, intent(in) :: i
    n = 0
    if (allocated(b%merged_ptr)) n = b%merged_ptr(i + 1) - b%merged_ptr(i)
  end function cell_pieces

  !> Centre of particle i's lattice cell (m): the particle itself unless the particles were
  !! moved off the lattice (&body perturbation), whose cells stay the lattice's.
  pure function cell_centre_of(b, i) result(o)
    type(body_t), intent(in) :: b
    integer, intent(in) :: i
    real(wp) :: o(2)
    if (allocated(b%cell_centre)) then
      o = b%cell_centre(1:2, i)
    else
      o = b%x(1:2, i)
    end if
  end function cell_centre_of

  !> Can a particle of the region reg (lower, upper corner; closed) touch a point within
  !! [lo, hi]? It can when the region reaches within grow (the largest support) of it.
  pure logical function near_region(lo, hi, grow, reg)
    real(wp), intent(in) :: lo(2), hi(2), grow(2), reg(2, 2)
    near_region = all(hi + grow >= reg(:, 1)) .and. all(lo - grow <= reg(:, 2))
  end function near_region

  !> The bounding box [lo, hi] of particle i's cell (every piece's vertices) and of the
  !! particle itself: every point SCNI integrates for it lies within.
  pure subroutine cell_extent(b, i, lo, hi)
    type(body_t), intent(in) :: b
    integer, intent(in) :: i
    real(wp), intent(out) :: lo(2), hi(2)
    real(wp) :: cv(2, max_cv)
    integer :: piece, ncv
    lo = b%x(1:2, i)
    hi = lo
    do piece = 0, cell_pieces(b, i)
      call particle_cell(b, i, piece, cv, ncv)
      if (ncv < 1) cycle
      lo = min(lo, minval(cv(:, 1:ncv), dim=2))
      hi = max(hi, maxval(cv(:, 1:ncv), dim=2))
    end do
  end subroutine cell_extent

  !> Positions in the list of kept points (kpos(q), 0 if not kept) and their number.
  pure subroutine kept_list(keep, kpos, nk)
    logical, intent(in) :: keep(:)
    integer, intent(out) :: kpos(:), nk
    integer :: q
    nk = 0
    do q = 1, size(keep)
      kpos(q) = 0
      if (.not. keep(q)) cycle
      nk = nk + 1
      kpos(q) = nk
    end do
  end subroutine kept_list

  !> Area quadrature of a cell: fan triangles from the vertex mean, 3 points each (exact for
  !! quadratics; signed areas keep it exact for any simple polygon).
  pure subroutine cell_area_points(cv, ncv, xg, wg, ng)
    real(wp), intent(in) :: cv(:, :)
    integer, intent(in) :: ncv
    real(wp), intent(out) :: xg(:, :), wg(:)
    integer, intent(out) :: ng
    real(wp) :: o(2), a(2), bb(2), area
    integer :: k
    real(wp), parameter :: bary(3, 3) = reshape([2.0_wp/3.0_wp, 1.0_wp/6.0_wp, &
      1.0_wp/6.0_wp, 1.0_wp/6.0_wp, 2.0_wp/3.0_wp, 1.0_wp/6.0_wp, 1.0_wp/6.0_wp, &
      1.0_wp/6.0_wp, 2.0_wp/3.0_wp], [3, 3])
    integer :: q
    o = sum(cv(:, 1:ncv), dim=2)/real(ncv, wp)
    ng = 0
    do k = 1, ncv
      a = cv(:, k)
      bb = cv(:, modulo(k, ncv) + 1)
      area = 0.5_wp*((a(1) - o(1))*(bb(2) - o(2)) - (bb(1) - o(1))*(a(2) - o(2)))
      if (area == 0.0_wp) cycle
      do q = 1, 3
        ng = ng + 1
        xg(:, ng) = bary(1, q)*o + bary(2, q)*a + bary(3, q)*bb
        wg(ng) = area/3.0_wp
      end do
    end do
  end subroutine cell_area_points

  !> Shape functions at p folded onto real particles: n1/n2 (components), dn1/dn2. Cloud
  !! particle k is particle twin(k), or the mirror image of particle -twin(k) across the
  !! axis when twin(k) < 0 (it carries (-u_r, u_z) of its twin).
  subroutine folded_shape(c, twin, p, nf, fid, fn, fdn, ok)
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: twin(:)
    real(wp), intent(in) :: p(2)
    integer, intent(out) :: nf
    integer, intent(out) :: fid(:)
    real(wp), intent(out) :: fn(:, :)
    !> the derivatives, when present (else only the values: cloud_shape_values apart, the
    !! same values to the bit at a quarter of the work)
    real(wp), intent(out), optional :: fdn(:, :, :)
    logical, intent(out) :: ok
    integer :: ids(max_nb), nnb, k, j, m
    real(wp) :: n(max_nb), dn(2, max_nb), s
    if (present(fdn)) then
      call cloud_shape(c, p, nnb, ids, n, dn, ok)
    else
      call cloud_shape_values(c, p, nnb, ids, n, ok, apart=.true.)
    end if
    nf = 0
    if (.not. ok) return
    do k = 1, nnb
      j = abs(twin(ids(k)))
      s = 1.0_wp
      if (twin(ids(k)) < 0) s = -1.0_wp
      m = 0
      if (twin(ids(k)) < 0) then
        do m = nf, 1, -1
          if (fid(m) == j) exit
        end do
      end if
      if (m == 0) then
        nf = nf + 1
        m = nf
        fid(m) = j
        fn(:, m) = 0.0_wp
        if (present(fdn)) fdn(:, :, m) = 0.0_wp
      end if
      fn(1, m) = fn(1, m) + s*n(k)
      fn(2, m) = fn(2, m) + n(k)
      if (.not. present(fdn)) cycle
      fdn(:, 1, m) = fdn(:, 1, m) + s*dn(:, k)
      fdn(:, 2, m) = fdn(:, 2, m) + dn(:, k)
    end do
  end subroutine folded_shape

  subroutine build_scni(b, c, twin, np, rho0, reg, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: twin(:), np
    real(wp), intent(in) :: rho0, reg(2, 2)
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: gl(:, :, :), hl(:, :), ml(:, :), sub(:, :, :), wsub(:, :)
    integer, allocatable :: idl(:, :), nl(:), slot(:), kpos(:)
    logical, allocatable :: keep(:)
    real(wp) :: cv(2, max_cv), xg(2, 3*max_cv), wg(3*max_cv), p(2), nrm(2), e(2), len_e
    real(wp) :: vol_l, fn(2, max_nb), rw, gw, hv(2), vh(2), big
    real(wp) :: hc(2, max_cv), o(2), hpiece, lo(2), hi(2)
    integer :: maxk, i, ncv, ngp, k, q, nf, fid(max_nb), s, bad, j, nhc, dir, piece, nk, kk
    logical :: ok
    real(wp), parameter :: gx(2) = [0.5_wp - 0.5_wp/sqrt(3.0_wp), 0.5_wp + 0.5_wp/sqrt(3.0_wp)]
    t%nq = np
    ! the cells kept (tl_build's region): their rows, in the padded arrays by kpos
    allocate(keep(np), kpos(np))
    do i = 1, np
      call cell_extent(b, i, lo, hi)
      keep(i) = near_region(lo, hi, c%rmax(1:2), reg)
    end do
    call kept_list(keep, kpos, nk)
    maxk = union_bound(b, c, keep)
    allocate(gl(4, maxk, max(nk, 1)), hl(maxk, max(nk, 1)), ml(maxk, max(nk, 1)), &
      idl(maxk, max(nk, 1)), nl(max(nk, 1)))
    allocate(sub(4, maxk, max(nk, 1)), wsub(2, np))
    allocate(t%xq(t%dims%ndim, np), t%owner(np), t%wgt(np))
    big = 1.0e3_wp*maxval(abs(b%x)) + 1.0_wp
    bad = 0
    !$omp parallel default(none) shared(b, c, twin, np, t, gl, hl, ml, idl, nl, maxk, rho0, &
    !$omp sub, wsub, big, kpos) &
    !$omp private(cv, ncv, xg, wg, ngp, k, q, p, nrm, e, len_e, vol_l, fn, nf, fid, &
    !$omp ok, s, slot, rw, gw, j, hc, nhc, dir, hv, vh, o, piece, hpiece, kk) &
    !$omp reduction(max: bad)
    allocate(slot(np))
    slot = 0
    !$omp do schedule(dynamic, 64)
    do i = 1, np
      kk = kpos(i)
      t%xq(:, i) = b%x(:, i)
      t%owner(i) = i
      if (kk == 0) then
        ! a cell not kept: its weight only (the same sums as a kept cell's)
        vol_l = 0.0_wp
        do piece = 0, cell_pieces(b, i)
          call particle_cell(b, i, piece, cv, ncv)
          call cell_area_points(cv, ncv, xg, wg, ngp)
          do q = 1, ngp
            rw = 1.0_wp
            if (t%axisym) rw = xg(1, q)
            vol_l = vol_l + wg(q)*rw
          end do
        end do
        wsub(:, i) = 0.0_wp
        t%wgt(i) = vol_l
        if (t%axisym) t%wgt(i) = 2.0_wp*pi*vol_l
        cycle
      end if
      nl(kk) = 0
      sub(:, :, kk) = 0.0_wp
      vol_l = 0.0_wp
      hv = 0.0_wp
      o = cell_centre_of(b, i)
      ! the cell is the union of its pieces: each piece's area and boundary integrals are
      ! added, the edges two pieces share cancelling (the same Gauss points, opposite normals)
      do piece = 0, cell_pieces(b, i)
        call particle_cell(b, i, piece, cv, ncv)
        call cell_area_points(cv, ncv, xg, wg, ngp)
        ! area integrals: V_L, int N dA (hoop) and int rho0 N r dA (mass)
        do q = 1, ngp
          rw = 1.0_wp
          if (t%axisym) rw = xg(1, q)
          vol_l = vol_l + wg(q)*rw
          call folded_shape(c, twin, xg(:, q), nf, fid, fn, ok=ok)
          if (.not. ok) then
            bad = max(bad, i)
            cycle
          end if
          do k = 1, nf
            call add_slot(fid(k), kk, slot, nl, idl, gl, hl, ml, s)
            ml(s, kk) = ml(s, kk) + wg(q)*rw*fn(2, k)
            hl(s, kk) = hl(s, kk) + wg(q)*fn(1, k)
            if (t%axisym) gl(1, s, kk) = gl(1, s, kk) - wg(q)*fn(1, k)
            if (t%axisym) gl(3, s, kk) = gl(3, s, kk) - wg(q)*fn(2, k)
          end do
        end do
        ! boundary integrals: two Gauss points per edge, outward normal of a CCW cell
        do k = 1, ncv
          e = cv(:, modulo(k, ncv) + 1) - cv(:, k)
          len_e = norm2(e)
          if (len_e == 0.0_wp) cycle
          nrm = [e(2), -e(1)]/len_e
          do q = 1, 2
            p = cv(:, k) + gx(q)*e
            rw = 1.0_wp
            if (t%axisym) rw = p(1)
            gw = 0.5_wp*len_e*rw
            call folded_shape(c, twin, p, nf, fid, fn, ok=ok)
            if (.not. ok) then
              bad = max(bad, i)
              cycle
            end if
            do j = 1, nf
              call add_slot(fid(j), kk, slot, nl, idl, gl, hl, ml, s)
              gl(1:2, s, kk) = gl(1:2, s, kk) + gw*fn(1, j)*nrm
              gl(3:4, s, kk) = gl(3:4, s, kk) + gw*fn(2, j)*nrm
            end do
          end do
        end do
        ! the parts of the piece right of and above the cell centre (stabilization): the
        ! same smoothing on each, for d/dX1 (right half) and d/dX2 (upper half)
        do dir = 1, 2
          if (dir == 1) then
            call clip_polygon_box(cv(:, 1:ncv), [o(1), -big], [big, big], hc, nhc)
          else
            call clip_polygon_box(cv(:, 1:ncv), [-big, o(2)], [big, big], hc, nhc)
          end if
          if (nhc < 3) cycle
          call half_cell(c, twin, t%axisym, hc, nhc, dir, kk, slot, nl, idl, gl, hl, ml, &
            sub, hpiece, ok)
          if (.not. ok) bad = max(bad, i)
          hv(dir) = hv(dir) + hpiece
        end do
      end do
      gl(:, 1:nl(kk), kk) = gl(:, 1:nl(kk), kk)/vol_l
      ! sub-cell minus cell gradients and the weights W_h (1 + W_h/(W - W_h)); a half that
      ! is (nearly) empty, as for particles on the boundary, gets no stabilization
      do dir = 1, 2
        vh(dir) = vol_l - hv(dir)
        if (hv(dir) > empty_half*vol_l .and. vh(dir) > empty_half*vol_l) then
          sub(2*dir - 1:2*dir, 1:nl(kk), kk) = sub(2*dir - 1:2*dir, 1:nl(kk), kk)/hv(dir)
          sub(2*dir - 1, 1:nl(kk), kk) = sub(2*dir - 1, 1:nl(kk), kk) - gl(dir, 1:nl(kk), kk)
          sub(2*dir, 1:nl(kk), kk) = sub(2*dir, 1:nl(kk), kk) - gl(dir + 2, 1:nl(kk), kk)
          wsub(dir, i) = hv(dir)*(1.0_wp + hv(dir)/vh(dir))
        else
          sub(2*dir - 1:2*dir, 1:nl(kk), kk) = 0.0_wp
          wsub(dir, i) = 0.0_wp
        end if
      end do
      if (t%axisym) wsub(:, i) = 2.0_wp*pi*wsub(:, i)
      if (t%axisym) then
        hl(1:nl(kk), kk) = hl(1:nl(kk), kk)/vol_l
        t%wgt(i) = 2.0_wp*pi*vol_l
        ml(1:nl(kk), kk) = 2.0_wp*pi*rho0*ml(1:nl(kk), kk)
      else
        hl(1:nl(kk), kk) = 0.0_wp
        t%wgt(i) = vol_l
        ml(1:nl(kk), kk) = rho0*ml(1:nl(kk), kk)
      end if
      do k = 1, nl(kk)
        slot(idl(k, kk)) = 0
      end do
    end do
    !$omp end do
    deallocate(slot)
    !$omp end parallel
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined in the "// &
        "cell of particle "//itoa(bad)//": "//shape_failure(c, cell_centre_of(b, bad), &
        0.5_wp*b%spacing(1:2)))
      return
    end if
    call compress(t, gl, hl, ml, idl, nl, kpos, sub, wsub)
  end subroutine build_scni

  !> Smoothed derivative along dir of N^1 and N^2 over a half cell hc (r-weighted in
  !! axisymmetry, as the whole cell's), unnormalised, into sub(2 dir - 1 : 2 dir, :, i);
  !! hv returns its (r-weighted) area.
  subroutine half_cell(c, twin, axisym, hc, nhc, dir, i, slot, nl, idl, gl, hl, ml, sub, &
    hv, ok)
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: twin(:), nhc, dir, i
    logical, intent(in) :: axisym
    real(wp), intent(in) :: hc(:, :)
    integer, intent(inout) :: slot(:), nl(:), idl(:, :)
    real(wp), intent(inout) :: gl(:, :, :), hl(:, :), ml(:, :), sub(:, :, :)
    real(wp), intent(out) :: hv
    logical, intent(out) :: ok
    real(wp) :: xg(2, 3*max_cv), wg(3*max_cv), fn(2, max_nb), e(2), nrm(2)
    real(wp) :: p(2), len_e, rw, gw
    integer :: ngp, q, k, nf, fid(max_nb), s, j
    real(wp), parameter :: gx(2) = [0.5_wp - 0.5_wp/sqrt(3.0_wp), 0.5_wp + 0.5_wp/sqrt(3.0_wp)]
    ok = .true.
    hv = 0.0_wp
    call cell_area_points(hc, nhc, xg, wg, ngp)
    do q = 1, ngp
      rw = 1.0_wp
      if (axisym) rw = xg(1, q)
      hv = hv + wg(q)*rw
      if (.not. (axisym .and. dir == 1)) cycle
      call folded_shape(c, twin, xg(:, q), nf, fid, fn, ok=ok)
      if (.not. ok) return
      do k = 1, nf
        call add_slot(fid(k), i, slot, nl, idl, gl, hl, ml, s)
        sub(1:2, s, i) = sub(1:2, s, i) - wg(q)*fn(:, k)
      end do
    end do
    do k = 1, nhc
      e = hc(:, modulo(k, nhc) + 1) - hc(:, k)
      len_e = norm2(e)
      if (len_e == 0.0_wp) cycle
      nrm = [e(2), -e(1)]/len_e
      if (nrm(dir) == 0.0_wp) cycle
      do q = 1, 2
        p = hc(:, k) + gx(q)*e
        rw = 1.0_wp
        if (axisym) rw = p(1)
        gw = 0.5_wp*len_e*rw*nrm(dir)
        call folded_shape(c, twin, p, nf, fid, fn, ok=ok)
        if (.not. ok) return
        do j = 1, nf
          call add_slot(fid(j), i, slot, nl, idl, gl, hl, ml, s)
          sub(2*dir - 1:2*dir, s, i) = sub(2*dir - 1:2*dir, s, i) + gw*fn(:, j)
        end do
      end do
    end do
  end subroutine half_cell

  !> Local slot s of particle j in the accumulation arrays of point i (new slots zeroed).
  !! slot(:) maps particles to slots and must be reset by the caller after point i.
  pure subroutine add_slot(j, i, slot, nl, idl, gl, hl, ml, s)
    integer, intent(in) :: j, i
    integer, intent(inout) :: slot(:), nl(:), idl(:, :)
    real(wp), intent(inout) :: gl(:, :, :), hl(:, :), ml(:, :)
    integer, intent(out) :: s
    s = slot(j)
    if (s == 0) then
      nl(i) = nl(i) + 1
      s = nl(i)
      slot(j) = s
      idl(s, i) = j
      gl(:, s, i) = 0.0_wp
      hl(s, i) = 0.0_wp
      ml(s, i) = 0.0_wp
    end if
  end subroutine add_slot

  !> Upper bound of the particles touching one cell (the box around its pieces grown by the
  !! largest support); of the cells keep(:) holds when present.
  function union_bound(b, c, keep) result(maxk)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    logical, intent(in), optional :: keep(:)
    integer :: maxk
    integer, allocatable :: cand(:)
    integer :: i, n, k
    real(wp) :: lo(2), hi(2), m(2)
    allocate(cand(c%np))
    maxk = 1
    do i = 1, b%np
      if (present(keep)) then
        if (.not. keep(i)) cycle
      end if
      lo = cell_centre_of(b, i)
      hi = lo
      do k = 1, cell_pieces(b, i)
        m = b%merged_centre(:, b%merged_ptr(i) + k - 1)
        lo = min(lo, m)
        hi = max(hi, m)
      end do
      call bins_candidates(c%bins, 0.5_wp*(lo + hi), c%rmax(1:2) + 0.5_wp*b%spacing(1:2) &
        + 0.5_wp*(hi - lo), cand, n)
      maxk = max(maxk, n)
    end do
  end function union_bound

  subroutine build_gauss(b, c, twin, np, rho0, reg, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: twin(:), np
    real(wp), intent(in) :: rho0, reg(2, 2)
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: xq(:, :), wq(:), gl(:, :, :), hl(:, :), ml(:, :)
    integer, allocatable :: owner(:), idl(:, :), nl(:), kpos(:)
    logical, allocatable :: keep(:)
    real(wp) :: cv(2, max_cv), xg(2, 3*max_cv), wg(3*max_cv), fn(2, max_nb), fdn(2, 2, max_nb)
    real(wp) :: rw
    integer :: i, ncv, ngp, q, nq, k, nf, fid(max_nb), maxk, bad, piece, nk, kk
    logical :: ok
    ! count the points first
    nq = 0
    do i = 1, np
      do piece = 0, cell_pieces(b, i)
        call particle_cell(b, i, piece, cv, ncv)
        call cell_area_points(cv, ncv, xg, wg, ngp)
        nq = nq + ngp
      end do
    end do
    allocate(xq(2, nq), wq(nq), owner(nq))
    nq = 0
    do i = 1, np
      do piece = 0, cell_pieces(b, i)
        call particle_cell(b, i, piece, cv, ncv)
        call cell_area_points(cv, ncv, xg, wg, ngp)
        xq(:, nq + 1:nq + ngp) = xg(:, 1:ngp)
        wq(nq + 1:nq + ngp) = wg(1:ngp)
        owner(nq + 1:nq + ngp) = i
        nq = nq + ngp
      end do
    end do
    ! the points kept (tl_build's region): their rows, in the padded arrays by kpos
    allocate(keep(nq), kpos(nq))
    do q = 1, nq
      keep(q) = near_region(xq(:, q), xq(:, q), c%rmax(1:2), reg)
    end do
    call kept_list(keep, kpos, nk)
    maxk = union_bound(b, c)
    allocate(gl(4, maxk, max(nk, 1)), hl(maxk, max(nk, 1)), ml(maxk, max(nk, 1)), &
      idl(maxk, max(nk, 1)), nl(max(nk, 1)))
    t%nq = nq
    t%xq = xq
    t%owner = owner
    allocate(t%wgt(nq))
    do q = 1, nq
      rw = 1.0_wp
      if (t%axisym) rw = 2.0_wp*pi*xq(1, q)
      t%wgt(q) = wq(q)*rw
    end do
    bad = 0
    !$omp parallel do default(none) shared(c, twin, np, t, xq, gl, hl, ml, idl, nl, rho0, &
    !$omp nq, kpos) private(fn, fdn, nf, fid, ok, k, kk) reduction(max: bad) &
    !$omp schedule(dynamic, 64)
    do q = 1, nq
      kk = kpos(q)
      if (kk == 0) cycle
      call folded_shape(c, twin, xq(:, q), nf, fid, fn, fdn, ok)
      nl(kk) = 0
      if (.not. ok) then
        bad = max(bad, q)
        cycle
      end if
      nl(kk) = nf
      do k = 1, nf
        idl(k, kk) = fid(k)
        gl(1:2, k, kk) = fdn(:, 1, k)
        gl(3:4, k, kk) = fdn(:, 2, k)
        hl(k, kk) = 0.0_wp
        if (t%axisym) hl(k, kk) = fn(1, k)/xq(1, q)
        ml(k, kk) = rho0*t%wgt(q)*fn(2, k)
      end do
    end do
    !$omp end parallel do
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined at Gauss "// &
        "point "//itoa(bad)//": "//shape_failure(c, xq(:, bad), [0.0_wp, 0.0_wp]))
      return
    end if
    call compress(t, gl, hl, ml, idl, nl, kpos)
  end subroutine build_gauss

  subroutine build_direct(b, c, twin, np, rho0, reg, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: twin(:), np
    real(wp), intent(in) :: rho0, reg(2, 2)
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: gl(:, :, :), hl(:, :), ml(:, :)
    integer, allocatable :: idl(:, :), nl(:), kpos(:)
    logical, allocatable :: keep(:)
    real(wp) :: fn(2, max_nb), fdn(2, 2, max_nb)
    integer :: i, k, nf, fid(max_nb), maxk, bad, nk, kk
    logical :: ok
    ! the points kept (tl_build's region): their rows, in the padded arrays by kpos
    allocate(keep(np), kpos(np))
    do i = 1, np
      keep(i) = near_region(b%x(:, i), b%x(:, i), c%rmax(1:2), reg)
    end do
    call kept_list(keep, kpos, nk)
    maxk = union_bound(b, c)
    t%nq = np
    allocate(gl(4, maxk, max(nk, 1)), hl(maxk, max(nk, 1)), ml(maxk, max(nk, 1)), &
      idl(maxk, max(nk, 1)), nl(max(nk, 1)))
    t%xq = b%x
    t%owner = [(i, i = 1, np)]
    t%wgt = b%vol
    bad = 0
    do i = 1, np
      kk = kpos(i)
      if (kk == 0) cycle
      call folded_shape(c, twin, b%x(:, i), nf, fid, fn, fdn, ok)
      nl(kk) = 0
      if (.not. ok) then
        bad = i
        cycle
      end if
      nl(kk) = nf
      do k = 1, nf
        idl(k, kk) = fid(k)
        gl(1:2, k, kk) = fdn(:, 1, k)
        gl(3:4, k, kk) = fdn(:, 2, k)
        hl(k, kk) = 0.0_wp
        ml(k, kk) = rho0*b%vol(i)*fn(2, k)
      end do
    end do
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined at "// &
        "particle "//itoa(bad)//": "//shape_failure(c, b%x(:, bad), [0.0_wp, 0.0_wp]))
      return
    end if
    call compress(t, gl, hl, ml, idl, nl, kpos)
  end subroutine build_direct

  !> Why the shape functions are undefined at p or within half(1:2) of it (a cell), and
  !! the fix: more particles cover a point than the max_nb one point of the tables holds,
  !! fewer than the basis needs, or enough in a degenerate layout (M singular all the same).
  function shape_failure(c, p, half) result(why)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(2), half(2)
    character(len=:), allocatable :: why
    integer :: ncover, nmin, nmax, i, j
    nmin = huge(1)
    nmax = 0
    do j = -1, 1
      do i = -1, 1
        ncover = cloud_count_cover(c, p + [i, j]*half)
        nmin = min(nmin, ncover)
        nmax = max(nmax, ncover)
      end do
    end do
    if (nmax > max_nb) then
      why = 'covered by up to '//itoa(nmax)//' particles, more than the '//itoa(max_nb)// &
        ' one point of the tables holds; decrease support_factor'
    else if (nmin < c%m) then
      why = 'covered by only '//itoa(nmin)//' particle(s), and the basis needs at least '// &
        itoa(c%m)//'; increase support_factor'
    else
      why = 'moment matrix singular although '//itoa(nmin)//' particles cover it '// &
        '(a degenerate layout, e.g. all on one line); check the particle positions'
    end if
  end function shape_failure

  !> Dense per-point work arrays into CSR; masses summed per particle. The work arrays
  !! hold the kept points only: point q's in slot kpos(q) (nl its count), none if 0.
  subroutine compress(t, gl, hl, ml, idl, nl, kpos, sub, wsub)
    type(solid_tables_t), intent(inout) :: t
    real(wp), intent(in) :: gl(:, :, :), hl(:, :), ml(:, :)
    integer, intent(in) :: idl(:, :), nl(:), kpos(:)
    real(wp), intent(in), optional :: sub(:, :, :), wsub(:, :)
    integer :: q, k, e, nnz, kk, n
    nnz = 0
    do q = 1, t%nq
      if (kpos(q) > 0) nnz = nnz + nl(kpos(q))
    end do
    allocate(t%ptr(t%nq + 1), t%nbr(nnz), t%g(t%dims%ngrad, nnz), t%h(nnz), t%mass(t%np))
    allocate(t%gs(t%dims%ngrad, nnz), t%ws(t%dims%ndim, t%nq))
    t%gs = 0.0_wp
    t%ws = 0.0_wp
    if (present(wsub)) t%ws = wsub
    t%mass = 0.0_wp
    t%ptr(1) = 1
    do q = 1, t%nq
      kk = kpos(q)
      n = 0
      if (kk > 0) n = nl(kk)
      t%ptr(q + 1) = t%ptr(q) + n
      do k = 1, n
        e = t%ptr(q) + k - 1
        t%nbr(e) = idl(k, kk)
        t%g(:, e) = gl(:, k, kk)
        t%h(e) = hl(k, kk)
        if (present(sub)) t%gs(:, e) = sub(:, k, kk)
        t%mass(idl(k, kk)) = t%mass(idl(k, kk)) + ml(k, kk)
      end do
    end do
  end subroutine compress

  !> N^c_I(X_J) for the physical positions x_J = X_J + sum_I N^c_I(X_J) d_cI; the rows of
  !! the particles within the largest support and cell extent ext of the region reg only
  !! (tl_build's box): every node of a row of a point in reg (decomposition_m
  !! local_part_build takes the position rows of those).
  subroutine build_positions(b, c, twin, np, reg, ext, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: twin(:), np
    real(wp), intent(in) :: reg(2, 2), ext(2)
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: cnt(:), idl(:, :), kpos(:)
    logical, allocatable :: keep(:)
    real(wp), allocatable :: nl(:, :, :)
    real(wp) :: fn(2, max_nb)
    integer :: j, nf, fid(max_nb), maxk, bad, k, e, nk, kk
    logical :: ok
    allocate(keep(np), kpos(np))
    do j = 1, np
      keep(j) = near_region(b%x(:, j), b%x(:, j), c%rmax(1:2) + ext, reg)
    end do
    call kept_list(keep, kpos, nk)
    maxk = union_bound(b, c)
    allocate(cnt(np), idl(maxk, max(nk, 1)), nl(2, maxk, max(nk, 1)))
    bad = 0
    !$omp parallel do default(none) shared(b, c, twin, np, cnt, idl, nl, kpos) &
    !$omp private(fn, nf, fid, ok, kk) reduction(max: bad) schedule(dynamic, 64)
    do j = 1, np
      kk = kpos(j)
      cnt(j) = 0
      if (kk == 0) cycle
      call folded_shape(c, twin, b%x(:, j), nf, fid, fn, ok=ok)
      cnt(j) = nf
      if (.not. ok) bad = max(bad, j)
      idl(1:nf, kk) = fid(1:nf)
      nl(:, 1:nf, kk) = fn(:, 1:nf)
    end do
    !$omp end parallel do
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined at "// &
        "particle "//itoa(bad)//": "//shape_failure(c, b%x(:, bad), [0.0_wp, 0.0_wp]))
      return
    end if
    allocate(t%pptr(np + 1), t%pnbr(sum(cnt)), t%pn(t%dims%ndim, sum(cnt)))
    t%pptr(1) = 1
    do j = 1, np
      t%pptr(j + 1) = t%pptr(j) + cnt(j)
      do k = 1, cnt(j)
        e = t%pptr(j) + k - 1
        t%pnbr(e) = idl(k, kpos(j))
        t%pn(:, e) = nl(:, k, kpos(j))
      end do
    end do
  end subroutine build_positions

end module rkpm_tl_m
