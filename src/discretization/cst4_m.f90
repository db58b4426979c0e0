!> CST4 finite elements (Section 6, second half): rectangular boxes split by their diagonals
!! into four constant-strain triangles around a centre node, the mesh the paper uses as the
!! finite-element counterpart of its RKPM Taylor bar (30 x 360 boxes: 43,200 triangles,
!! 21,991 nodes). This module builds the mesh and fills the discretization-neutral tables of
!! solid_tables_m, so the total-Lagrangian kernels of tl_kinematics_m (F, D, P, the internal
!! force of eq. 72) run on elements exactly as on RKPM particles:
!!  - one integration point per triangle, at its centroid, weight W = A (plane strain, per
!!    unit thickness) or 2 pi r_c A (axisymmetric: the one-point rule for int r dA, exact
!!    for the linear r);
!!  - nodal interpolation: the three linear shape functions of each triangle, with constant
!!    gradients; the hoop term of u_r/r is taken at the centroid, N_I(c)/r_c = 1/(3 r_c), as
!!    the RKPM tables take it at the cell;
!!  - lumped mass by the row sum of the consistent mass (eq. 70).
!! The nodes live in a body_t, so contact and output see them as they see particles: first
!! the box corners in make_rectangle's order (its boundary flags and counter-clockwise
!! polyline), then the box centres.
module cst4_m
  use kinds_m, only: wp, pi
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use body_m, only: body_t, body_keep_used, lattice_t
  use generators_m, only: make_rectangle, make_annulus, set_supports, lattice_pick, polar_boxes, &
    lattice_corners
  use rank_comm_m, only: share_first
  use sorting_m, only: sorted_place
  use geometry_m, only: full_turn_tol, twice_area
  use dims_m, only: dims_plane
  use solid_tables_m, only: solid_tables_t, tables_finish_elements, element_rows
  use mesh_cells_m, only: check_cells
  implicit none
  private
  public :: cst4_mesh_t, cst4_rectangle, cst4_annulus, cst4_tables, cst4_region

  !> Relative tolerance (of the nominal spacing) for "the node lies on the axis r = 0" and
  !! for checking make_rectangle's lattice: far above round-off of X, far below a box.
  real(wp), parameter :: geom_tol = 1.0e-9_wp

  !> Triangles over the nodes of a body_t.
  type :: cst4_mesh_t
    integer :: ne = 0                  !< triangles
    integer :: nbox(2) = 0             !< boxes per direction (structured meshes)
    integer, allocatable :: tri(:, :)  !< (3, ne) node numbers, counter-clockwise
    integer :: ncorner = 0             !< box-corner nodes (numbered first)
  end type cst4_mesh_t

contains

  !> nbox(1) x nbox(2) boxes on [lo, hi] (m), each cut by its diagonals into four triangles
  !! around a centre node. Nodes: the (nbox(1)+1) x (nbox(2)+1) corners as make_rectangle
  !! orders them (x fastest; its boundary flags, loop and geometry), then the box centres
  !! (x fastest, interior). b%vol is the lumped nodal area (1/3 of each touching triangle,
  !! m^2); b%spacing(1:2) the box size (m); supports rho = support_factor(1:2) x box size,
  !! the dilation parameters taken from the element sizes ("one can construct the moment
  !! matrix upon the finite element mesh"). Triangles: four per box in box order (x fastest),
  !! bottom, right, top, left.
  subroutine cst4_rectangle(lo, hi, nbox, support_factor, b, mesh, err, share)
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: nbox(2)
    real(wp), intent(in) :: support_factor(:)
    type(body_t), intent(out) :: b
    type(cst4_mesh_t), intent(out) :: mesh
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: only rank me's share of the nodes (generators_m make_rectangle's, from
    !! the lattice's recipe b%lat, lattice_node) and of the triangles (mesh%tri: elements
    !! b%cell0 ... of b%ncells), the whole body never made
    integer, intent(in), optional :: share(2)
    real(wp), allocatable :: x(:, :)
    logical, allocatable :: bnd(:)
    real(wp) :: dx(2), tol, a3
    integer :: nc, ncen, np, ib, jb, c(4), k, e, box
    if (any(nbox < 1)) then
      call set_error(err, 'CST4 rectangle: nbox = ('//itoa(nbox(1))//', '//itoa(nbox(2))// &
        '): need at least one box in each direction')
      return
    end if
    if (any(hi <= lo)) then
      call set_error(err, 'CST4 rectangle: hi = ('//rtoa(hi(1))//', '//rtoa(hi(2))// &
        ') must exceed lo = ('//rtoa(lo(1))//', '//rtoa(lo(2))//') in each direction')
      return
    end if
    if (size(support_factor) < 2) then
      call set_error(err, 'CST4 rectangle: support_factor needs two entries (x, y), got '// &
        itoa(size(support_factor)))
      return
    end if
    if (any(support_factor(1:2) <= 0.0_wp)) then
      call set_error(err, 'CST4 rectangle: support_factor = ('//rtoa(support_factor(1))// &
        ', '//rtoa(support_factor(2))//') must be positive')
      return
    end if
    if (present(share)) then
      call make_rectangle(b, lo, hi, nbox + 1, err, share, cst4=.true.)
      if (allocated(err)) return
      nc = (nbox(1) + 1)*(nbox(2) + 1)
      mesh%nbox = nbox
      mesh%ncorner = nc
      b%ncells = 4*nbox(1)*nbox(2)
      b%cell0 = share_first(b%ncells, share(1), share(2))
      mesh%ne = share_first(b%ncells, share(1) + 1, share(2)) - b%cell0
      allocate(mesh%tri(3, mesh%ne))
      do e = 1, mesh%ne
        mesh%tri(:, e) = rectangle_triangle(nbox, b%cell0 + e - 1)
      end do
      call set_supports(b, support_factor(1:2))
      b%lat%rho = support_factor(1:2)*b%spacing(1:2)
      return
    end if
    call make_rectangle(b, lo, hi, nbox + 1, err)
    if (allocated(err)) return
    b%lat%cst4 = .true.
    nc = (nbox(1) + 1)*(nbox(2) + 1)
    ncen = nbox(1)*nbox(2)
    np = nc + ncen
    dx = b%spacing(1:2)
    ! the corner numbering below assumes make_rectangle's lattice order (x fastest)
    tol = geom_tol*minval(dx)
    if (b%np /= nc) then
      call set_error(err, 'CST4 rectangle: make_rectangle gave '//itoa(b%np)// &
        ' lattice points, expected '//itoa(nc)//' (internal error)', 1)
      return
    end if
    do jb = 1, nbox(2) + 1
      do ib = 1, nbox(1) + 1
        k = corner(ib, jb)
        if (any(abs(b%x(:, k) - (lo + [real(ib - 1, wp), real(jb - 1, wp)]*dx)) > tol)) then
          call set_error(err, 'CST4 rectangle: make_rectangle point '//itoa(k)// &
            ' is not box corner ('//itoa(ib)//', '//itoa(jb)//') (internal error)', 1)
          return
        end if
      end do
    end do
    mesh%nbox = nbox
    mesh%ncorner = nc
    mesh%ne = 4*ncen
    allocate(x(2, np), bnd(np), mesh%tri(3, mesh%ne))
    x(:, 1:nc) = b%x
    bnd(1:nc) = b%boundary
    bnd(nc + 1:np) = .false.
    do jb = 1, nbox(2)
      do ib = 1, nbox(1)
        box = ib + (jb - 1)*nbox(1)
        c = [corner(ib, jb), corner(ib + 1, jb), corner(ib + 1, jb + 1), corner(ib, jb + 1)]
        ! the diagonals of a rectangle cross at the mean of its corners
        call split_box(c, nc + box, 4*(box - 1), x, mesh%tri)
      end do
    end do
    call move_alloc(x, b%x)
    call move_alloc(bnd, b%boundary)
    b%np = np
    ! lumped nodal area: each triangle (a quarter box) gives a third of itself to each node
    deallocate(b%vol)
    allocate(b%vol(np))
    b%vol = 0.0_wp
    a3 = 0.25_wp*dx(1)*dx(2)/3.0_wp
    do e = 1, mesh%ne
      b%vol(mesh%tri(:, e)) = b%vol(mesh%tri(:, e)) + a3
    end do
    call set_supports(b, support_factor(1:2))
    b%lat%rho = support_factor(1:2)*b%spacing(1:2)
  contains
    pure integer function corner(i, j)
      integer, intent(in) :: i, j
      corner = i + (j - 1)*(nbox(1) + 1)
    end function corner
  end subroutine cst4_rectangle

  !> Triangle e of the CST4 rectangle of nbox boxes (cst4_rectangle's numbering: four a
  !! box in box order, split_box's; nodes the corners, then the centres).
  pure function rectangle_triangle(nbox, e) result(tri)
    integer, intent(in) :: nbox(2), e
    integer :: tri(3)
    integer :: box, k, ib, jb, c(4), n1
    box = (e - 1)/4 + 1
    k = mod(e - 1, 4) + 1
    n1 = nbox(1) + 1
    ib = mod(box - 1, nbox(1)) + 1
    jb = (box - 1)/nbox(1) + 1
    c = [ib + (jb - 1)*n1, ib + 1 + (jb - 1)*n1, ib + 1 + jb*n1, ib + jb*n1]
    tri = [c(k), c(mod(k, 4) + 1), n1*(nbox(2) + 1) + box]
  end function rectangle_triangle

  !> Triangle e of the CST4 body of recipe lat (a rectangle's, rectangle_triangle; an
  !! annulus's, cst4_annulus's numbering: four a polar box in box order, the radius
  !! fastest, split_box's, its corners (ib, jb), (ib + 1, jb), (ib + 1, jb + 1),
  !! (ib, jb + 1), the last row of a ring's boxes closing onto the first corners).
  pure function box_triangle(lat, e) result(tri)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: e
    integer :: tri(3)
    integer :: box, k, ib, jb, c(4), nr, nt
    if (.not. lat%polar) then
      tri = rectangle_triangle(lat%n - 1, e)
      return
    end if
    nr = lat%n(1)
    nt = lat%n(2)
    box = (e - 1)/4 + 1
    k = mod(e - 1, 4) + 1
    ib = mod(box - 1, nr - 1) + 1
    jb = (box - 1)/(nr - 1) + 1
    c = [corner(ib, jb), corner(ib + 1, jb), corner(ib + 1, jb + 1), corner(ib, jb + 1)]
    tri = [c(k), c(mod(k, 4) + 1), nr*nt + box]
  contains
    pure integer function corner(i, j)
      integer, intent(in) :: i, j
      corner = i + (modulo(j - 1, nt))*nr
    end function corner
  end function box_triangle

  !> What a rank makes of the CST4 rectangle or annulus b (its recipe b%lat: the whole body
  !! is never made) for its box (3, 2) of the decomposition: the triangles all of whose
  !! nodes lie within 2 l + s of the box (l the longest edge, a box's side or an annulus's
  !! outer arc's chord, s the spacing, for the rounding), as mesh over the nodes of body r
  !! (generators_m lattice_pick's, cut to those the triangles use), with their numbers in
  !! the whole mesh, eglob (ascending; ne_whole of them). They hold every triangle
  !! cst4_tables keeps a row of for the box (its centroid or a vertex in it: every vertex
  !! within l of the box) and every triangle of each of those rows' nodes (within l of such
  !! a vertex), in the whole mesh's order: those nodes' masses are the same sums in the
  !! same order as the whole body's (as tet4_m tet4_region's tetrahedra).
  subroutine cst4_region(b, box, r, mesh, eglob, ne_whole)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: box(3, 2)
    type(body_t), intent(out) :: r
    type(cst4_mesh_t), intent(out) :: mesh
    integer, allocatable, intent(out) :: eglob(:)
    integer, intent(out) :: ne_whole
    type(body_t) :: near
    real(wp) :: grow, nowhere(1), l
    integer :: none(1), nc, n, pass, k, e, at(3), i, m
    logical, allocatable :: used(:)
    nc = lattice_corners(b%lat)
    mesh%nbox = [b%lat%n(1) - 1, polar_boxes(b%lat)]
    ne_whole = 4*mesh%nbox(1)*mesh%nbox(2)
    l = maxval(b%spacing(1:2))
    if (b%lat%polar) l = max(b%lat%dr, (b%lat%r0 + real(b%lat%n(1) - 1, wp)*b%lat%dr)* &
      b%lat%dt)
    grow = 3.0_wp*l
    none = 0
    nowhere = 0.0_wp
    call lattice_pick(b, 1, b%np, box(1:2, 1) - grow, box(1:2, 2) + grow, 0, none, nowhere, &
      near)
    ! (every triangle holds its box's centre: the near centres' boxes, in ascending order)
    allocate(used(near%np))
    used = .false.
    do pass = 1, 2
      n = 0
      do i = 1, near%np
        if (near%glob(i) <= nc) cycle
        do k = 1, 4
          e = 4*(near%glob(i) - nc - 1) + k
          at = box_triangle(b%lat, e)
          do m = 1, 3
            at(m) = sorted_place(near%glob, at(m))
          end do
          if (any(at == 0)) cycle
          n = n + 1
          if (pass == 1) cycle
          mesh%tri(:, n) = at
          eglob(n) = e
          used(at) = .true.
        end do
      end do
      if (pass == 1) allocate(mesh%tri(3, n), eglob(n))
    end do
    mesh%ne = n
    ! the nodes the triangles use, renumbered
    call body_keep_used(near, used, mesh%tri(:, 1:mesh%ne), r)
  end subroutine cst4_region

  !> CST4 elements on an annulus sector (a ring when theta1 - theta0 = 2 pi): the polar
  !! lattice of make_annulus (nr radii on [r0, r1], nt angles, radius fastest; its boundary
  !! flags and loops) gives (nr - 1) x (nt - 1) polar boxes, nt around a full ring (the
  !! last closes onto the first), each cut by its diagonals into four triangles around a
  !! centre node at the mean of its corners (nodes numbered after the corners, box order,
  !! radius fastest). b%vol is the lumped nodal area, a third of each touching triangle's
  !! area (m^2); supports are the caller's (make_annulus's local spacing).
  subroutine cst4_annulus(center, r0, r1, t0, t1, nr, nt, b, mesh, err, share)
    real(wp), intent(in) :: center(2), r0, r1, t0, t1
    integer, intent(in) :: nr, nt
    type(body_t), intent(out) :: b
    type(cst4_mesh_t), intent(out) :: mesh
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: only rank me's share of the nodes (generators_m make_annulus's, from
    !! the polar recipe b%lat, lattice_node) and of the triangles (mesh%tri: elements
    !! b%cell0 ... of b%ncells), the whole body never made
    integer, intent(in), optional :: share(2)
    real(wp), allocatable :: x(:, :)
    logical, allocatable :: bnd(:)
    real(wp) :: xt(2, 3), dn(2, 3), area, alt
    integer :: nc, nbt, ncen, np, ib, jb, c(4), e, box
    logical :: full
    if (present(share)) then
      call make_annulus(b, center, r0, r1, t0, t1, nr, nt, err, share)
      if (allocated(err)) return
      mesh%nbox = [nr - 1, polar_boxes(b%lat)]
      mesh%ncorner = nr*nt
      b%ncells = 4*mesh%nbox(1)*mesh%nbox(2)
      b%cell0 = share_first(b%ncells, share(1), share(2))
      mesh%ne = share_first(b%ncells, share(1) + 1, share(2)) - b%cell0
      allocate(mesh%tri(3, mesh%ne))
      do e = 1, mesh%ne
        mesh%tri(:, e) = box_triangle(b%lat, b%cell0 + e - 1)
      end do
      return
    end if
    call make_annulus(b, center, r0, r1, t0, t1, nr, nt, err)
    if (allocated(err)) return
    full = t1 - t0 >= 2.0_wp*pi - full_turn_tol
    nbt = merge(nt, nt - 1, full)
    nc = b%np
    ncen = (nr - 1)*nbt
    np = nc + ncen
    mesh%nbox = [nr - 1, nbt]
    mesh%ncorner = nc
    mesh%ne = 4*ncen
    allocate(x(2, np), bnd(np), mesh%tri(3, mesh%ne))
    x(:, 1:nc) = b%x
    bnd(1:nc) = b%boundary
    bnd(nc + 1:np) = .false.
    do jb = 1, nbt
      do ib = 1, nr - 1
        box = ib + (jb - 1)*(nr - 1)
        ! counter-clockwise: outwards along the radius, then on in the angle
        c = [corner(ib, jb), corner(ib + 1, jb), corner(ib + 1, jb + 1), corner(ib, jb + 1)]
        call split_box(c, nc + box, 4*(box - 1), x, mesh%tri)
      end do
    end do
    call move_alloc(x, b%x)
    call move_alloc(bnd, b%boundary)
    b%np = np
    deallocate(b%vol)
    allocate(b%vol(np))
    b%vol = 0.0_wp
    do e = 1, mesh%ne
      xt = b%x(:, mesh%tri(:, e))
      call triangle_gradients(xt, area, dn, alt)
      b%vol(mesh%tri(:, e)) = b%vol(mesh%tri(:, e)) + area/3.0_wp
    end do
  contains
    pure integer function corner(i, j)
      integer, intent(in) :: i, j
      corner = i + (modulo(j - 1, nt))*nr
    end function corner
  end subroutine cst4_annulus

  !> The box with corners c (counter-clockwise) cut by its diagonals: its centre node m at
  !! the mean of the corners, and triangles e+1..e+4 (bottom, right, top, left of a
  !! rectangle) around it.
  pure subroutine split_box(c, m, e, x, tri)
    integer, intent(in) :: c(4), m, e
    real(wp), intent(inout) :: x(:, :)
    integer, intent(inout) :: tri(:, :)
    x(:, m) = 0.25_wp*sum(x(:, c), dim=2)
    tri(:, e + 1) = [c(1), c(2), m]
    tri(:, e + 2) = [c(2), c(3), m]
    tri(:, e + 3) = [c(3), c(4), m]
    tri(:, e + 4) = [c(4), c(1), m]
  end subroutine split_box

  !> Tables of the total-Lagrangian solid on the triangles of mesh over the nodes of b:
  !! one point per triangle at its centroid; axisym selects r = X1, z = X2 (nodes must lie
  !! in r >= 0; nodes on the axis get fix1, u_r = 0). rho0: density (kg/m^3).
  !!
  !! box (3, 2), a rank's box of the decomposition (lower, upper corner; the first two
  !! rows used; doc/parallel.md): the rows (nodes, gradients, hoop terms) are kept only for
  !! the triangles whose centroid or a vertex lies in the box (closed), which holds every
  !! point the rank's part owns and every point touching a node it owns (decomposition_m
  !! local_part_build takes no other rows); the others' rows are empty, and the tables are
  !! not transposed (the split transposes the part's). Every triangle's area, centroid,
  !! weight and altitude are computed all the same (a few flops each), so the masses, the
  !! smallest altitude and the checks are the whole body's on every rank, with no sum
  !! over the ranks (as tet4_m tet4_tables' box).
  subroutine cst4_tables(b, mesh, axisym, rho0, t, err, box)
    type(body_t), intent(in) :: b
    type(cst4_mesh_t), intent(in) :: mesh
    logical, intent(in) :: axisym
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(out) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: box(3, 2)
    integer, allocatable :: touched(:)
    real(wp), allocatable :: areas(:)
    logical, allocatable :: keep(:)
    real(wp) :: tol, xt(2, 3), dn(2, 3), area, rc, alt, hmin, rsum
    integer :: np, ne, e, k, bad, i, nnz
    np = b%np
    ne = mesh%ne
    call check_cells(b%name, b%ndim, b%np, mesh%tri, mesh%ne, 3, 2, 'CST4', err)
    if (allocated(err)) return
    if (.not. (rho0 > 0.0_wp)) then
      call set_error(err, "body '"//trim(b%name)//"': CST4 density rho0 = "//rtoa(rho0)// &
        ' must be positive')
      return
    end if
    tol = geom_tol*nominal_spacing(b)
    if (axisym) then
      i = minloc(b%x(1, :), dim=1)
      if (b%x(1, i) < -tol) then
        call set_error(err, "body '"//trim(b%name)//"': axisymmetric CST4 node "//itoa(i)// &
          ' has r = x1 = '//rtoa(b%x(1, i))//' < 0: the mesh must lie in r >= 0 '// &
          '(x = r is the first coordinate)')
        return
      end if
    end if
    t%np = np
    t%nq = ne
    t%dims = dims_plane   ! these builders make the plane tables
    t%scheme = 0
    t%axisym = axisym
    t%interpolating = .true.
    allocate(t%xq(t%dims%ndim, ne), t%owner(ne), t%wgt(ne), areas(ne))
    t%owner = 0
    ! each triangle writes only its own entries: no races
    hmin = huge(1.0_wp)
    bad = huge(0)
    !$omp parallel do default(none) shared(b, mesh, t, ne, axisym, areas) &
    !$omp private(xt, dn, area, rc, alt) reduction(min: hmin, bad) schedule(static)
    do e = 1, ne
      xt = b%x(:, mesh%tri(:, e))
      call triangle_gradients(xt, area, dn, alt)
      rc = sum(xt(1, :))/3.0_wp
      t%xq(:, e) = sum(xt, dim=2)/3.0_wp
      if (.not. (area > 0.0_wp) .or. (axisym .and. .not. (rc > 0.0_wp))) then
        bad = min(bad, e)
        cycle
      end if
      hmin = min(hmin, alt)
      areas(e) = area
      if (axisym) then
        t%wgt(e) = 2.0_wp*pi*rc*area
      else
        t%wgt(e) = area
      end if
    end do
    !$omp end parallel do
    call element_rows(t, b%x, mesh%tri, keep, box)
    nnz = t%ptr(ne + 1) - 1
    allocate(t%nbr(nnz), t%g(t%dims%ngrad, nnz), t%h(nnz), t%gs(t%dims%ngrad, nnz), &
      t%ws(t%dims%ndim, ne))
    t%gs = 0.0_wp
    t%ws = 0.0_wp
    if (bad > ne) then
      !$omp parallel do default(none) shared(b, mesh, t, ne, axisym, keep) &
      !$omp private(xt, dn, area, rc, alt, k, i) schedule(static)
      do e = 1, ne
        if (.not. keep(e)) cycle
        xt = b%x(:, mesh%tri(:, e))
        call triangle_gradients(xt, area, dn, alt)
        rc = sum(xt(1, :))/3.0_wp
        do k = 1, 3
          i = t%ptr(e) + k - 1
          t%nbr(i) = mesh%tri(k, e)
          ! both displacement components interpolate with the same N_I
          t%g(:, i) = [dn(:, k), dn(:, k)]
          if (axisym) then
            t%h(i) = 1.0_wp/(3.0_wp*rc)
          else
            t%h(i) = 0.0_wp
          end if
        end do
      end do
      !$omp end parallel do
    end if
    if (bad <= ne) then
      xt = b%x(:, mesh%tri(:, bad))
      call triangle_gradients(xt, area, dn, alt)
      call set_error(err, "body '"//trim(b%name)//"': CST4 triangle "//itoa(bad)// &
        ' (nodes '//itoa(mesh%tri(1, bad))//', '//itoa(mesh%tri(2, bad))//', '// &
        itoa(mesh%tri(3, bad))//') has area '//rtoa(area)//' m^2 and centroid radius '// &
        rtoa(sum(xt(1, :))/3.0_wp)//' m: triangles need a positive area (nodes '// &
        'counter-clockwise) and, in axisymmetry, a centroid off the axis')
      return
    end if
    t%hmin = hmin
    ! lumped mass, row sums of the consistent mass (eq. 70): rho0 int N_I dA = rho0 A/3 per
    ! node, or 2 pi rho0 int N_I r dA = 2 pi rho0 A (2 r_I + r_J + r_K)/12 (a scatter: serial)
    allocate(t%mass(np), touched(np))
    t%mass = 0.0_wp
    touched = 0
    do e = 1, ne
      rsum = sum(b%x(1, mesh%tri(:, e)))
      do k = 1, 3
        i = mesh%tri(k, e)
        touched(i) = touched(i) + 1
        if (axisym) then
          t%mass(i) = t%mass(i) + 2.0_wp*pi*rho0*areas(e)*(b%x(1, i) + rsum)/12.0_wp
        else
          t%mass(i) = t%mass(i) + rho0*areas(e)/3.0_wp
        end if
      end do
    end do
    if (any(touched == 0)) then
      i = findloc(touched, 0, dim=1)
      call set_error(err, "body '"//trim(b%name)//"': CST4 node "//itoa(i)//' belongs to '// &
        'no triangle (it would have no mass): remove it or mesh it')
      return
    end if
    allocate(t%fix1(np))
    t%fix1 = axisym .and. abs(b%x(1, :)) <= tol
    ! nodal interpolation: the position table N_I(X_J) is the identity
    call tables_finish_elements(t, transpose=.not. present(box))
  end subroutine cst4_tables

  !> Area A (m^2, positive when counter-clockwise), shape-function gradients dn(:, k) =
  !! grad N_k (1/m) and smallest altitude 2A/(longest edge) (m) of the triangle xt(2, 3).
  pure subroutine triangle_gradients(xt, area, dn, alt)
    real(wp), intent(in) :: xt(2, 3)
    real(wp), intent(out) :: area, dn(2, 3), alt
    real(wp) :: a2, lmax
    integer :: k, k1, k2
    a2 = twice_area(xt)
    area = 0.5_wp*a2
    dn = 0.0_wp
    alt = 0.0_wp
    if (.not. (a2 > 0.0_wp)) return
    lmax = 0.0_wp
    do k = 1, 3
      k1 = modulo(k, 3) + 1
      k2 = modulo(k + 1, 3) + 1
      ! N_k = ((X_k1 x X_k2) + (y_k1 - y_k2) x + (x_k2 - x_k1) y)/(2A)
      dn(1, k) = (xt(2, k1) - xt(2, k2))/a2
      dn(2, k) = (xt(1, k2) - xt(1, k1))/a2
      lmax = max(lmax, norm2(xt(:, k2) - xt(:, k1)))
    end do
    alt = a2/lmax
  end subroutine triangle_gradients

  !> The smaller nominal spacing of b (m), or, for a body without one, the square root of
  !! its smallest positive nodal area (for the on-axis tolerance).
  pure real(wp) function nominal_spacing(b) result(s)
    type(body_t), intent(in) :: b
    s = minval(b%spacing(1:2))
    if (s > 0.0_wp) return
    s = 1.0_wp
    if (allocated(b%vol)) then
      if (any(b%vol > 0.0_wp)) s = sqrt(minval(b%vol, mask=b%vol > 0.0_wp))
    end if
  end function nominal_spacing
end module cst4_m
