!> A particle body (or the nodes of a finite-element mesh): reference positions, volumes,
!! per-direction supports, boundary flags and
!! the ordered boundary polylines contact needs (master surface segments, eqs. 89-92), plus
!! the window/basis choice and the exact geometry when a generator made it.
module body_m
  use kinds_m, only: wp
  use rank_comm_m, only: share_first
  use geometry_m, only: geometry_t
  implicit none
  private
  public :: body_t, name_len, max_cell_vertices, body_keep_share, body_cell, extrusion_t
  public :: mesh_file_t, lattice_t
  public :: body_whole, body_keep_used, body_region_rows, used_places

  integer, parameter :: name_len = 64
  !> Vertices of one integration cell at most (a clipped lattice cell, a file's cell)
  integer, parameter :: max_cell_vertices = 64

  !> A 3D body of linear tetrahedra from a mesh file (tools/mesh_body.py --3d) that each rank
  !! reads only its share and region of (tet_file_m): the file, its tetrahedra's count, the
  !! longest edge of the whole mesh (the region's reach), the whole body's extent and the
  !! translation the body was moved by (&body translate), which every row read later gets.
  type :: mesh_file_t
    character(len=:), allocatable :: path
    integer :: ne = 0
    real(wp) :: lmax = 0.0_wp
    real(wp) :: lo(3) = 0.0_wp, hi(3) = 0.0_wp
    real(wp) :: shift(3) = 0.0_wp
    !> the rank (of nranks) that read it: the body's checks are cut in slabs of space
    integer :: me = 0, nranks = 1
    !> a rank's RKPM region read by the supports near its box (tet_file_region): the
    !! largest support of the box's nodes, per axis, by which the region's cells are
    !! chosen (rkpm_tl3d_m); negative: the region reaches by the whole mesh's
    real(wp) :: rbox(3) = -1.0_wp
    !> a plane mesh file's RKPM body in axisymmetry: the least and largest first
    !! coordinate of the mirror images about the axis of the whole body's particles
    !! (rkpm_tl_m axis_images; huge, -huge: none), which rank 0 took (mfcd_mpi)
    real(wp) :: image(2) = [huge(1.0_wp), -huge(1.0_wp)]
  end type mesh_file_t

  !> How an extruded 3D body's particles are made (generators_m extrude_body): its section
  !! (x-y positions, areas and boundary flags of the n2 section particles) and its nz
  !! layers from z0 to z1, dz apart, particle i of layer k numbered i + (k - 1) n2; then
  !! moved by shift when shifted (&body translate) and given the supports rho. Held (some
  !! 30 B a particle of the section) so that a rank can make just the particles its region
  !! needs (generators_m extrude_pick), the same bits as the whole body's.
  type :: extrusion_t
    integer :: n2 = 0, nz = 0
    real(wp), allocatable :: x2(:, :), vol2(:)
    logical, allocatable :: bnd2(:)
    real(wp) :: z0 = 0.0_wp, z1 = 0.0_wp, dz = 0.0_wp
    logical :: shifted = .false.
    real(wp) :: shift(3) = 0.0_wp
    real(wp) :: rho(3) = 0.0_wp
    !> the section's triangles (3, nt) of a body of tetrahedra (tet4_m tet4_prisms: its
    !! elements numbered by layer, triangle, then the prism's three), else unallocated
    integer, allocatable :: tri2(:, :)
    !> the closed surface's recipe (generators_m extruded_facet): the end caps' section
    !! triangles ctri (3, nt; generators_m section_triangles) and the section's boundary
    !! segments seg (2, nside: each from its first particle to the next along its loop);
    !! unallocated when the section has no triangulation that closes it
    integer, allocatable :: ctri(:, :), seg(:, :)
  end type extrusion_t

  !> How a rectangle's particles are made (generators_m make_rectangle): the lattice points
  !! origin + (i dx, j dy), i = 0 .. n(1) - 1, j = 0 .. n(2) - 1, particle (i + 1) + j n(1),
  !! each with its lattice cell clipped by the rectangle g (make_polygon's operations, which
  !! keep exactly these points and merge no cell into them: generators_m lattice_particle);
  !! then moved by shift when shifted (&body translate) and given the supports rho. Held
  !! (some 200 B; a polygon's runs below perimeter-sized) so that a rank can make just the
  !! particles its share and region need (generators_m lattice_pick), the same bits as the
  !! whole body's.
  type :: lattice_t
    integer :: n(2) = 0
    real(wp) :: origin(2) = 0.0_wp, dx(2) = 0.0_wp
    type(geometry_t) :: g
    !> a CST4 rectangle's (cst4_m cst4_rectangle): the lattice points are the corners of
    !! its (n(1) - 1) x (n(2) - 1) boxes, nodes 1 ... n(1) n(2), followed by the boxes'
    !! centres (node n(1) n(2) + box), each box cut into four triangles; the nodes' volumes
    !! are the lumped areas (generators_m lattice_node)
    logical :: cst4 = .false.
    logical :: shifted = .false.
    real(wp) :: shift(2) = 0.0_wp
    real(wp) :: rho(2) = 0.0_wp
    !> a polygon's lattice (generators_m make_polygon with a share, when it merges no
    !! lattice cell: polygon_walk): g the polygon, the lattice points origin + (i dx, j dy)
    !! with i from i0, j from j0, n(1) x n(2) of them; its nq particles lie in runs of
    !! consecutive i along the rows, in make_polygon's order (rows upwards, i ascending):
    !! run r is row run_j(r), i from run_i(1, r) to run_i(2, r), particles run_q(r) + 1
    !! ...; the runs of row j are run_ptr(j - j0 + 1) ... run_ptr(j - j0 + 2) - 1;
    !! col_low(i - i0 + 1) is the lowest particle's row in column i (j0 - 1: none). Rows,
    !! runs and columns: perimeter-sized. Unallocated run_ptr: a rectangle, whose particle
    !! (i + 1) + j n(1) is lattice point (i, j), i and j from 0.
    integer :: i0 = 0, j0 = 0, nq = 0
    integer, allocatable :: run_ptr(:), run_j(:), run_i(:, :), run_q(:), col_low(:)
    !> an annulus sector's CST4 nodes (cst4_m cst4_annulus with a share; cst4 true): the
    !! polar lattice of make_annulus, radii r0 + (i - 1) dr, angles t0 + (j - 1) dt about
    !! center, i = 1 ... n(1), j = 1 ... n(2), corner i + (j - 1) n(1) (the radius
    !! fastest); full: a whole ring, its last boxes closing onto the first; g the annulus.
    !! The supports at a node as made: factor x max(sdr, |x - center| sdt) (body_setup_m's
    !! local spacing, its own sdr and sdt), rho the largest of them.
    logical :: polar = .false., full = .false.
    real(wp) :: center(2) = 0.0_wp, r0 = 0.0_wp, dr = 0.0_wp, t0 = 0.0_wp, dt = 0.0_wp
    real(wp) :: sdr = 0.0_wp, sdt = 0.0_wp, factor(2) = 0.0_wp
  end type lattice_t

  type :: body_t
    character(len=name_len) :: name = ''
    character(len=32) :: shape = ''
    integer :: ndim = 2
    integer :: np = 0
    real(wp), allocatable :: x(:, :)      !< reference positions (ndim, np) (m)
    real(wp), allocatable :: vol(:)       !< particle volume (m^ndim; area in 2D)
    real(wp), allocatable :: rho(:, :)    !< support radius per direction (ndim, np) (m)
    logical, allocatable :: boundary(:)   !< particle lies on (or its cell is cut by) the boundary
    !> Centre of each particle's lattice cell (ndim, np) (m) once the particles have been moved
    !! off the lattice points (&body perturbation): the cells, and so the volumes and the SCNI
    !! smoothing domains, stay the lattice's. Unallocated: every cell is centred on its particle
    real(wp), allocatable :: cell_centre(:, :)
    !> Lattice cells merged into particle cells (polygon bodies, make_polygon): the cells of
    !! lattice points outside the polygon that still hold part of it. Particle i's cell is its
    !! own lattice cell plus the lattice cells centred at merged_centre(:, merged_ptr(i) :
    !! merged_ptr(i+1)-1), each clipped by the polygon; its volume is their total area, so the
    !! cells tile the body. Unallocated: no cell is merged (every other shape)
    integer, allocatable :: merged_ptr(:)
    real(wp), allocatable :: merged_centre(:, :)
    !> Explicit integration cells (an HDF5 particle file with /cells, e.g. the median-dual
    !! cells of a mesh from tools/mesh_body.py): particle i's cell is the polygon
    !! cell_xy(:, cell_ptr(i) : cell_ptr(i+1)-1), counter-clockwise; the cells tile the body
    !! and their areas are the volumes. Unallocated: lattice cells (or none)
    integer, allocatable :: cell_ptr(:)
    real(wp), allocatable :: cell_xy(:, :)
    !> > 0: the explicit cells repeat every cell_period particles (an extruded body's
    !! layers, whose sections are the same polygons: particle i's cell is cell
    !! body_cell(b, i) of cell_ptr, which holds cell_period cells); 0: one cell a particle
    integer :: cell_period = 0
    !> Boundary polylines in CSR form: loop k is loop_idx(loop_ptr(k) : loop_ptr(k+1)-1),
    !! counter-clockwise (outward normal = e3 x t on the right of the walking direction).
    integer :: nloops = 0
    integer, allocatable :: loop_ptr(:)
    integer, allocatable :: loop_idx(:)
    logical, allocatable :: loop_closed(:)
    !> The exact sums of every particle's coordinates and of every volume (a checkpoint
    !! recognises its bodies by them: run_checkpoint_m body_fingerprints, the same bits on
    !! any number of ranks holding any shares of the particles)
    real(wp) :: fingerprint(2) = 0.0_wp
    !> A rank's share of the body (body_keep_share; 0: the whole body): x, vol, rho and
    !! boundary hold the particles row0, row0 + 1, ..., cells the elements cell0, ... of
    !! ncells
    integer :: row0 = 0, cell0 = 0, ncells = 0
    !> The body was made as a rank's share only (build_bodies on ranks: generators_m
    !! extrude_body's rows; the whole body never existed on the rank): x, vol, rho and
    !! boundary hold particles row0 ... of np, as body_keep_share leaves them
    logical :: held_share = .false.
    real(wp) :: spacing(3) = 0.0_wp       !< nominal particle spacing per direction (m)
    real(wp) :: support_factor(3) = 0.0_wp
    real(wp) :: h(3) = 1.0_wp             !< basis scale: nominal support radius (m)
    integer :: kid = 1, wshape = 1, bid = 0
    type(geometry_t) :: geom
    !> Element connectivity (3, ne) when the body is a finite-element (CST4) mesh whose nodes
    !! are the points above; unallocated for particle bodies
    integer, allocatable :: cells(:, :)
    !> 3D bodies: the boundary surface as triangles over the particles (3, nfacet),
    !! counter-clockwise seen from outside (the outward normal is (x2 - x1) x (x3 - x1)),
    !! closed; unallocated when the generator cannot close it (contact in 3D needs it).
    !! On ranks (mfcd_mpi) a rank may hold some rows of it only: the facets numbered
    !! facet0, facet0 + 1, ... of the whole surface's nfacets (facet0 > 0: an extruded
    !! body made per rank, a mesh file read per part, a deformable body's share after the
    !! set-up: body_keep_share), which the ranks write into /bodies together; facet0 = 0:
    !! facets is the whole surface
    integer, allocatable :: facets(:, :)
    integer :: facet0 = 0, nfacets = 0
    !> A 3D RKPM body from a tetrahedral mesh (a gmsh script's volumes): the tetrahedra
    !! (4, ne) over its particles, positive volume, whose median-dual cells are the
    !! particles' integration cells (rkpm_tl3d_m); unallocated for every other body
    integer, allocatable :: tets(:, :)
    !> An extruded body's recipe (extrusion_t), when its particles can be made per region
    type(extrusion_t), allocatable :: ext
    !> A rectangle's or a polygon's recipe (lattice_t), when its particles can be made per region
    type(lattice_t), allocatable :: lat
    !> A body of tetrahedra read per part from its mesh file (mesh_file_t); facet_key: the
    !! rank's facets of it (those whose smallest node is in its share), each with its place
    !! 4 (e - 1) + f in the whole mesh's order (tetrahedron e, face f), until the ranks
    !! hold them in rows in that order (tet_file_m tet_file_facets: facet0, nfacets)
    type(mesh_file_t), allocatable :: mfile
    integer, allocatable :: facet_key(:)
    !> Some particles of a larger body (extrude_pick: a rank's region): x, vol, rho and
    !! boundary hold np particles whose numbers in the whole body (of np_whole) are
    !! glob (ascending); unallocated for a whole body (or a share, row0)
    integer, allocatable :: glob(:)
    integer :: np_whole = 0
  end type body_t

contains

  !> The explicit cell (of cell_ptr, cell_xy) of particle i of body b.
  pure integer function body_cell(b, i) result(k)
    type(body_t), intent(in) :: b
    integer, intent(in) :: i
    k = i
    if (allocated(b%glob)) k = b%glob(i)
    if (b%cell_period > 0) k = mod(k - 1, b%cell_period) + 1
  end function body_cell

  !> The number in the whole body of particle i of b (b%glob where b holds some of a
  !! larger body's particles).
  pure integer function body_whole(b, i) result(g)
    type(body_t), intent(in) :: b
    integer, intent(in) :: i
    g = i
    if (allocated(b%glob)) g = b%glob(i)
  end function body_whole

  !> The particles of near that used marks, as body r in near's order (its description and
  !! numbers in the whole body, glob, kept), and cells over near's particles renumbered
  !! over r's: a rank's region of an element body (tet4_m tet4_region, cst4_m
  !! cst4_region), the nodes its elements use.
  subroutine body_keep_used(near, used, cells, r)
    type(body_t), intent(in) :: near
    logical, intent(in) :: used(:)
    integer, intent(inout) :: cells(:, :)
    type(body_t), intent(out) :: r
    integer :: loc(size(used))
    integer, allocatable :: keep(:)
    integer :: i, n, m
    loc = used_places(used)
    n = count(used)
    do m = 1, size(cells, 2)
      cells(:, m) = loc(cells(:, m))
    end do
    keep = pack([(i, i = 1, near%np)], used)
    r = near
    r%np = n
    r%x = near%x(:, keep)
    r%vol = near%vol(keep)
    r%boundary = near%boundary(keep)
    r%rho = near%rho(:, keep)
    r%glob = near%glob(keep)
  end subroutine body_keep_used

  !> Each kept entry's place among the kept ones (used(i): the count of used(1:i)), 0 for
  !! the others: the renumbering of a mesh's nodes over those a region keeps.
  pure function used_places(used) result(loc)
    logical, intent(in) :: used(:)
    integer, allocatable :: loc(:)
    integer :: i, n
    allocate(loc(size(used)))
    loc = 0
    n = 0
    do i = 1, size(used)
      if (.not. used(i)) cycle
      n = n + 1
      loc(i) = n
    end do
  end function used_places

  !> Region r of body b read from b's mesh file by a rank (tri_file_m tri_file_region,
  !! tet_file_m tet_file_region): the file's nodes sel(used) (whole numbers, ascending),
  !! their positions xsel (as in the file: b%mfile's shift added here), volumes vsel,
  !! boundary flags bsel and longest edges hsel (the supports: b's factors times them);
  !! b's description (name, shape, kernel, basis, spacing, supports' factors, whole count
  !! np_whole) and file; no boundary loops.
  subroutine body_region_rows(b, nd, sel, used, xsel, vsel, bsel, hsel, r)
    type(body_t), intent(in) :: b
    integer, intent(in) :: nd, sel(:)
    logical, intent(in) :: used(:), bsel(:)
    real(wp), intent(in) :: xsel(:, :), vsel(:), hsel(:)
    type(body_t), intent(out) :: r
    integer :: i, m
    r%name = b%name
    r%shape = b%shape
    r%ndim = nd
    r%kid = b%kid
    r%wshape = b%wshape
    r%bid = b%bid
    r%spacing = b%spacing
    r%support_factor = b%support_factor
    r%h = b%h
    r%np = count(used)
    r%np_whole = b%np
    r%glob = pack(sel, used)
    allocate(r%x(nd, r%np))
    i = 0
    do m = 1, size(sel)
      if (.not. used(m)) cycle
      i = i + 1
      r%x(:, i) = xsel(1:nd, m) + b%mfile%shift(1:nd)
    end do
    r%vol = pack(vsel, used)
    r%boundary = pack(bsel, used)
    allocate(r%rho(nd, r%np))
    r%rho = spread(b%support_factor(1:nd), 2, r%np)*spread(pack(hsel, used), 1, nd)
    r%nloops = 0
    allocate(r%loop_ptr(1), r%loop_idx(0), r%loop_closed(0))
    r%loop_ptr(1) = 1
    ! (the file, for what the set-up asks of the whole body later: kinematic_masks)
    r%mfile = b%mfile
  end subroutine body_region_rows

  !> Body b reduced to rank me's share of it (of nranks), for the ranks of mfcd_mpi once
  !! the set-up has read it: the rows of its particles row0 .. row0 + nrows - 1 (the
  !! contiguous run np*me/nranks + 1 ... np*(me + 1)/nranks) of the positions, volumes,
  !! supports and boundary flags, and the same share of its elements (cell0, ncells: the
  !! whole count), which the ranks write into /bodies together (run_output_m
  !! write_body_rows); the same share of its facets (facet0, nfacets: the whole count;
  !! rows another split made before, a body made per rank's, kept as they are), written
  !! the same way; the boundary loops on rank 0 only (2D), which it writes; the rest
  !! freed (integration cells, the mesh of a body's dual cells, an extruded body's
  !! recipe). Its name, sizes, spacing, supports' factors, kernel, geometry
  !! and fingerprint stay. A body made as the share (held_share) keeps its rows.
  subroutine body_keep_share(b, me, nranks)
    type(body_t), intent(inout) :: b
    integer, intent(in) :: me, nranks
    integer :: i0, i1
    i0 = share_first(b%np, me, nranks)
    i1 = share_first(b%np, me + 1, nranks) - 1
    ! (a body made as the share holds it already)
    if (.not. b%held_share) then
      b%row0 = i0
      b%x = b%x(:, i0:i1)
      b%vol = b%vol(i0:i1)
      if (allocated(b%rho)) b%rho = b%rho(:, i0:i1)
      if (allocated(b%boundary)) b%boundary = b%boundary(i0:i1)
    end if
    b%held_share = .true.
    if (allocated(b%ext)) deallocate(b%ext)
    if (allocated(b%lat)) deallocate(b%lat)
    ! (a share made as such holds its elements' share already: ncells > 0)
    if (allocated(b%cells) .and. b%ncells == 0) call keep_columns(b%cells, b%ncells, b%cell0)
    if (allocated(b%cell_centre)) deallocate(b%cell_centre)
    if (allocated(b%merged_ptr)) deallocate(b%merged_ptr)
    if (allocated(b%merged_centre)) deallocate(b%merged_centre)
    if (allocated(b%cell_ptr)) deallocate(b%cell_ptr)
    if (allocated(b%cell_xy)) deallocate(b%cell_xy)
    b%cell_period = 0
    if (allocated(b%tets)) deallocate(b%tets)
    if (allocated(b%facets) .and. b%facet0 == 0) call keep_columns(b%facets, b%nfacets, &
      b%facet0)
    if (me == 0) return
    if (allocated(b%loop_ptr)) deallocate(b%loop_ptr)
    if (allocated(b%loop_idx)) deallocate(b%loop_idx)
    if (allocated(b%loop_closed)) deallocate(b%loop_closed)

  contains

    !> a's columns (elements, facets) cut to rank me's share: n the whole count, first
    !! the share's first column
    subroutine keep_columns(a, n, first)
      integer, allocatable, intent(inout) :: a(:, :)
      integer, intent(out) :: n, first
      n = size(a, 2)
      first = share_first(n, me, nranks)
      a = a(:, first:share_first(n, me + 1, nranks) - 1)
    end subroutine keep_columns
  end subroutine body_keep_share
end module body_m
