!> A plane mesh file of linear triangles (the layout tools/mesh_body.py writes: /particles/x,
!! (np, 2) in h5py, /particles/volume, loop and order, /mesh/triangles, (ne, 3) 1-based)
!! read per part, so that no rank of mfcd_mpi holds the whole body of a plane gmsh script
!! past the set-up's checks (doc/parallel.md). The file is the one rank 0 meshed the
!! script into (body_setup_m geo_mesh_file) and then built the whole body from, through
!! every serial check (mfcd_mpi check_whole): the ranks trust its values, and take the
!! whole mesh's facts from the attributes of /mesh that rank 0 wrote (spacing, the
!! expression make_from_arrays evaluates; longest_edge; lo, hi, the extent).
!!
!! A rank holds its share of the nodes (the consecutive rows share_first gives) with what
!! the serial body takes of each (make_from_arrays, set_mesh_extras): its position, volume
!! and boundary flag (the file's columns), and its longest edge (its support's length),
!! from the triangles that touch it, all of which it reads, so each is the serial number
!! to the bit; its share of the triangles (the rows of /bodies it writes); and the
!! boundary loops whole (perimeter-sized: one pass over the loop and order columns, the
!! loops ordered as make_from_arrays orders them). For the set-up of its elements the
!! region of a box (tri_file_region): the triangles all of whose nodes lie in it, with
!! those nodes' serial facts. The file is streamed in blocks of block_rows rows (some
!! 16 B a node and 12 B a triangle a pass, at the set-up only); no rank reads it whole.
module tri_file_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use sorting_m, only: sort_index, sorted_place
  use rank_comm_m, only: share_first
  use hdf5_io_m, only: h5file_t, h5_open_read, h5_close, h5_has, h5_shape, h5_read_block, &
    h5_read_rows, h5_read_attr, h5_has_attr
  use body_m, only: body_t, body_region_rows, used_places
  use cst4_m, only: cst4_mesh_t
  use tet_file_m, only: block_rows, unique_nodes
  implicit none
  private
  public :: tri_file_share, tri_file_region, tri_file_count, tri_file_positions

  !> The triangles that touch a set of nodes, with the positions of all their nodes
  type :: touching_t
    integer :: n = 0
    integer, allocatable :: e(:)          !< their numbers in the file (ascending)
    integer, allocatable :: t(:, :)       !< their nodes, the file's numbers
    integer, allocatable :: nl(:, :)      !< t as places in node
    integer, allocatable :: node(:)       !< every node of them (ascending)
    real(wp), allocatable :: xn(:, :)     !< their positions, as in the file
  end type touching_t

contains

  !> Rank me's share (of nranks) of the body of the plane mesh file path (what names it):
  !! b holds the nodes row0 ... of np (positions, volumes, boundary flags), the triangles
  !! cell0 ... of ncells, the boundary loops whole, held_share, the spacing and its mfile
  !! (the path, the whole mesh's longest edge and extent). local: the longest edge at each
  !! node of the share (the supports'). Not collective: each rank reads its rows.
  subroutine tri_file_share(path, what, me, nranks, b, local, err, facts)
    character(len=*), intent(in) :: path, what
    integer, intent(in) :: me, nranks
    type(body_t), intent(out) :: b
    real(wp), allocatable, intent(out) :: local(:)
    type(error_t), allocatable, intent(inout) :: err
    !> the file of the whole mesh's facts (/mesh attributes), when path has none (a user's
    !! file: body_setup_m plane_facts_file); else path's
    character(len=*), intent(in), optional :: facts
    type(h5file_t) :: f, ff
    type(error_t), allocatable :: e2
    type(touching_t) :: tc
    integer, allocatable :: lp(:), tb(:, :)
    integer :: np, ne, r0, r1, n, c0, c1, i0, nb, i, g
    real(wp) :: spacing, lmax, lo(2), hi(2), image(2)
    call open_plane(path, what, f, np, ne, err)
    if (allocated(err)) return
    r0 = share_first(np, me, nranks)
    r1 = share_first(np, me + 1, nranks) - 1
    n = r1 - r0 + 1
    c0 = share_first(ne, me, nranks)
    c1 = share_first(ne, me + 1, nranks) - 1
    allocate(b%x(2, n), b%vol(n), lp(n), b%cells(3, c1 - c0 + 1))
    if (n > 0) then
      call h5_read_block(f, '/particles/x', b%x, r0, err)
      if (.not. allocated(err)) call h5_read_block(f, '/particles/volume', b%vol, r0, err)
      if (.not. allocated(err)) call h5_read_block(f, '/particles/loop', lp, r0, err)
    end if
    if (.not. allocated(err)) call read_loops(f, np, b, err)
    ! the triangles touching the share's nodes (every one that gives a node its longest
    ! edge), and the share of the triangles, in one pass
    call tc_start(tc)
    do i0 = 1, ne, block_rows
      if (allocated(err)) exit
      nb = min(block_rows, ne - i0 + 1)
      call read_tri_block(f, what, np, i0, nb, tb, err)
      if (allocated(err)) exit
      do i = 1, nb
        g = i0 + i - 1
        if (g >= c0 .and. g <= c1) b%cells(:, g - c0 + 1) = tb(:, i)
        if (any(tb(:, i) >= r0 .and. tb(:, i) <= r1)) call tc_add(tc, g, tb(:, i))
      end do
    end do
    if (.not. allocated(err)) call tc_positions(f, np, tc, err)
    if (present(facts) .and. .not. allocated(err)) then
      call h5_open_read(ff, facts, e2)
      if (allocated(e2)) call set_error(err, what//": the whole file's facts ('"//facts// &
        "') cannot be read")
    end if
    if (.not. allocated(err)) then
      if (present(facts)) then
        call whole_facts(ff)
      else
        call whole_facts(f)
      end if
    end if
    if (present(facts)) call h5_close(ff, e2)
    call h5_close(f, e2)
    if (allocated(err)) return
    call longest_edges(tc, [(i, i = r0, r1)], local)
    b%ndim = 2
    b%np = np
    b%row0 = r0
    b%held_share = .true.
    b%boundary = lp > 0
    b%cell0 = c0
    b%ncells = ne
    b%spacing = 0.0_wp
    b%spacing(1:2) = spacing
    allocate(b%mfile)
    b%mfile%path = path
    b%mfile%ne = ne
    b%mfile%lmax = lmax
    b%mfile%lo(1:2) = lo
    b%mfile%hi(1:2) = hi
    b%mfile%me = me
    b%mfile%nranks = nranks
    b%mfile%image = image

  contains

    !> The whole mesh's facts from fa's /mesh attributes (and, for an RKPM body in
    !! axisymmetry, its images' extent: mfcd_mpi check_whole)
    subroutine whole_facts(fa)
      type(h5file_t), intent(in) :: fa
      call read_facts(fa, what, spacing, lmax, lo, hi, err)
      image = [huge(1.0_wp), -huge(1.0_wp)]
      if (.not. allocated(err)) then
        if (h5_has_attr(fa, '/mesh', 'axis_images')) call h5_read_attr(fa, '/mesh', &
          'axis_images', image, err)
      end if
    end subroutine whole_facts
  end subroutine tri_file_share

  !> The nodes of the plane body b read per part (b%mfile) within the box lo ... hi (in
  !! the placed body: b%mfile%shift added), as body r: with mesh, only the nodes of the
  !! triangles all of whose nodes lie in the box, and those triangles over r's nodes in the
  !! file's order, with their file numbers eglob; without, every node in the box, with its
  !! integration cell (the file's /cells/ptr and /cells/xy rows: an RKPM body over the
  !! median-dual cells). Their positions, volumes, boundary flags and supports (b's factors
  !! times the longest edge at each: every triangle touching them is read) and their whole
  !! numbers r%glob (ascending, of np_whole = b%np); b's name, kernel, basis, spacing and
  !! file. Not collective.
  subroutine tri_file_region(b, lo, hi, r, err, mesh, eglob, cells)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(3), hi(3)
    type(body_t), intent(out) :: r
    type(error_t), allocatable, intent(inout) :: err
    type(cst4_mesh_t), intent(out), optional :: mesh
    integer, allocatable, intent(out), optional :: eglob(:)
    !> without mesh: read the nodes' cells (default), or not (the nodes only: a cloud)
    logical, intent(in), optional :: cells
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    type(touching_t) :: tc
    integer, allocatable :: sel(:), lsel(:), tb(:, :), loc(:), kept(:)
    real(wp), allocatable :: xsel(:, :), vsel(:), local(:)
    logical, allocatable :: used(:)
    real(wp) :: ulo(2), uhi(2)
    integer :: np, ne, i0, nb, i, m, k, n, p
    character(len=:), allocatable :: what
    logical :: with_cells
    what = "mesh file '"//b%mfile%path//"'"
    ulo = lo(1:2) - b%mfile%shift(1:2)
    uhi = hi(1:2) - b%mfile%shift(1:2)
    call open_plane(b%mfile%path, what, f, np, ne, err)
    if (allocated(err)) return
    call nodes_in_box(f, np, ulo, uhi, sel, err, xsel, vsel, lsel)
    ! the triangles touching them; those all of whose nodes are among them
    call tc_start(tc)
    allocate(kept(64))
    n = 0
    do i0 = 1, ne, block_rows
      if (allocated(err)) exit
      nb = min(block_rows, ne - i0 + 1)
      call read_tri_block(f, what, np, i0, nb, tb, err)
      if (allocated(err)) exit
      do i = 1, nb
        p = count([(sorted_place(sel, tb(k, i)) > 0, k = 1, 3)])
        if (p == 0) cycle
        call tc_add(tc, i0 + i - 1, tb(:, i))
        if (p < 3) cycle
        n = n + 1
        if (n > size(kept)) kept = [kept, kept]
        kept(n) = tc%n
      end do
    end do
    if (.not. allocated(err)) call tc_positions(f, np, tc, err)
    call h5_close(f, e2)
    if (allocated(err)) return
    call longest_edges(tc, sel, local)
    allocate(used(size(sel)))
    used = .false.
    do m = 1, n
      do k = 1, 3
        used(sorted_place(sel, tc%t(k, kept(m)))) = .true.
      end do
    end do
    if (present(mesh)) then
      loc = used_places(used)
      mesh%ne = n
      allocate(mesh%tri(3, n), eglob(n))
      do m = 1, n
        do k = 1, 3
          mesh%tri(k, m) = loc(sorted_place(sel, tc%t(k, kept(m))))
        end do
        eglob(m) = tc%e(kept(m))
      end do
    else
      ! every node in the box, with its cell
      used = .true.
    end if
    call body_region_rows(b, 2, sel, used, xsel, vsel, lsel > 0, local, r)
    with_cells = .not. present(mesh)
    if (present(cells)) with_cells = with_cells .and. cells
    if (with_cells) then
      call read_cells(b%mfile%path, what, np, sel, r, err)
      if (allocated(err)) return
      if (any(b%mfile%shift(1:2) /= 0.0_wp)) r%cell_xy = r%cell_xy + &
        spread(b%mfile%shift(1:2), 2, size(r%cell_xy, 2))
    end if
  end subroutine tri_file_region

  !> The integration cells of the nodes g (ascending) of the plane mesh file path onto r
  !! (cell_ptr over them, cell_xy: their /cells/xy rows, unplaced): the rows g and g + 1 of
  !! /cells/ptr (exact as reals: node counts far below 2^53), then their runs of /cells/xy.
  subroutine read_cells(path, what, np, g, r, err)
    character(len=*), intent(in) :: path, what
    integer, intent(in) :: np, g(:)
    type(body_t), intent(inout) :: r
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer, allocatable :: dims(:), at(:), rows(:)
    real(wp), allocatable :: p(:, :)
    integer :: n, m, i, k, nxy, a, c
    logical :: has
    n = size(g)
    call h5_open_read(f, path, err)
    if (allocated(err)) return
    ! (each looked for: h5_has is not pure, which .and. may skip)
    has = h5_has(f, '/cells/ptr')
    if (has) has = h5_has(f, '/cells/xy')
    if (.not. has) then
      call set_error(err, what//" has no /cells (ptr, xy): the median-dual cells an RKPM "// &
        "body integrates over")
      call h5_close(f, e2)
      return
    end if
    call h5_shape(f, '/cells/xy', dims, err)
    if (.not. allocated(err)) then
      nxy = dims(size(dims))
      ! (the rows g and g + 1, ascending without repeats; at: each g's place in them)
      allocate(rows(2*n), at(n))
      m = 0
      do i = 1, n
        if (m == 0) then
          m = 1
          rows(m) = g(i)
        else if (rows(m) /= g(i)) then
          m = m + 1
          rows(m) = g(i)
        end if
        at(i) = m
        m = m + 1
        rows(m) = g(i) + 1
      end do
      allocate(p(1, m))
      call h5_read_rows(f, '/cells/ptr', p, rows(1:m), np + 1, .true., err)
    end if
    if (.not. allocated(err)) then
      allocate(r%cell_ptr(n + 1))
      r%cell_ptr(1) = 1
      do i = 1, n
        r%cell_ptr(i + 1) = r%cell_ptr(i) + nint(p(1, at(i) + 1)) - nint(p(1, at(i)))
      end do
      deallocate(rows)
      allocate(rows(r%cell_ptr(n + 1) - 1))
      k = 0
      do i = 1, n
        a = nint(p(1, at(i)))
        c = nint(p(1, at(i) + 1))
        if (a < 1 .or. c < a .or. c - 1 > nxy) then
          call set_error(err, what//": /cells/ptr is not ascending within 1 ... "// &
            itoa(nxy + 1))
          exit
        end if
        rows(k + 1:k + c - a) = [(a + m, m = 0, c - a - 1)]
        k = k + c - a
      end do
    end if
    if (.not. allocated(err)) then
      allocate(r%cell_xy(2, size(rows)))
      call h5_read_rows(f, '/cells/xy', r%cell_xy, rows, nxy, .false., err)
    end if
    call h5_close(f, e2)
  end subroutine read_cells

  !> The positions of the nodes g (any order, repeats allowed) of the plane body b read
  !! per part, placed (b%mfile's shift added): its boundary loops' vertices.
  subroutine tri_file_positions(b, g, x, err)
    type(body_t), intent(in) :: b
    integer, intent(in) :: g(:)
    real(wp), allocatable, intent(out) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer, allocatable :: node(:), at(:, :)
    real(wp), allocatable :: xn(:, :)
    integer :: np, ne, i
    allocate(x(2, size(g)))
    call open_plane(b%mfile%path, "mesh file '"//b%mfile%path//"'", f, np, ne, err)
    if (allocated(err)) return
    call unique_nodes(reshape(g, [1, size(g)]), node, at)
    allocate(xn(2, size(node)))
    call h5_read_rows(f, '/particles/x', xn, node, np, .false., err)
    call h5_close(f, e2)
    if (allocated(err)) return
    do i = 1, size(g)
      x(:, i) = xn(:, at(1, i)) + b%mfile%shift(1:2)
    end do
  end subroutine tri_file_positions

  !> The longest edge at each node sel(i) (ascending) of the triangles tc, every one
  !! touching them (set_mesh_extras' lengths: node k to node k + 1 of each triangle, in
  !! turn; a maximum, so in any order the same bits).
  subroutine longest_edges(tc, sel, local)
    type(touching_t), intent(in) :: tc
    integer, intent(in) :: sel(:)
    real(wp), allocatable, intent(out) :: local(:)
    real(wp) :: len_e
    integer :: m, k, l, i
    allocate(local(size(sel)))
    local = 0.0_wp
    do m = 1, tc%n
      do k = 1, 3
        l = modulo(k, 3) + 1
        len_e = norm2(tc%xn(:, tc%nl(k, m)) - tc%xn(:, tc%nl(l, m)))
        i = sorted_place(sel, tc%t(k, m))
        if (i > 0) local(i) = max(local(i), len_e)
        i = sorted_place(sel, tc%t(l, m))
        if (i > 0) local(i) = max(local(i), len_e)
      end do
    end do
  end subroutine longest_edges

  !> Whether any node of the plane body b read per part lies within lo ... hi, placed (1,
  !! else 0; 1 when the file cannot be read again: nothing is refused for it here).
  integer function tri_file_count(b, lo, hi) result(n)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(3), hi(3)
    type(h5file_t) :: f
    type(error_t), allocatable :: err, e2
    integer, allocatable :: sel(:)
    integer :: np, ne
    n = 1
    call open_plane(b%mfile%path, "mesh file '"//b%mfile%path//"'", f, np, ne, err)
    if (allocated(err)) return
    call nodes_in_box(f, np, lo(1:2) - b%mfile%shift(1:2), hi(1:2) - b%mfile%shift(1:2), &
      sel, err)
    call h5_close(f, e2)
    if (.not. allocated(err)) n = min(1, size(sel))
  end function tri_file_count

  ! --- the file, streamed ---------------------------------------------------------------

  !> Open the plane mesh file and read its sizes: /particles/x (2, np), volume, loop and
  !! order (np), /mesh/triangles (3, ne).
  subroutine open_plane(path, what, f, np, ne, err)
    character(len=*), intent(in) :: path, what
    type(h5file_t), intent(out) :: f
    integer, intent(out) :: np, ne
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: dims(:)
    type(error_t), allocatable :: e2
    character(len=17), parameter :: cols(3) = [character(len=17) :: '/particles/volume', &
      '/particles/loop', '/particles/order']
    integer :: k
    np = 0
    ne = 0
    call h5_open_read(f, path, e2)
    if (allocated(e2)) then
      call set_error(err, what//" ('"//path//"') is not a readable HDF5 file")
      return
    end if
    call shape_of('/particles/x', dims)
    if (size(dims) /= 2) then
      call set_error(err, what//": dataset /particles/x (np x 2) missing")
    else if (dims(1) /= 2) then
      call set_error(err, what//": /particles/x is not a plane body's (2 coordinates)")
    else
      np = dims(2)
      do k = 1, 3
        call shape_of(trim(cols(k)), dims)
        if (.not. (size(dims) == 1 .and. dims(1) == np)) then
          call set_error(err, what//": "//trim(cols(k))//" is missing or not of "// &
            itoa(np)//" values")
          exit
        end if
      end do
    end if
    if (.not. allocated(err)) then
      call shape_of('/mesh/triangles', dims)
      if (size(dims) /= 2) then
        call set_error(err, what//" has no /mesh/triangles")
      else if (dims(1) /= 3 .or. dims(2) == 0) then
        call set_error(err, what//": /mesh/triangles must be (ne, 3) node numbers, ne > 0")
      else
        ne = dims(2)
      end if
    end if
    if (allocated(err)) call h5_close(f, e2)
  contains
    subroutine shape_of(name, d)
      character(len=*), intent(in) :: name
      integer, allocatable, intent(out) :: d(:)
      type(error_t), allocatable :: e3
      if (h5_has(f, name)) call h5_shape(f, name, d, e3)
      if (.not. allocated(d)) allocate(d(0))
    end subroutine shape_of
  end subroutine open_plane

  !> The whole mesh's facts rank 0 wrote with the file (body_setup_m geo_mesh_file).
  subroutine read_facts(f, what, spacing, lmax, lo, hi, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    real(wp), intent(out) :: spacing, lmax, lo(2), hi(2)
    type(error_t), allocatable, intent(inout) :: err
    call h5_read_attr(f, '/mesh', 'spacing', spacing, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/mesh', 'longest_edge', lmax, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/mesh', 'lo', lo, err)
    if (.not. allocated(err)) call h5_read_attr(f, '/mesh', 'hi', hi, err)
    if (allocated(err)) err%message = what//": the whole mesh's facts (attributes of "// &
      "/mesh) cannot be read: "//err%message
  end subroutine read_facts

  !> The boundary loops of the whole body onto b, as make_from_arrays makes them (loop k
  !! the rows with loop = k, ascending, sorted by their order values): one pass over the
  !! loop and order columns in blocks, keeping the boundary rows only.
  subroutine read_loops(f, np, b, err)
    type(h5file_t), intent(in) :: f
    integer, intent(in) :: np
    type(body_t), intent(inout) :: b
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: lb(:), ob(:), gi(:), gl(:), go(:), members(:), srt(:)
    real(wp), allocatable :: key(:)
    integer :: i0, nb, i, m, k, nl, pos
    allocate(gi(64), gl(64), go(64))
    m = 0
    nl = 0
    do i0 = 1, np, block_rows
      nb = min(block_rows, np - i0 + 1)
      if (allocated(lb)) deallocate(lb, ob)
      allocate(lb(nb), ob(nb))
      call h5_read_block(f, '/particles/loop', lb, i0, err)
      if (.not. allocated(err)) call h5_read_block(f, '/particles/order', ob, i0, err)
      if (allocated(err)) return
      do i = 1, nb
        if (lb(i) <= 0) cycle
        m = m + 1
        if (m > size(gi)) then
          gi = [gi, gi]
          gl = [gl, gl]
          go = [go, go]
        end if
        gi(m) = i0 + i - 1
        gl(m) = lb(i)
        go(m) = ob(i)
        nl = max(nl, lb(i))
      end do
    end do
    b%nloops = nl
    allocate(b%loop_ptr(nl + 1), b%loop_idx(m), b%loop_closed(nl))
    b%loop_closed = .true.
    b%loop_ptr(1) = 1
    pos = 0
    do k = 1, nl
      members = pack([(i, i = 1, m)], gl(1:m) == k)
      key = real(go(members), wp)
      if (allocated(srt)) deallocate(srt)
      allocate(srt(size(members)))
      call sort_index(key, srt)
      b%loop_idx(pos + 1:pos + size(members)) = gi(members(srt))
      pos = pos + size(members)
      b%loop_ptr(k + 1) = pos + 1
    end do
  end subroutine read_loops

  !> The nodes sel (ascending) whose positions lie within lo ... hi, with their
  !! positions, volumes and loop numbers when asked: one pass over the columns in blocks.
  subroutine nodes_in_box(f, np, lo, hi, sel, err, xsel, vsel, lsel)
    type(h5file_t), intent(in) :: f
    integer, intent(in) :: np
    real(wp), intent(in) :: lo(2), hi(2)
    integer, allocatable, intent(out) :: sel(:)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable, intent(out), optional :: xsel(:, :), vsel(:)
    integer, allocatable, intent(out), optional :: lsel(:)
    real(wp), allocatable :: xb(:, :), vb(:), xk(:, :), vk(:)
    integer, allocatable :: lb(:), lk(:)
    integer :: i0, nb, i, m
    logical :: facts
    facts = present(xsel)
    allocate(sel(64), xk(2, 64), vk(64), lk(64))
    m = 0
    do i0 = 1, np, block_rows
      nb = min(block_rows, np - i0 + 1)
      if (allocated(xb)) deallocate(xb, vb, lb)
      allocate(xb(2, nb), vb(nb), lb(nb))
      call h5_read_block(f, '/particles/x', xb, i0, err)
      if (facts .and. .not. allocated(err)) call h5_read_block(f, '/particles/volume', vb, &
        i0, err)
      if (facts .and. .not. allocated(err)) call h5_read_block(f, '/particles/loop', lb, &
        i0, err)
      if (allocated(err)) return
      do i = 1, nb
        if (any(xb(:, i) < lo) .or. any(xb(:, i) > hi)) cycle
        m = m + 1
        if (m > size(sel)) then
          sel = [sel, sel]
          xk = reshape([xk, xk], [2, 2*size(xk, 2)])
          vk = [vk, vk]
          lk = [lk, lk]
        end if
        sel(m) = i0 + i - 1
        if (.not. facts) cycle
        xk(:, m) = xb(:, i)
        vk(m) = vb(i)
        lk(m) = lb(i)
      end do
    end do
    sel = sel(1:m)
    if (.not. facts) return
    xsel = xk(:, 1:m)
    vsel = vk(1:m)
    lsel = lk(1:m)
  end subroutine nodes_in_box

  !> Triangles i0 ... i0 + n - 1 of the file, tb (3, n), every node within 1 ... np.
  subroutine read_tri_block(f, what, np, i0, n, tb, err)
    type(h5file_t), intent(in) :: f
    character(len=*), intent(in) :: what
    integer, intent(in) :: np, i0, n
    integer, allocatable, intent(out) :: tb(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable :: t8(:, :)
    allocate(t8(3, n))
    call h5_read_block(f, '/mesh/triangles', t8, i0, err)
    if (allocated(err)) return
    if (any(t8 < 1 .or. t8 > np)) then
      call set_error(err, what//": /mesh/triangles names a node outside 1.."//itoa(np))
      return
    end if
    tb = int(t8)
  end subroutine read_tri_block

  subroutine tc_start(tc)
    type(touching_t), intent(out) :: tc
    allocate(tc%e(64), tc%t(3, 64))
  end subroutine tc_start

  !> Triangle e (nodes t) kept in tc (room doubled when full).
  subroutine tc_add(tc, e, t)
    type(touching_t), intent(inout) :: tc
    integer, intent(in) :: e, t(3)
    integer, allocatable :: e2(:), t2(:, :)
    if (tc%n == size(tc%e)) then
      allocate(e2(2*tc%n), t2(3, 2*tc%n))
      e2(1:tc%n) = tc%e
      t2(:, 1:tc%n) = tc%t
      call move_alloc(e2, tc%e)
      call move_alloc(t2, tc%t)
    end if
    tc%n = tc%n + 1
    tc%e(tc%n) = e
    tc%t(:, tc%n) = t
  end subroutine tc_add

  !> tc's arrays cut to its triangles, their nodes (ascending) and those nodes' positions.
  subroutine tc_positions(f, np, tc, err)
    type(h5file_t), intent(in) :: f
    integer, intent(in) :: np
    type(touching_t), intent(inout) :: tc
    type(error_t), allocatable, intent(inout) :: err
    tc%e = tc%e(1:tc%n)
    tc%t = tc%t(:, 1:tc%n)
    call unique_nodes(tc%t, tc%node, tc%nl)
    allocate(tc%xn(2, size(tc%node)))
    call h5_read_rows(f, '/particles/x', tc%xn, tc%node, np, .false., err)
  end subroutine tc_positions
end module tri_file_m
