!> A 3D mesh file of linear tetrahedra (tools/mesh_body.py --3d: /particles/x, (np, 3) in
!! h5py, /particles/volume and /mesh/tetrahedra, (ne, 4) 1-based) read per part, so that
!! no rank of mfcd_mpi holds the whole mesh (doc/parallel.md). Every rank keeps only what
!! its share of the nodes, or a box of the decomposition, needs: the nodes, and the
!! tetrahedra that touch them with the positions of all their nodes. What the serial body
!! takes of a node (body_setup_m tet_mesh_body: its volume, the quarters of its tetrahedra
!! summed node 1, 2, 3, 4 of each tetrahedron in turn; its longest edge, the det(M)
!! support; its boundary flag, a node of a face of one tetrahedron only) needs only the
!! tetrahedra that touch it, all of which the rank has, so each is the serial number to
!! the bit. The checks of the whole file are the serial ones (body_setup_m
!! read_file_tets), made by each rank over its share of the rows and reduced over the
!! ranks (tet_file_share: the serial message on every rank), the volumes' agreement for
!! the rank's share. A file with an index (/mesh/node_box, /mesh/tet_box: the box of each
!! block of index_rows rows, mesh_cells_m mesh_index; tools/mesh_body.py --3d and
!! mfcd_mpi's own meshes write one, numbered in space; checked like the rest) is read for
!! a box only in the blocks whose box meets it, so a rank reads its part's rows, not the
!! file; without one, every rank streams the whole file in blocks of block_rows rows for
!! its share's tetrahedra and its region (some 56 B a node, at the set-up only).
module tet_file_m
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use sorting_m, only: sort_index, radix_index, incidence_csr
  use rank_comm_m, only: rank_comm_t, share_first, share_rank, route_columns
  use exact_sum_m, only: exact_sum_t, exact_add, exact_merge, exact_value, exact_allmerge
  use hdf5_io_m, only: h5file_t, h5_open_read, h5_close, h5_has, h5_shape, h5_read_block, &
    h5_read_rows, h5_read
  use body_m, only: body_t, mesh_file_t, body_region_rows, used_places
  use mesh_cells_m, only: tet_volume, index_rows
  use log_m, only: log_print
  use tet4_m, only: tet4_mesh_t, face_nodes
  implicit none
  private
  public :: tet_file_share, tet_file_region, tet_file_facets, tet_file_positions, volume_spacing
  public :: block_rows, tet_file_count, mesh_index_t, read_index, node_outside, tet_outside
  public :: rows_read, file_error, unique_nodes, merge_places

  !> Rows a block of the file (64 Ki rows: 1.5 MiB of positions, 2 MiB of tetrahedra; a
  !! test sets a few, so that a small mesh spans many blocks)
  integer :: block_rows = 65536
  !> The file's volumes against the tetrahedra's: a relative difference beyond this is not
  !! round-off (read_file_tets' tolerance, the same reason)
  real(wp), parameter :: vol_tol = 1.0e-9_wp
  !> Rows of positions and tetrahedra read for boxes so far (nodes_in_box, scan_tets with a
  !! set of nodes): what the index saves, seen by the tests
  integer(i64) :: rows_read = 0

  !> A mesh file's index (mesh_cells_m mesh_index): the box (lo, hi) of each block of
  !! index_rows nodes and of the nodes of each block of index_rows tetrahedra
  type :: mesh_index_t
    logical :: has = .false.
    real(wp), allocatable :: nbox(:, :), tbox(:, :)
  end type mesh_index_t

  !> What tet_file_share's checks find over shares of the file's rows (scan_stage): the
  !! first wrong row of each kind (huge: none), in the serial checks' order: 1 a tetrahedron
  !! naming a node outside 1 ... np, 2 a node not finite, 3 a node outside its index box,
  !! 4 a tetrahedron without a positive volume, 5 a tetrahedron outside its index box; the
  !! extent lo ... hi, the longest edge, the volume column's exact sum
  type :: scan_t
    integer :: bad(5) = huge(1)
    real(wp) :: lo(3) = huge(1.0_wp), hi(3) = -huge(1.0_wp), lmax = 0.0_wp
    type(exact_sum_t) :: vsum
    !> (scan_reduce: some rank could not read its rows)
    logical :: unread = .false.
  end type scan_t

  !> The tetrahedra that touch a set of nodes, with the positions of all their nodes
  type :: touching_t
    integer :: n = 0
    integer, allocatable :: e(:)          !< their numbers in the file (ascending)
    integer, allocatable :: t(:, :)       !< their nodes, the file's numbers
    real(wp), allocatable :: v(:)         !< their volumes
    integer, allocatable :: node(:)       !< every node of them (ascending)
    integer, allocatable :: nl(:, :)      !< t as places in node
    real(wp), allocatable :: xn(:, :)     !< their positions, as in the file
  end type touching_t

contains

  !> The nominal spacing of a tetrahedral body whose volume column is v (np of them): the
  !! cube root of their mean, their sum exact (exact_sum_m), so that a rank summing its share
  !! of the file and the serial body summing it whole have the same bits.
  function volume_spacing(v, np) result(h)
    real(wp), intent(in) :: v(:)
    integer, intent(in) :: np
    real(wp) :: h
    type(exact_sum_t) :: a
    integer :: i
    do i = 1, size(v)
      call exact_add(a, v(i))
    end do
    h = (exact_value(a)/real(np, wp))**(1.0_wp/3.0_wp)
  end function volume_spacing

  !> Rank me's share (of nranks) of the body of the tetrahedral mesh file path (what names
  !! it for messages): b holds the nodes row0 ... of np (positions, the serial volumes,
  !! boundary flags) and the tetrahedra cell0 ... of ncells, held_share, its mfile (the
  !! path, the whole mesh's longest edge and extent), its spacing volume_spacing's of the
  !! file's volume column (serial too: body_setup_m), and its facets whose smallest node
  !! is in the share with their places in the whole mesh (facet_key; tet_file_facets
  !! puts them in rows over the ranks). local: the longest edge at each node of the share (the supports').
  !!
  !! The whole file's checks (the serial reading's, in its order: the node numbers, the
  !! index's shape, finite values, each node in its index box, positive volumes, each
  !! tetrahedron in its index box) and facts (the extent, the longest edge, the volume
  !! column's sum) are made by the ranks of comm each over its share of the rows, then
  !! reduced (the first wrong row of each kind the smallest over the ranks: the serial
  !! message on every rank); without comm by one rank over every share in turn (the whole
  !! file, the same checks and numbers). Then the tetrahedra touching the share's nodes:
  !! with the file's index from the blocks whose box meets the share's box only. So a rank
  !! of comm reads its shares of the rows and the blocks near its share, not the file.
  !! Collective over comm.
  subroutine tet_file_share(path, what, me, nranks, b, local, err, comm)
    character(len=*), intent(in) :: path, what
    integer, intent(in) :: me, nranks
    type(body_t), intent(out) :: b
    real(wp), allocatable, intent(out) :: local(:)
    type(error_t), allocatable, intent(inout) :: err
    class(rank_comm_t), intent(inout), optional :: comm
    type(h5file_t) :: f
    type(mesh_index_t) :: ix
    type(error_t), allocatable :: e2
    type(touching_t) :: tc
    type(scan_t) :: total, one
    real(wp), allocatable :: xs(:, :), colv(:), v4(:)
    real(wp) :: lo(3), hi(3), lmax, slo(3), shi(3)
    integer :: np, ne, r0, r1, n, i, k, c0, c1, nover, stage, q
    integer(i64), allocatable :: t8(:, :)
    call open_mesh(path, what, f, np, ne, err)
    if (allocated(err)) return
    r0 = share_first(np, me, nranks)
    r1 = share_first(np, me + 1, nranks) - 1
    n = r1 - r0 + 1
    c0 = share_first(ne, me, nranks)
    c1 = share_first(ne, me + 1, nranks) - 1
    allocate(xs(3, n), colv(n), t8(4, c1 - c0 + 1))
    ! (the serial checks' order: the node numbers, the index, the nodes, the tetrahedra)
    do stage = 1, 3
      ! (the index after the node numbers, as the serial reading takes it: read_file_tets;
      ! the same file on every rank, so the same result)
      if (stage == 2) then
        call read_index(f, what, np, ne, ix, err)
        ! (said once, by the first rank: the others' logs go nowhere)
        if (.not. allocated(err) .and. .not. ix%has .and. me == 0 .and. nranks > 1) &
          call log_print(what//" has no index (/mesh/node_box, /mesh/tet_box): every "// &
          "rank reads the whole file for its part; tools/mesh_body.py --reindex numbers "// &
          "it in space and writes one")
      end if
      if (allocated(err)) exit
      if (present(comm)) then
        one = scan_t()
        call scan_stage(f, ix, stage, np, ne, me, nranks, one, xs, colv, t8, err)
        ! (a rank that cannot read its rows still takes part: no rank waits for it)
        call scan_reduce(one, comm, allocated(err))
        if (one%unread .and. .not. allocated(err)) call set_error(err, what//": another "// &
          "rank could not read its rows of the file")
        if (allocated(err)) exit
        call scan_merge(total, one)
      else
        do q = 0, nranks - 1
          one = scan_t()
          if (q == me) then
            call scan_stage(f, ix, stage, np, ne, q, nranks, one, xs, colv, t8, err)
          else
            call scan_stage(f, ix, stage, np, ne, q, nranks, one, err=err)
          end if
          if (allocated(err)) exit
          call scan_merge(total, one)
        end do
      end if
      if (allocated(err)) exit
      call scan_error(f, what, np, total, err)
      if (allocated(err)) exit
    end do
    ! the tetrahedra touching the share's nodes: by the index, those of the blocks whose
    ! box meets the share's box; else every block
    if (.not. allocated(err)) then
      if (ix%has) then
        slo = huge(1.0_wp)
        shi = -huge(1.0_wp)
        do k = 1, n
          slo = min(slo, xs(:, k))
          shi = max(shi, xs(:, k))
        end do
        call scan_tets(f, '', np, ne, 0, -1, tc, err, ix, sel=[(i, i = r0, r1)], &
          lo=slo, hi=shi)
      else
        call scan_tets(f, what, np, ne, r0, r1, tc, err, ix)
      end if
    end if
    call h5_close(f, e2)
    if (allocated(err)) return
    lo = total%lo
    hi = total%hi
    lmax = total%lmax
    ! the serial volumes, longest edges, boundary flags and facets of the share's nodes
    b%ndim = 3
    b%np = np
    b%row0 = r0
    b%held_share = .true.
    call node_facts(tc, [(i, i = r0, r1)], v4, local, b%boundary, b%facets, b%facet_key, &
      nover)
    do k = 1, n
      if (.not. (abs(colv(k) - v4(k)) <= vol_tol*v4(k))) then
        call set_error(err, what//", particle "//itoa(r0 + k - 1)//": its volume "// &
          rtoa(colv(k))//" m^3 is not its quarter of the tetrahedra it belongs to, "// &
          rtoa(v4(k))//" m^3 (a node in no tetrahedron has none): /particles/volume "// &
          "and /mesh/tetrahedra disagree; write the file with tools/mesh_body.py --3d")
        return
      end if
    end do
    ! (then tet_mesh_body's: a face of the share's nodes in more than two tetrahedra)
    if (nover > 0) then
      call set_error(err, what//": "//itoa(nover)//" faces belong to more than two "// &
        "tetrahedra (the mesh is not conforming); fix the script")
      return
    end if
    ! (make_from_arrays' check: a node in no tetrahedron, given a volume of 0)
    if (any(v4 <= 0.0_wp)) then
      call set_error(err, 'particle file: every particle volume must be positive')
      return
    end if
    call move_alloc(xs, b%x)
    call move_alloc(v4, b%vol)
    b%cells = int(t8)
    b%cell0 = c0
    b%ncells = ne
    b%nloops = 0
    allocate(b%loop_ptr(1), b%loop_idx(0), b%loop_closed(0))
    b%loop_ptr(1) = 1
    b%spacing = 0.0_wp
    b%spacing(1:3) = (exact_value(total%vsum)/real(np, wp))**(1.0_wp/3.0_wp)
    allocate(b%mfile)
    b%mfile%path = path
    b%mfile%ne = ne
    b%mfile%lmax = lmax
    b%mfile%lo = lo
    b%mfile%hi = hi
    b%mfile%me = me
    b%mfile%nranks = nranks
  end subroutine tet_file_share

  !> The nodes of the body b read per part (b%mfile) within the box lo ... hi (in the
  !! placed body: b%mfile%shift added) as body r: their positions, serial volumes, boundary
  !! flags and supports (b's factors times the longest edge at each), their whole numbers
  !! r%glob (ascending, of np_whole); b's name, kernel, basis and spacing. With mesh: only
  !! the nodes of the tetrahedra all of whose nodes lie in the box, and those tetrahedra
  !! over r's nodes, with their whole numbers eglob (ascending).
  !!
  !! With supports (an RKPM body over the tetrahedra's median-dual cells, rkpm_tl3d_m
  !! scni_tables_3d): lo ... hi is a rank's box, and the nodes are those the box's tables
  !! can read, by the supports near the box rather than the whole mesh's largest (a graded
  !! mesh's coarsest element would otherwise reach over most of it): with R the largest
  !! support of the box's nodes (per axis) and l_i the longest edge at node i, the kept
  !! cells are those whose node lies within R + l_i of the box (a cell reaches no farther
  !! than l_i from its node; a node of the box covers no farther than R from it), L their
  !! longest l_i, and the region the nodes j within rho_j + R + 2 L of it (a particle
  !! covering a point of a kept cell). r%mfile%rbox = R for the cells' choice there.
  subroutine tet_file_region(b, lo, hi, r, err, mesh, eglob, supports)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(3), hi(3)
    type(body_t), intent(out) :: r
    type(error_t), allocatable, intent(inout) :: err
    type(tet4_mesh_t), intent(out), optional :: mesh
    integer, allocatable, intent(out), optional :: eglob(:)
    logical, intent(in), optional :: supports
    type(h5file_t) :: f
    type(mesh_index_t) :: ix
    type(error_t), allocatable :: e2
    type(touching_t) :: tc
    integer, allocatable :: sel(:), fct(:, :), key(:), keep(:), loc(:), selp(:)
    real(wp), allocatable :: xsel(:, :), v4(:), local(:)
    logical, allocatable :: bnd(:), used(:)
    real(wp) :: rbox(3)
    integer :: np, ne, m, n, l, nover
    logical :: sup
    sup = .false.
    if (present(supports)) sup = supports
    rbox = -1.0_wp
    call open_mesh(b%mfile%path, "mesh file '"//b%mfile%path//"'", f, np, ne, err, ix)
    if (sup) then
      if (.not. allocated(err)) call support_region(f, ix, b, np, ne, lo, hi, sel, xsel, &
        tc, rbox, err)
    else
      if (.not. allocated(err)) call nodes_in_box(f, np, lo - b%mfile%shift, &
        hi - b%mfile%shift, sel, xsel, err, ix)
      if (.not. allocated(err)) call scan_tets(f, '', np, ne, 0, -1, tc, err, ix, &
        sel=sel, lo=lo - b%mfile%shift, hi=hi - b%mfile%shift)
    end if
    call h5_close(f, e2)
    if (allocated(err)) return
    call node_facts(tc, sel, v4, local, bnd, fct, key, nover)
    allocate(used(size(sel)))
    used = .true.
    if (present(mesh)) then
      ! the tetrahedra all of whose nodes are in the box, and the nodes they use
      used = .false.
      allocate(keep(tc%n))
      selp = merge_places(tc%node, sel)
      n = 0
      do m = 1, tc%n
        if (all(selp(tc%nl(:, m)) > 0)) then
          n = n + 1
          keep(n) = m
          used(selp(tc%nl(:, m))) = .true.
        end if
      end do
      loc = used_places(used)
      mesh%ne = n
      allocate(mesh%tet(4, n), eglob(n))
      do m = 1, n
        do l = 1, 4
          mesh%tet(l, m) = loc(selp(tc%nl(l, keep(m))))
        end do
        eglob(m) = tc%e(keep(m))
      end do
    end if
    call body_region_rows(b, 3, sel, used, xsel, v4, bnd, local, r)
    r%mfile%rbox = rbox
    ! (b's facets, the rank's rows of the surface, as a region made from an extruded
    ! body's recipe holds them: a side over the region takes its surface from side_facts)
    if (allocated(b%facets)) then
      r%facets = b%facets
    else
      allocate(r%facets(3, 0))
    end if
    r%facet0 = b%facet0
    r%nfacets = b%nfacets
  end subroutine tet_file_region

  !> The nodes sel (ascending, positions xsel unplaced) of tet_file_region's region by the
  !! supports for the box lo ... hi (placed) of the body b read per part, with the
  !! tetrahedra touching them (tc) and R (rbox). One pass over the file's nodes and one over
  !! its tetrahedra, as for a box: the nodes within the largest reach the region can have
  !! (R + 2 L + rho_j with the whole mesh's longest edge for every length: 2 (f + 1) l for
  !! support factors f, against the 2 (f + 2) l of the region by the whole mesh's), and the
  !! longest edge at each of them (every tetrahedron touching them is read); then R from
  !! those in the box, the kept cells' L and the region. Each test has a margin (1e-9
  !! relative, and 1e-9 of the mesh's extent) over the cells' choice in scni_tables_3d,
  !! which compares placed positions with the box: the region holds every node a cell
  !! kept there reads.
  subroutine support_region(f, ix, b, np, ne, lo, hi, sel, xsel, tc, rbox, err)
    type(h5file_t), intent(in) :: f
    type(mesh_index_t), intent(in) :: ix
    type(body_t), intent(in) :: b
    integer, intent(in) :: np, ne
    real(wp), intent(in) :: lo(3), hi(3)
    integer, allocatable, intent(out) :: sel(:)
    real(wp), allocatable, intent(out) :: xsel(:, :)
    type(touching_t), intent(out) :: tc
    real(wp), intent(out) :: rbox(3)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), parameter :: rel = 1.0e-9_wp
    integer, allocatable :: sc(:), fct(:, :), key(:)
    real(wp), allocatable :: xc(:, :), v4(:), local(:)
    logical, allocatable :: bnd(:), in(:)
    real(wp) :: tol, lk, sf(3), d(3), ulo(3), uhi(3), g(3)
    integer :: m, nover
    sf = b%support_factor(1:3)
    ulo = lo - b%mfile%shift
    uhi = hi - b%mfile%shift
    tol = rel*maxval(b%mfile%hi - b%mfile%lo)
    g = (2.0_wp*sf + 2.0_wp)*b%mfile%lmax*(1.0_wp + rel) + 3.0_wp*tol
    call nodes_in_box(f, np, ulo - g, uhi + g, sc, xc, err, ix)
    if (.not. allocated(err)) call scan_tets(f, '', np, ne, 0, -1, tc, err, ix, &
      sel=sc, lo=ulo - g, hi=uhi + g)
    if (allocated(err)) return
    call node_facts(tc, sc, v4, local, bnd, fct, key, nover)
    ! R: the box's largest support (its nodes are among sc, their edges whole)
    rbox = 0.0_wp
    do m = 1, size(sc)
      if (any(xc(:, m) < ulo) .or. any(xc(:, m) > uhi)) cycle
      rbox = max(rbox, sf*local(m))
    end do
    ! the kept cells' longest edge L
    lk = 0.0_wp
    do m = 1, size(sc)
      d = max(ulo - xc(:, m), 0.0_wp, xc(:, m) - uhi)
      if (all(d <= rbox*(1.0_wp + rel) + local(m)*(1.0_wp + rel) + tol)) lk = max(lk, local(m))
    end do
    ! the particles covering a point of a kept cell
    allocate(in(size(sc)))
    do m = 1, size(sc)
      d = max(ulo - xc(:, m), 0.0_wp, xc(:, m) - uhi)
      in(m) = all(d <= (sf*local(m) + rbox + 2.0_wp*lk)*(1.0_wp + rel) + 2.0_wp*tol)
    end do
    sel = pack(sc, in)
    allocate(xsel(3, size(sel)))
    xsel = reshape(pack(xc, spread(in, 1, 3)), [3, size(sel)])
  end subroutine support_region

  !> Whether any node of the body b read per part lies within lo ... hi, placed (1, else
  !! 0; 1 when the file cannot be read again: nothing is refused for it here).
  integer function tet_file_count(b, lo, hi) result(n)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(3), hi(3)
    type(h5file_t) :: f
    type(mesh_index_t) :: ix
    type(error_t), allocatable :: err, e2
    integer, allocatable :: sel(:)
    real(wp), allocatable :: xsel(:, :)
    integer :: np, ne
    n = 1
    call open_mesh(b%mfile%path, "mesh file '"//b%mfile%path//"'", f, np, ne, err, ix)
    if (allocated(err)) return
    call nodes_in_box(f, np, lo - b%mfile%shift, hi - b%mfile%shift, sel, xsel, err, ix)
    call h5_close(f, e2)
    if (.not. allocated(err)) n = min(1, size(sel))
  end function tet_file_count

  !> The positions of the nodes g (ascending) of the body b read per part, placed (b%mfile's
  !! shift added): a surface's vertices.
  subroutine tet_file_positions(b, g, x, err)
    type(body_t), intent(in) :: b
    integer, intent(in) :: g(:)
    real(wp), allocatable, intent(out) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer :: np, ne, i
    allocate(x(3, size(g)))
    call open_mesh(b%mfile%path, "mesh file '"//b%mfile%path//"'", f, np, ne, err)
    if (allocated(err)) return
    call h5_read_rows(f, '/particles/x', x, g, np, .false., err)
    call h5_close(f, e2)
    do i = 1, size(g)
      x(:, i) = x(:, i) + b%mfile%shift
    end do
  end subroutine tet_file_positions

  !> The facets of the bodies read per part put in rows over the ranks, in the whole
  !! mesh's order (tet4_boundary_faces': tetrahedron, then face): a rank's facets (those
  !! whose smallest node is in its share, with their places: facet_key) go to the rank
  !! holding their place's range of the 4 ne (rank_comm_m share_first), which orders its
  !! own; each rank then holds the rows facet0 ... of the surface's nfacets, which the
  !! ranks write into /bodies together (run_output_m body_rows): no rank holds the whole
  !! surface (a side takes the part near its region: side_surface_m). Collective.
  subroutine tet_file_facets(bodies, comm)
    type(body_t), intent(inout) :: bodies(:)
    class(rank_comm_t), intent(inout) :: comm
    real(wp), allocatable :: key(:), all(:, :)
    integer, allocatable :: idx(:), dest(:), got(:, :)
    integer :: k, n, j, np
    np = comm%nranks
    do k = 1, size(bodies)
      if (.not. allocated(bodies(k)%facet_key)) cycle
      associate (b => bodies(k))
        n = size(b%facet_key)
        ! (each facet, with its place, to the rank of its place's range of the 4 ne)
        allocate(dest(n))
        do j = 1, n
          dest(j) = share_rank(b%facet_key(j), 4*b%mfile%ne, np)
        end do
        call route_columns(comm, dest, reshape([(b%facet_key(j), b%facets(:, j), &
          j = 1, n)], [4, n]), got)
        key = real(got(1, :), wp)
        allocate(idx(size(key)))
        call sort_index(key, idx)
        b%facets = got(2:4, idx)
        ! (the rows before this rank's: the counts of the ranks before it)
        allocate(all(1, np))
        call comm%allgather_real([real(size(key), wp)], all)
        b%facet0 = nint(sum(all(1, 1:comm%me))) + 1
        b%nfacets = nint(sum(all(1, :)))
        deallocate(b%facet_key)
        deallocate(dest, got, key, idx, all)
      end associate
    end do
  end subroutine tet_file_facets

  ! --- the file, streamed ---------------------------------------------------------------

  !> Open the mesh file and read its sizes: /particles/x (3, np), /particles/volume (np),
  !! /mesh/tetrahedra (4, ne), the messages as the serial reading's.
  subroutine open_mesh(path, what, f, np, ne, err, ix)
    character(len=*), intent(in) :: path, what
    type(h5file_t), intent(out) :: f
    integer, intent(out) :: np, ne
    type(error_t), allocatable, intent(inout) :: err
    !> the file's index (read_index), if it has one
    type(mesh_index_t), intent(out), optional :: ix
    integer, allocatable :: dims(:)
    type(error_t), allocatable :: e2
    np = 0
    ne = 0
    call h5_open_read(f, path, e2)
    if (allocated(e2)) then
      call set_error(err, "particle file '"//path//"' is not a readable HDF5 file")
      return
    end if
    if (h5_has(f, '/particles/x')) call h5_shape(f, '/particles/x', dims, e2)
    if (.not. allocated(dims)) allocate(dims(0))
    if (size(dims) /= 2) then
      call set_error(err, "particle file '"//path//"': dataset /particles/x (np x ndim) "// &
        "missing")
    else if (dims(1) /= 3) then
      call set_error(err, "particle file '"//path//"': /particles/x has the wrong number "// &
        "of coordinates for &run ndim")
    else
      np = dims(2)
      if (h5_has(f, '/particles/volume')) call h5_shape(f, '/particles/volume', dims, e2)
      if (.not. (size(dims) == 1 .and. dims(1) == np)) call set_error(err, "particle "// &
        "file '"//path//"': cannot read /particles/x and /particles/volume (np values)")
    end if
    if (.not. allocated(err)) then
      if (.not. h5_has(f, '/mesh/tetrahedra')) then
        call set_error(err, what//" has no /mesh/tetrahedra: a deformable 3D body from a "// &
          "file is its tetrahedral mesh ('fem': its elements; 'rkpm': their median-dual "// &
          "cells); write the file with tools/mesh_body.py --3d, or mesh the script in "// &
          "the deck (shape = 'geo')")
      else
        call h5_shape(f, '/mesh/tetrahedra', dims, err)
        if (.not. allocated(err)) then
          if (size(dims) /= 2 .or. dims(1) /= 4) then
            call set_error(err, what//": /mesh/tetrahedra must be (ne, 4) node numbers")
          else
            ne = dims(2)
            if (ne == 0) call set_error(err, what//": /mesh/tetrahedra is empty")
          end if
        end if
      end if
    end if
    if (.not. allocated(err) .and. present(ix)) call read_index(f, what, np, ne, ix, err)
    if (allocated(err)) call h5_close(f, e2)
  end subroutine open_mesh

  !> The nodes sel (ascending) whose positions lie within lo ... hi, and their positions:
  !! with the file's index ix (checked by tet_file_share's whole reading), from the blocks
  !! whose box meets lo ... hi only; each block read once.
  subroutine nodes_in_box(f, np, lo, hi, sel, xsel, err, ix)
    type(h5file_t), intent(in) :: f
    integer, intent(in) :: np
    real(wp), intent(in) :: lo(3), hi(3)
    integer, allocatable, intent(out) :: sel(:)
    real(wp), allocatable, intent(out) :: xsel(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(mesh_index_t), intent(in) :: ix
    real(wp), allocatable :: xb(:, :), x2(:, :)
    integer, allocatable :: first(:), count(:), s2(:)
    integer :: i0, n, i, m, j
    if (ix%has) then
      call row_runs(np, first, count, ix%nbox, lo, hi)
    else
      call row_runs(np, first, count)
    end if
    ! (one pass over the blocks: the kept rows grow by doubling, the box's size)
    allocate(sel(1024), xsel(3, 1024))
    m = 0
    do j = 1, size(first)
      i0 = first(j)
      n = count(j)
      if (allocated(xb)) deallocate(xb)
      allocate(xb(3, n))
      call h5_read_block(f, '/particles/x', xb, i0, err)
      if (allocated(err)) return
      rows_read = rows_read + n
      do i = 1, n
        if (any(xb(:, i) < lo) .or. any(xb(:, i) > hi)) cycle
        m = m + 1
        if (m > size(sel)) then
          allocate(s2(2*size(sel)), x2(3, 2*size(sel)))
          s2(1:m - 1) = sel(1:m - 1)
          x2(:, 1:m - 1) = xsel(:, 1:m - 1)
          call move_alloc(s2, sel)
          call move_alloc(x2, xsel)
        end if
        sel(m) = i0 + i - 1
        xsel(:, m) = xb(:, i)
      end do
    end do
    sel = sel(1:m)
    xsel = xsel(:, 1:m)
  end subroutine nodes_in_box

  !> The tetrahedra that touch the nodes r0 ... r1 (or sel, ascending), with the positions
  !! of all their nodes (tc). With sel, the file's index ix and the box lo ... hi that holds
  !! sel's nodes: only the blocks of tetrahedra whose box meets it are read (a tetrahedron
  !! touching a node of the box has its box meet it).
  subroutine scan_tets(f, what, np, ne, r0, r1, tc, err, ix, sel, lo, hi)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    integer, intent(in) :: np, ne, r0, r1
    type(touching_t), intent(out) :: tc
    type(error_t), allocatable, intent(inout) :: err
    type(mesh_index_t), intent(in) :: ix
    integer, intent(in), optional :: sel(:)
    real(wp), intent(in), optional :: lo(3), hi(3)
    integer, allocatable :: tb(:, :), nb(:), wb(:, :), member(:), ek(:), tk(:, :)
    integer, allocatable :: first(:), count(:)
    logical :: mine
    integer :: i0, n, i, cnt, m, run, nn
    if (ix%has .and. present(sel)) then
      call row_runs(ne, first, count, ix%tbox, lo, hi)
    else
      call row_runs(ne, first, count)
    end if
    allocate(ek(1024), tk(4, 1024))
    cnt = 0
    do run = 1, size(first)
      i0 = first(run)
      n = count(run)
      call read_tets_block(f, what, np, i0, n, tb, err)
      if (allocated(err)) return
      if (present(sel)) then
        rows_read = rows_read + n
        ! (the block's nodes in sel: one merge of two ascending lists)
        call unique_nodes(tb, nb, wb)
        member = merge_places(nb, sel)
      end if
      do i = 1, n
        if (present(sel)) then
          mine = any(member(wb(:, i)) > 0)
        else
          mine = any(tb(:, i) >= r0 .and. tb(:, i) <= r1)
        end if
        if (.not. mine) cycle
        cnt = cnt + 1
        if (cnt > size(ek)) call grow_kept(ek, tk)
        ek(cnt) = i0 + i - 1
        tk(:, cnt) = tb(:, i)
      end do
    end do
    ! the kept tetrahedra's nodes and their positions (what a node's facts read)
    tc%n = cnt
    tc%e = ek(1:cnt)
    tc%t = tk(:, 1:cnt)
    call unique_nodes(tc%t, tc%node, tc%nl)
    nn = size(tc%node)
    allocate(tc%xn(3, nn), tc%v(cnt))
    call h5_read_rows(f, '/particles/x', tc%xn, tc%node, np, .false., err)
    if (allocated(err)) return
    do m = 1, cnt
      tc%v(m) = tet_volume(tc%xn, tc%nl(:, m))
    end do
  end subroutine scan_tets

  !> Tetrahedra i0 ... i0 + n - 1 of the file, tb (4, n), every node number within 1 ... np
  !! (read_file_tets' message; checked before the conversion to default integers).
  subroutine read_tets_block(f, what, np, i0, n, tb, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    integer, intent(in) :: np, i0, n
    integer, allocatable, intent(out) :: tb(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable :: t8(:, :)
    allocate(t8(4, n))
    call h5_read_block(f, '/mesh/tetrahedra', t8, i0, err)
    if (allocated(err)) return
    if (any(t8 < 1 .or. t8 > np)) then
      call file_error(err, what, np, 1, 0, [0, 0, 0, 0], 0.0_wp)
      return
    end if
    tb = int(t8)
  end subroutine read_tets_block

  !> ek and tk with room for twice as many tetrahedra (a copy, no temporary of the pair).
  subroutine grow_kept(ek, tk)
    integer, allocatable, intent(inout) :: ek(:), tk(:, :)
    integer, allocatable :: e2(:), t2(:, :)
    integer :: n
    n = size(ek)
    allocate(e2(2*n), t2(4, 2*n))
    e2(1:n) = ek
    t2(:, 1:n) = tk
    call move_alloc(e2, ek)
    call move_alloc(t2, tk)
  end subroutine grow_kept

  !> The distinct numbers of t, ascending, and t as places in them (at, t's shape).
  subroutine unique_nodes(t, nodes, at)
    integer, intent(in) :: t(:, :)
    integer, allocatable, intent(out) :: nodes(:), at(:, :)
    integer, allocatable :: flat(:), idx(:), w(:)
    integer :: i, n
    flat = reshape(t, [size(t)])
    allocate(idx(size(flat)), w(size(flat)), nodes(size(flat)))
    call radix_index(flat, idx)
    n = 0
    do i = 1, size(flat)
      if (n > 0) then
        if (nodes(n) == flat(idx(i))) then
          w(idx(i)) = n
          cycle
        end if
      end if
      n = n + 1
      nodes(n) = flat(idx(i))
      w(idx(i)) = n
    end do
    nodes = nodes(1:n)
    at = reshape(w, shape(t))
  end subroutine unique_nodes

  !> For a and b ascending without repeats: the place of each a(i) in b, 0 where it is
  !! not there (one merge: no search a number).
  pure function merge_places(a, b) result(p)
    integer, intent(in) :: a(:), b(:)
    integer :: p(size(a))
    integer :: i, j
    p = 0
    j = 1
    do i = 1, size(a)
      do while (j <= size(b))
        if (b(j) >= a(i)) exit
        j = j + 1
      end do
      if (j > size(b)) exit
      if (b(j) == a(i)) p(i) = j
    end do
  end function merge_places

  !> What the serial body takes of each node of sel (ascending; every tetrahedron touching
  !! one is in tc): v4 the quarters of its tetrahedra, summed node 1, 2, 3, 4 of each in
  !! turn in the file's order (tet_mesh_body's sums), local its longest edge, bnd whether
  !! it is a node of a face of one tetrahedron only; the boundary faces whose smallest node
  !! is in sel, fct (3, :) as tet4_boundary_faces writes them, with their places key
  !! (4 (e - 1) + f), ascending. (Some 24 B a tetrahedron of tc beside tc: no array over
  !! its faces.)
  subroutine node_facts(tc, sel, v4, local, bnd, fct, key, nover)
    type(touching_t), intent(in) :: tc
    integer, intent(in) :: sel(:)
    real(wp), allocatable, intent(out) :: v4(:), local(:)
    logical, allocatable, intent(out) :: bnd(:)
    integer, allocatable, intent(out) :: fct(:, :), key(:)
    !> the faces of sel's nodes in more than two tetrahedra (the mesh not conforming),
    !! counted as tet4_boundary_faces counts them: every tetrahedron's such face
    integer, intent(out) :: nover
    integer, allocatable :: sl(:, :), selp(:), ptr(:), tl(:)
    integer :: ns, k, m, i, j, l, p, q, a, nn, pass, nshare, o
    logical, allocatable :: shared(:, :)
    integer :: s1(3), s2(3), fa(3)
    real(wp) :: len_e
    ns = size(sel)
    allocate(v4(ns), local(ns), bnd(ns))
    v4 = 0.0_wp
    local = 0.0_wp
    bnd = .false.
    ! (the kept tetrahedra's nodes as places in sel, 0: not in sel)
    selp = merge_places(tc%node, sel)
    allocate(sl(4, tc%n))
    do m = 1, tc%n
      sl(:, m) = selp(tc%nl(:, m))
    end do
    do k = 1, 4
      do m = 1, tc%n
        i = sl(k, m)
        if (i > 0) v4(i) = v4(i) + 0.25_wp*tc%v(m)
      end do
    end do
    do m = 1, tc%n
      do k = 1, 3
        do j = k + 1, 4
          len_e = norm2(tc%xn(:, tc%nl(k, m)) - tc%xn(:, tc%nl(j, m)))
          i = sl(k, m)
          if (i > 0) local(i) = max(local(i), len_e)
          i = sl(j, m)
          if (i > 0) local(i) = max(local(i), len_e)
        end do
      end do
    end do
    ! the faces with a node in sel: every tetrahedron holding such a face holds that node, so
    ! is in tc, and holds the face's first node, whose tetrahedra (a CSR over tc%node) are
    ! looked through for the other two
    nn = size(tc%node)
    call incidence_csr(tc%nl, nn, ptr, tl)
    ! (two passes: the facets counted, then kept, in the whole mesh's order: tc's, then
    ! each one's faces in turn)
    ! (a shared face is matched once, from its first tetrahedron: the others' marked)
    allocate(shared(4, tc%n))
    shared = .false.
    nover = 0
    do pass = 1, 2
      a = 0
      do m = 1, tc%n
        do p = 1, 4
          s2 = sl(face_nodes(:, p), m)
          if (all(s2 == 0)) cycle
          if (shared(p, m)) cycle
          fa = tc%nl(face_nodes(:, p), m)
          ! (the tetrahedra of the face's node in fewest)
          i = fa(minloc(ptr(fa + 1) - ptr(fa), 1))
          nshare = 0
          do q = ptr(i), ptr(i + 1) - 1
            o = tl(q)
            if (o == m) cycle
            if (.not. (any(tc%nl(:, o) == fa(1)) .and. any(tc%nl(:, o) == fa(2)) .and. &
              any(tc%nl(:, o) == fa(3)))) cycle
            nshare = nshare + 1
            ! (its face is the one opposite its fourth node)
            do l = 1, 4
              if (all(tc%nl(l, o) /= fa)) shared(l, o) = .true.
            end do
          end do
          if (nshare > 0) shared(p, m) = .true.
          ! (tet4_boundary_faces counts each tetrahedron's face that more than one other
          ! holds: all nshare + 1 of them)
          if (nshare > 1 .and. pass == 1) nover = nover + nshare + 1
          if (nshare /= 0) cycle
          ! a boundary face: its nodes are boundary nodes; one of the rank's facets when its
          ! smallest node is in sel
          s1 = tc%t(face_nodes(:, p), m)
          if (pass == 1) then
            do l = 1, 3
              if (s2(l) > 0) bnd(s2(l)) = .true.
            end do
          end if
          if (s2(minloc(s1, 1)) == 0) cycle
          a = a + 1
          if (pass == 1) cycle
          fct(:, a) = s1
          key(a) = 4*(tc%e(m) - 1) + p
        end do
      end do
      if (pass == 1) allocate(fct(3, a), key(a))
    end do
  end subroutine node_facts

  ! --- the whole file's checks, over shares -----------------------------------------------

  !> Stage stage of tet_file_share's checks over share q (of nranks) of the rows, into s
  !! (the first wrong row of each kind, the extent, the longest edge, the volume sum): 1 the
  !! share of tetrahedra's node numbers (t8: those rows, which stage 3 takes again rather
  !! than read them twice); 2 the share of nodes (xs, colv:
  !! their positions and volumes): finite, within their index boxes, their extent and
  !! volumes' sum; 3 the share of tetrahedra again: positive volumes (their nodes' positions
  !! read), longest edges, within their index boxes. Each stage runs only if the ones
  !! before found nothing wrong anywhere (scan_error).
  subroutine scan_stage(f, ix, stage, np, ne, q, nranks, s, xs, colv, t8, err)
    type(h5file_t), intent(in) :: f
    type(mesh_index_t), intent(in) :: ix
    integer, intent(in) :: stage, np, ne, q, nranks
    type(scan_t), intent(inout) :: s
    real(wp), intent(out), optional :: xs(:, :), colv(:)
    integer(i64), intent(inout), optional :: t8(:, :)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: xb(:, :), vb(:), xn(:, :)
    integer(i64), allocatable :: tb(:, :)
    integer, allocatable :: nodes(:), at(:, :)
    integer :: r0, r1, c0, c1, k, g, l, j
    real(wp) :: v
    r0 = share_first(np, q, nranks)
    r1 = share_first(np, q + 1, nranks) - 1
    c0 = share_first(ne, q, nranks)
    c1 = share_first(ne, q + 1, nranks) - 1
    select case (stage)
    case (1, 3)
      ! (stage 3 of this rank's share: its rows as stage 1 read them)
      if (stage == 3 .and. present(t8)) then
        tb = t8
      else
        allocate(tb(4, c1 - c0 + 1))
        if (c1 >= c0) call h5_read_block(f, '/mesh/tetrahedra', tb, c0, err)
        if (allocated(err)) return
      end if
      if (stage == 1) then
        do k = 1, size(tb, 2)
          if (any(tb(:, k) < 1 .or. tb(:, k) > np)) then
            s%bad(1) = c0 + k - 1
            exit
          end if
        end do
        if (present(t8)) t8 = tb
        return
      end if
      ! (their nodes' positions: every number in range, stage 1)
      call unique_nodes(int(tb), nodes, at)
      allocate(xn(3, size(nodes)))
      call h5_read_rows(f, '/particles/x', xn, nodes, np, .false., err)
      if (allocated(err)) return
      do k = 1, size(tb, 2)
        v = tet_volume(xn, at(:, k))
        if (.not. (v > 0.0_wp)) then
          s%bad(4) = c0 + k - 1
          exit
        end if
        do l = 1, 3
          do j = l + 1, 4
            s%lmax = max(s%lmax, norm2(xn(:, at(l, k)) - xn(:, at(j, k))))
          end do
        end do
        if (ix%has .and. s%bad(5) == huge(1)) then
          if (tet_outside(ix, c0 + k - 1, xn(:, at(:, k)))) s%bad(5) = c0 + k - 1
        end if
      end do
    case (2)
      allocate(xb(3, r1 - r0 + 1), vb(r1 - r0 + 1))
      if (r1 >= r0) call h5_read_block(f, '/particles/x', xb, r0, err)
      if (r1 >= r0 .and. .not. allocated(err)) call h5_read_block(f, '/particles/volume', &
        vb, r0, err)
      if (allocated(err)) return
      do k = 1, size(vb)
        g = r0 + k - 1
        if (.not. (all(ieee_is_finite(xb(:, k))) .and. ieee_is_finite(vb(k)))) then
          s%bad(2) = g
          exit
        end if
        s%lo = min(s%lo, xb(:, k))
        s%hi = max(s%hi, xb(:, k))
        call exact_add(s%vsum, vb(k))
        if (ix%has .and. s%bad(3) == huge(1)) then
          if (node_outside(ix, g, xb(:, k))) s%bad(3) = g
        end if
      end do
      if (present(xs)) xs = xb
      if (present(colv)) colv = vb
    end select
  end subroutine scan_stage

  !> a and b of two sets of shares made one: the first wrong rows, the extent, the longest
  !! edge and the exact volume sum of both
  subroutine scan_merge(a, b)
    type(scan_t), intent(inout) :: a
    type(scan_t), intent(in) :: b
    a%bad = min(a%bad, b%bad)
    a%lo = min(a%lo, b%lo)
    a%hi = max(a%hi, b%hi)
    a%lmax = max(a%lmax, b%lmax)
    call exact_merge(a%vsum, b%vsum)
  end subroutine scan_merge

  !> s over every rank of comm (collective): the smallest wrong rows, the extent, the
  !! longest edge, the exact sum (the same bits on every rank for any split)
  subroutine scan_reduce(s, comm, unread)
    type(scan_t), intent(inout) :: s
    class(rank_comm_t), intent(inout) :: comm
    !> this rank could not read its rows (s%unread: some rank)
    logical, intent(in) :: unread
    integer :: v(6)
    real(wp) :: r(7)
    s%unread = unread
    if (comm%nranks == 1) return
    v = [s%bad, merge(0, 1, unread)]
    call comm%min_int(v)
    s%bad = v(1:5)
    s%unread = v(6) == 0
    r = [-s%lo, s%hi, s%lmax]
    call comm%max_real(r)
    s%lo = -r(1:3)
    s%hi = r(4:6)
    s%lmax = r(7)
    s%vsum = exact_allmerge(s%vsum, comm)
  end subroutine scan_reduce

  !> The serial reading's message for the first kind s found wrong (a tetrahedron's volume
  !! from its row and nodes read again).
  subroutine scan_error(f, what, np, s, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    integer, intent(in) :: np
    type(scan_t), intent(in) :: s
    type(error_t), allocatable, intent(inout) :: err
    integer(i64) :: t8(4, 1)
    integer, allocatable :: nodes(:), at(:, :)
    real(wp), allocatable :: xn(:, :)
    integer :: k, t(4)
    real(wp) :: v
    k = findloc(s%bad < huge(1), .true., 1)
    if (k == 0) return
    t = 0
    v = 0.0_wp
    if (k == 4) then
      call h5_read_block(f, '/mesh/tetrahedra', t8, s%bad(4), err)
      if (allocated(err)) return
      t = int(t8(:, 1))
      call unique_nodes(reshape(t, [4, 1]), nodes, at)
      allocate(xn(3, size(nodes)))
      call h5_read_rows(f, '/particles/x', xn, nodes, np, .false., err)
      if (allocated(err)) return
      v = tet_volume(xn, at(:, 1))
    end if
    call file_error(err, what, np, k, s%bad(k), t, v)
  end subroutine scan_error

  !> A mesh file's message for a wrong row of kind k (scan_t's kinds), the serial reading's
  !! (body_setup_m read_file_tets) and the ranks' alike: row the node's or tetrahedron's
  !! number; for kind 4 (a tetrahedron without a positive volume) its nodes t and volume v.
  subroutine file_error(err, what, np, k, row, t, v)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in) :: what
    integer, intent(in) :: np, k, row, t(4)
    real(wp), intent(in) :: v
    select case (k)
    case (1)
      call set_error(err, what//": /mesh/tetrahedra names a node outside 1.."//itoa(np))
    case (2)
      call set_error(err, what//", particle "//itoa(row)//": a coordinate or the volume "// &
        "is not a finite number (NaN or Infinity); fix the file")
    case (3)
      call index_error(err, what, "particle "//itoa(row)//" lies outside its block's box "// &
        "in the index /mesh/node_box")
    case (4)
      call set_error(err, what//": tetrahedron "//itoa(row)//" of /mesh/tetrahedra (nodes "// &
        itoa(t(1))//", "//itoa(t(2))//", "//itoa(t(3))//", "//itoa(t(4))//") has volume "// &
        rtoa(v)//" m^3: each needs a positive volume, node 4 on the side of face (1, 2, "// &
        "3) its right-hand normal points to (tools/mesh_body.py --3d orders them)")
    case (5)
      call index_error(err, what, "tetrahedron "//itoa(row)//" has a node outside its "// &
        "block's box in the index /mesh/tet_box")
    end select
  end subroutine file_error

  ! --- the index ------------------------------------------------------------------------

  !> The index of the open mesh file f of np nodes and ne tetrahedra (ix%has: the file has
  !! one): both datasets or neither, each (6, blocks of index_rows rows).
  subroutine read_index(f, what, np, ne, ix, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    integer, intent(in) :: np, ne
    type(mesh_index_t), intent(out) :: ix
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: dn(:), dt(:)
    integer :: nb, nt
    logical :: hn, ht
    hn = h5_has(f, '/mesh/node_box')
    ht = h5_has(f, '/mesh/tet_box')
    if (.not. (hn .or. ht)) return
    nb = (np + index_rows - 1)/index_rows
    nt = (ne + index_rows - 1)/index_rows
    allocate(dn(0), dt(0))
    if (hn) call h5_shape(f, '/mesh/node_box', dn, err)
    if (ht .and. .not. allocated(err)) call h5_shape(f, '/mesh/tet_box', dt, err)
    if (allocated(err)) return
    if (.not. (size(dn) == 2 .and. size(dt) == 2)) then
      call index_error(err, what, "its index needs both /mesh/node_box and /mesh/tet_box")
      return
    end if
    if (.not. (dn(1) == 6 .and. dn(2) == nb .and. dt(1) == 6 .and. dt(2) == nt)) then
      call index_error(err, what, "its index /mesh/node_box and /mesh/tet_box must be ("// &
        itoa(nb)//", 6) and ("//itoa(nt)//", 6): the box (low x, y, z, high x, y, z) of "// &
        "each block of "//itoa(index_rows)//" rows")
      return
    end if
    allocate(ix%nbox(6, nb), ix%tbox(6, nt))
    call h5_read(f, '/mesh/node_box', ix%nbox, err)
    if (.not. allocated(err)) call h5_read(f, '/mesh/tet_box', ix%tbox, err)
    if (allocated(err)) return
    ! (finite boxes: no comparison with a NaN, which the positions' checks would trap)
    if (.not. (all(ieee_is_finite(ix%nbox)) .and. all(ieee_is_finite(ix%tbox)))) then
      call index_error(err, what, "its index /mesh/node_box or /mesh/tet_box has a box "// &
        "that is not finite numbers (NaN or Infinity)")
      return
    end if
    ix%has = .true.
  end subroutine read_index

  !> A wrong index's message (what the file is, why): the fix named.
  subroutine index_error(err, what, why)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in) :: what, why
    call set_error(err, what//": "//why//"; write the file with tools/mesh_body.py --3d "// &
      "(or --reindex it), or delete /mesh/node_box and /mesh/tet_box (the ranks then read "// &
      "the whole file)")
  end subroutine index_error

  !> Whether node g at p lies outside its block's box (a NaN box holds nothing).
  pure logical function node_outside(ix, g, p) result(out)
    type(mesh_index_t), intent(in) :: ix
    integer, intent(in) :: g
    real(wp), intent(in) :: p(3)
    integer :: k
    k = (g - 1)/index_rows + 1
    out = .not. (all(p >= ix%nbox(1:3, k)) .and. all(p <= ix%nbox(4:6, k)))
  end function node_outside

  !> Whether a node of tetrahedron e (its positions p (3, 4)) lies outside its block's box.
  pure logical function tet_outside(ix, e, p) result(out)
    type(mesh_index_t), intent(in) :: ix
    integer, intent(in) :: e
    real(wp), intent(in) :: p(3, 4)
    integer :: k, l
    k = (e - 1)/index_rows + 1
    out = .false.
    do l = 1, 4
      out = out .or. .not. (all(p(:, l) >= ix%tbox(1:3, k)) .and. &
        all(p(:, l) <= ix%tbox(4:6, k)))
    end do
  end function tet_outside

  !> The runs of rows to read (first(i), count(i), at most block_rows each) of a dataset of
  !! n rows whose index boxes are box (6, :): every row without a box (or without lo, hi),
  !! else the blocks whose box meets lo ... hi, consecutive ones joined.
  subroutine row_runs(n, first, count, box, lo, hi)
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: first(:), count(:)
    real(wp), intent(in), optional :: box(:, :), lo(3), hi(3)
    integer :: k, m, r0, r1
    logical :: meets
    allocate(first((n + index_rows - 1)/index_rows + n/block_rows + 1))
    allocate(count(size(first)))
    m = 0
    if (.not. (present(box) .and. present(lo) .and. present(hi))) then
      do r0 = 1, n, block_rows
        m = m + 1
        first(m) = r0
        count(m) = min(block_rows, n - r0 + 1)
      end do
    else
      do k = 1, size(box, 2)
        meets = all(box(1:3, k) <= hi) .and. all(box(4:6, k) >= lo)
        if (.not. meets) cycle
        r0 = (k - 1)*index_rows + 1
        r1 = min(n, k*index_rows)
        if (m > 0) then
          if (first(m) + count(m) == r0 .and. count(m) + r1 - r0 + 1 <= block_rows) then
            count(m) = count(m) + r1 - r0 + 1
            cycle
          end if
        end if
        m = m + 1
        first(m) = r0
        count(m) = r1 - r0 + 1
      end do
    end if
    first = first(1:m)
    count = count(1:m)
  end subroutine row_runs
end module tet_file_m
