!> A triangle mesh as the arrays of a body: the nodes, counter-clockwise triangles, the
!! boundary loops, each node's median-dual cell and its volume. This is the port of
!! tools/mesh_body.py (mesh_geo after gmsh, boundary_loops, dual_cells, write_body), so that a
!! .geo meshed in memory (&body shape = 'geo') gives the body that the script's particle file
!! gives with shape = 'file', bit for bit: the same nodes in the same order, the same
!! polygons with the same vertices in the same order, and every sum taken in numpy's order.
module mesh_cells_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use sorting_m, only: incidence_csr, radix_index
  implicit none
  private
  public :: mesh_from_tags, mesh_body_arrays, triangle_area, check_cells, tet_volume
  public :: space_order, mesh_index, index_rows

  !> Rows a block of a tetrahedral mesh file's index (/mesh/node_box, /mesh/tet_box:
  !! mesh_index): a rank reading its part reads the blocks whose box meets its own
  !! (tet_file_m), 96 KiB of positions a block (a test sets a few, so that a small mesh has
  !! many blocks; a file's index has the blocks of the writer's: tools/mesh_body.py's 4096)
  integer :: index_rows = 4096

contains

  !> Nodes and counter-clockwise triangles from a mesher's raw arrays (gmsh's getNodes and
  !! getElements): node tags tags(n) with coordinates xyz(3*n), and the node tags of the
  !! 3-node triangles, tri_tags(3*ne). Only the nodes of triangles are kept (a geometry's
  !! construction points are dropped), in the mesher's node order; x(2, np) are their x and y
  !! and tri(3, ne) the triangles in 1-based rows of x, each clockwise one with its second
  !! and third nodes swapped. With nv = 4 the elements are 4-node tetrahedra (tri_tags(4*ne)),
  !! x(3, np) the nodes' x, y, z and tri(4, ne) the tetrahedra, each of negative volume with
  !! its third and fourth nodes swapped; a tetrahedron of zero volume is an error.
  subroutine mesh_from_tags(tags, xyz, tri_tags, x, tri, err, nv)
    integer(i64), intent(in) :: tags(:), tri_tags(:)
    real(wp), intent(in) :: xyz(:)
    real(wp), allocatable, intent(out) :: x(:, :)
    integer, allocatable, intent(out) :: tri(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: nv
    integer, allocatable :: pos(:), renum(:)
    logical, allocatable :: used(:)
    integer(i64) :: maxtag
    integer :: n, ne, k, e, np, j, t, m, nd
    character(len=:), allocatable :: what
    real(wp) :: v
    m = 3
    if (present(nv)) m = nv
    nd = m - 1
    what = merge('triangle   ', 'tetrahedron', m == 3)
    n = size(tags)
    ne = size(tri_tags)/m
    if (ne == 0 .or. n == 0) then
      if (m == 3) then
        call set_error(err, 'the mesh has no triangles (is there a Plane Surface?)')
      else
        call set_error(err, 'the mesh has no tetrahedra (is there a Volume?)')
      end if
      return
    end if
    if (size(xyz) /= 3*n .or. size(tri_tags) /= m*ne) then
      call set_error(err, 'the mesher returned '//itoa(size(xyz))//' coordinates for '// &
        itoa(n)//' nodes and '//itoa(size(tri_tags))//' '//trim(what)//' node tags')
      return
    end if
    maxtag = maxval(tags)
    if (minval(tags) < 1 .or. maxtag > huge(1)) then
      call set_error(err, 'the mesher returned a node tag outside 1 .. '//itoa(huge(1)))
      return
    end if
    ! the position of each tag among the nodes (the script's `index`)
    allocate(pos(maxtag))
    pos = 0
    do k = 1, n
      pos(tags(k)) = k
    end do
    allocate(used(n))
    used = .false.
    do k = 1, m*ne
      if (tri_tags(k) < 1 .or. tri_tags(k) > maxtag) then
        t = 0
      else
        t = pos(tri_tags(k))
      end if
      if (t == 0) then
        call set_error(err, trim(what)//' '//itoa((k - 1)/m + 1)//' names node tag '// &
          itoa(int(tri_tags(k)))//', which is not among the mesh nodes')
        return
      end if
      used(t) = .true.
    end do
    ! np.unique(tri): the used positions in ascending order, renumbered 1 .. np
    allocate(renum(n))
    renum = 0
    np = 0
    do k = 1, n
      if (.not. used(k)) cycle
      np = np + 1
      renum(k) = np
    end do
    allocate(x(nd, np), tri(m, ne))
    do k = 1, n
      if (renum(k) > 0) x(:, renum(k)) = xyz(3*k - 2:3*k - 3 + nd)
    end do
    do e = 1, ne
      do j = 1, m
        tri(j, e) = renum(pos(tri_tags(m*(e - 1) + j)))
      end do
      if (m == 3) then
        ! counter-clockwise
        if (triangle_area(x, tri(:, e)) < 0.0_wp) tri(2:3, e) = tri([3, 2], e)
      else
        ! a positive volume
        v = tet_volume(x, tri(:, e))
        if (.not. (abs(v) > 0.0_wp)) then
          call set_error(err, 'tetrahedron '//itoa(e)//' of the mesh has no volume (a '// &
            'degenerate element)')
          return
        end if
        if (v < 0.0_wp) tri(3:4, e) = tri([4, 3], e)
      end if
    end do
    ! a 3D mesh numbered in space (a file's blocks of rows then lie in small boxes)
    if (m == 4) call space_order(x, tri)
  end subroutine mesh_from_tags

  !> The nodes x (3, np) and tetrahedra tet (4, ne) of a mesh numbered in space, as
  !! tools/mesh_body.py's space_order numbers them (the same doubles, the same order):
  !! the nodes sorted (stably) by the Morton key of their cell in a grid of 1024 cubes a
  !! side over the mesh's extent (cell c_a = floor((x_a - lo_a)/e*1024), at most 1023, e
  !! the largest extent; the key c_x, c_y, c_z's bits interleaved, x's lowest), then the
  !! tetrahedra (stably) by their smallest node, each keeping its nodes' order (its volume
  !! its sign). So consecutive rows of a file lie close together, and a rank reading its
  !! part of one reads a few blocks of it (mesh_index, tet_file_m); and a share of the
  !! numbering is a compact piece of the body.
  subroutine space_order(x, tet)
    real(wp), intent(inout) :: x(:, :)
    integer, intent(inout) :: tet(:, :)
    integer, allocatable :: key(:), idx(:), renum(:)
    real(wp) :: lo(3), ext
    integer :: i, a, bit, c, np, ne
    np = size(x, 2)
    ne = size(tet, 2)
    lo = minval(x, 2)
    ext = maxval(maxval(x, 2) - lo)
    allocate(key(np), idx(np))
    key = 0
    if (ext > 0.0_wp) then
      do i = 1, np
        do a = 1, 3
          c = min(1023, int(((x(a, i) - lo(a))/ext)*1024.0_wp))
          do bit = 0, 9
            if (btest(c, bit)) key(i) = ibset(key(i), 3*bit + a - 1)
          end do
        end do
      end do
    end if
    call radix_index(key, idx)
    x = x(:, idx)
    allocate(renum(np))
    renum(idx) = [(i, i = 1, np)]
    do i = 1, ne
      tet(:, i) = renum(tet(:, i))
    end do
    deallocate(key, idx)
    allocate(key(ne), idx(ne))
    key = minval(tet, 1)
    call radix_index(key, idx)
    tet = tet(:, idx)
  end subroutine space_order

  !> The index of a tetrahedral mesh file (tools/mesh_body.py --3d writes the same): nbox
  !! (6, nb) the box (lo, hi) of each block of index_rows nodes (the last block the rest),
  !! tbox (6, nt) the box of the nodes of each block of index_rows tetrahedra.
  subroutine mesh_index(x, tet, nbox, tbox)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tet(:, :)
    real(wp), allocatable, intent(out) :: nbox(:, :), tbox(:, :)
    integer :: i, k, l
    allocate(nbox(6, (size(x, 2) + index_rows - 1)/index_rows))
    allocate(tbox(6, (size(tet, 2) + index_rows - 1)/index_rows))
    nbox(1:3, :) = huge(1.0_wp)
    nbox(4:6, :) = -huge(1.0_wp)
    do i = 1, size(x, 2)
      k = (i - 1)/index_rows + 1
      nbox(1:3, k) = min(nbox(1:3, k), x(:, i))
      nbox(4:6, k) = max(nbox(4:6, k), x(:, i))
    end do
    tbox(1:3, :) = huge(1.0_wp)
    tbox(4:6, :) = -huge(1.0_wp)
    do i = 1, size(tet, 2)
      k = (i - 1)/index_rows + 1
      do l = 1, 4
        tbox(1:3, k) = min(tbox(1:3, k), x(:, tet(l, i)))
        tbox(4:6, k) = max(tbox(4:6, k), x(:, tet(l, i)))
      end do
    end do
  end subroutine mesh_index

  !> Signed volume of tetrahedron t of x (3, :): positive when node 4 lies on the side of
  !! the face (1, 2, 3) that its right-hand normal points to.
  pure real(wp) function tet_volume(x, t) result(v)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: t(4)
    real(wp) :: e1(3), e2(3), e3(3)
    e1 = x(:, t(2)) - x(:, t(1))
    e2 = x(:, t(3)) - x(:, t(1))
    e3 = x(:, t(4)) - x(:, t(1))
    v = (e1(1)*(e2(2)*e3(3) - e2(3)*e3(2)) - e1(2)*(e2(1)*e3(3) - e2(3)*e3(1)) &
      + e1(3)*(e2(1)*e3(2) - e2(2)*e3(1)))/6.0_wp
  end function tet_volume

  !> Signed area of triangle t of x, as the script's signed_areas computes it.
  pure real(wp) function triangle_area(x, t) result(a)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: t(3)
    a = 0.5_wp*((x(1, t(2)) - x(1, t(1)))*(x(2, t(3)) - x(2, t(1))) &
      - (x(1, t(3)) - x(1, t(1)))*(x(2, t(2)) - x(2, t(1))))
  end function triangle_area

  !> What the script writes for nodes x(2, np) and counter-clockwise triangles tri(3, ne):
  !! - vol(np): a third of every triangle's area at each node (the median-dual cell's area),
  !!   summed as numpy's add.at does: first nodes, then second nodes, then third nodes;
  !! - loop(np), order(np): the boundary loops, each the chain of directed triangle edges no
  !!   other triangle has reversed (material on the left), started at its smallest node,
  !!   loops in the order of those nodes; loop 0 for interior nodes;
  !! - ptr(np + 1), xy(2, nv): node i's median-dual cell, xy(:, ptr(i) : ptr(i+1)-1),
  !!   counter-clockwise: around the node, for each triangle (i, a, b) in turn the midpoint
  !!   of i-a and the centroid (then, at the end of a boundary node's fan, the midpoint of
  !!   i-b); a boundary node's cell starts at the node itself.
  !! A boundary that is not a set of closed loops, or a node whose triangles do not form one
  !! fan (a pinched mesh), is an error.
  subroutine mesh_body_arrays(x, tri, vol, loop, order, ptr, xy, err)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tri(:, :)
    real(wp), allocatable, intent(out) :: vol(:), xy(:, :)
    integer, allocatable, intent(out) :: loop(:), order(:), ptr(:)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: area(:)
    integer :: np, ne, k, e
    np = size(x, 2)
    ne = size(tri, 2)
    allocate(area(ne), vol(np))
    do e = 1, ne
      area(e) = triangle_area(x, tri(:, e))
    end do
    vol = 0.0_wp
    do k = 1, 3
      do e = 1, ne
        vol(tri(k, e)) = vol(tri(k, e)) + area(e)/3.0_wp
      end do
    end do
    call boundary_loops(np, tri, loop, order, err)
    if (allocated(err)) return
    call dual_cells(x, tri, ptr, xy, err)
  end subroutine mesh_body_arrays

  !> The script's boundary_loops: its dict of directed edges (first occurrence kept), the
  !! map nxt(a) = b of those whose reverse is not an edge (for two with the same a, the
  !! later wins), and the loops chained from the smallest node left.
  subroutine boundary_loops(np, tri, loop, order, err)
    integer, intent(in) :: np, tri(:, :)
    integer, allocatable, intent(out) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable :: key(:)
    integer, allocatable :: srt(:), ea(:), eb(:), nxt(:)
    logical, allocatable :: first(:)
    integer :: ne, m, k, e, j, lo, start, node, nloop, pos
    ne = size(tri, 2)
    m = 3*ne
    allocate(ea(m), eb(m), key(m), srt(m), first(m), nxt(np), loop(np), order(np))
    do e = 1, ne
      do k = 1, 3
        j = 3*(e - 1) + k
        ea(j) = tri(k, e)
        eb(j) = tri(modulo(k, 3) + 1, e)
        key(j) = int(ea(j), i64)*(np + 1) + eb(j)
      end do
    end do
    ! sort the edge keys (stable, by key then by position) to find duplicates and reverses
    call sort_keys(key, srt)
    first = .true.
    do j = 2, m
      if (key(srt(j)) == key(srt(j - 1))) first(srt(j)) = .false.
    end do
    nxt = 0
    do j = 1, m
      if (.not. first(j)) cycle
      if (has_key(int(eb(j), i64)*(np + 1) + ea(j))) cycle
      nxt(ea(j)) = eb(j)
    end do
    loop = 0
    order = 0
    nloop = 0
    do start = 1, np
      if (nxt(start) == 0) cycle
      nloop = nloop + 1
      pos = 0
      loop(start) = nloop
      order(start) = pos
      node = nxt(start)
      nxt(start) = 0
      do while (node /= start)
        pos = pos + 1
        loop(node) = nloop
        order(node) = pos
        if (nxt(node) == 0) then
          call set_error(err, 'the boundary is not a set of closed loops (a node where '// &
            'two boundary chains meet?)')
          return
        end if
        lo = nxt(node)
        nxt(node) = 0
        node = lo
      end do
    end do
  contains
    logical function has_key(kk)
      integer(i64), intent(in) :: kk
      integer :: a, b, c
      a = 1
      b = m
      has_key = .false.
      do while (a <= b)
        c = (a + b)/2
        if (key(srt(c)) == kk) then
          has_key = .true.
          return
        else if (key(srt(c)) < kk) then
          a = c + 1
        else
          b = c - 1
        end if
      end do
    end function has_key
  end subroutine boundary_loops

  !> srt: the positions of key in ascending order of key, equal keys by position (stable).
  subroutine sort_keys(key, srt)
    integer(i64), intent(in) :: key(:)
    integer, intent(out) :: srt(:)
    integer :: n, i
    n = size(key)
    ! a merge sort of the integer keys (sorting_m sorts reals, which could not tell keys
    ! beyond 2**53 apart)
    srt = [(i, i = 1, n)]
    if (n < 2) return
    call merge_sort(1, n)
  contains
    recursive subroutine merge_sort(lo, hi)
      integer, intent(in) :: lo, hi
      integer :: mid, p, q, r
      integer, allocatable :: tmp(:)
      if (hi - lo < 1) return
      mid = (lo + hi)/2
      call merge_sort(lo, mid)
      call merge_sort(mid + 1, hi)
      allocate(tmp(hi - lo + 1))
      p = lo
      q = mid + 1
      r = 0
      do while (p <= mid .and. q <= hi)
        r = r + 1
        if (key(srt(q)) < key(srt(p))) then
          tmp(r) = srt(q)
          q = q + 1
        else
          tmp(r) = srt(p)
          p = p + 1
        end if
      end do
      do while (p <= mid)
        r = r + 1
        tmp(r) = srt(p)
        p = p + 1
      end do
      do while (q <= hi)
        r = r + 1
        tmp(r) = srt(q)
        q = q + 1
      end do
      srt(lo:hi) = tmp
    end subroutine merge_sort
  end subroutine sort_keys

  !> The script's dual_cells (the docstring of mesh_body_arrays), with its dict semantics:
  !! for a repeated neighbour a in a node's fan the later triangle wins, the fan's start is
  !! the first a (in the order first seen) that is no triangle's b.
  subroutine dual_cells(x, tri, ptr, xy, err)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tri(:, :)
    integer, allocatable, intent(out) :: ptr(:)
    real(wp), allocatable, intent(out) :: xy(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: fptr(:), fa(:), fb(:), fe(:)
    real(wp), allocatable :: cen(:, :)
    integer :: np, ne, e, k, i, f, f0, nf, nv, a, seen, g
    logical :: boundary, found
    np = size(x, 2)
    ne = size(tri, 2)
    ! centroids, summed in numpy's order (x[t].mean(axis=0))
    allocate(cen(2, ne))
    do e = 1, ne
      cen(:, e) = ((x(:, tri(1, e)) + x(:, tri(2, e))) + x(:, tri(3, e)))/3.0_wp
    end do
    ! each node's fan: its triangles in triangle order (fe), as (a, b, triangle): a and b
    ! the triangle's next two nodes counter-clockwise from the fan's node
    call incidence_csr(tri, np, fptr, fe)
    allocate(fa(3*ne), fb(3*ne))
    do i = 1, np
      do f = fptr(i), fptr(i + 1) - 1
        e = fe(f)
        k = findloc(tri(:, e), i, dim=1)
        fa(f) = tri(modulo(k, 3) + 1, e)
        fb(f) = tri(modulo(k + 1, 3) + 1, e)
      end do
    end do
    ! the cells: a boundary node's has 2 nf + 2 vertices, an interior node's 2 nf
    nv = 0
    do i = 1, np
      nf = fptr(i + 1) - fptr(i)
      nv = nv + 2*nf + 2
    end do
    allocate(ptr(np + 1), xy(2, nv))
    ptr(1) = 1
    nv = 0
    do i = 1, np
      f0 = fptr(i)
      nf = fptr(i + 1) - f0
      ! starts: the a (first occurrences, in order) that are no b
      boundary = .false.
      a = fa(f0)
      do f = f0, f0 + nf - 1
        if (any(fa(f0:f - 1) == fa(f))) cycle
        if (any(fb(f0:f0 + nf - 1) == fa(f))) cycle
        boundary = .true.
        a = fa(f)
        exit
      end do
      if (boundary) call put(x(:, i))
      seen = 0
      do while (seen < nf)
        ! by_a[a]: the last triangle of the fan with this a
        found = .false.
        do g = f0 + nf - 1, f0, -1
          if (fa(g) == a) then
            found = .true.
            exit
          end if
        end do
        if (.not. found) exit
        call put(0.5_wp*(x(:, i) + x(:, a)))
        call put(cen(:, fe(g)))
        seen = seen + 1
        a = fb(g)
        if (.not. boundary .and. a == fa(f0)) exit
      end do
      if (boundary) call put(0.5_wp*(x(:, i) + x(:, a)))
      if (seen /= nf) then
        call set_error(err, 'node '//itoa(i)//': its triangles do not form one fan (a '// &
          'pinched mesh)')
        return
      end if
      ptr(i + 1) = nv + 1
    end do
    xy = xy(:, 1:nv)
  contains
    subroutine put(p)
      real(wp), intent(in) :: p(2)
      nv = nv + 1
      xy(:, nv) = p
    end subroutine put
  end subroutine dual_cells

  !> An element mesh's connectivity against its body (the one check of cst4_m's and tet4_m's
  !! tables): ndim = nd, ne >= 1 elements of nper nodes (cells(nper, ne)), every node
  !! number in 1..np. what names the elements in the message ('CST4 triangle', ...).
  subroutine check_cells(name, ndim, np, cells, ne, nper, nd, what, err)
    character(len=*), intent(in) :: name, what
    integer, intent(in) :: ndim, np, ne, nper, nd
    integer, allocatable, intent(in) :: cells(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer :: e
    if (ndim /= nd) then
      call set_error(err, "body '"//trim(name)//"': "//what//" elements need ndim = "// &
        itoa(nd)//", got "//itoa(ndim))
    else if (ne < 1 .or. .not. allocated(cells)) then
      call set_error(err, "body '"//trim(name)//"': the mesh has no "//what//" elements")
    else if (size(cells, 1) /= nper .or. size(cells, 2) /= ne) then
      call set_error(err, "body '"//trim(name)//"': the "//what//" connectivity is "// &
        itoa(size(cells, 1))//' x '//itoa(size(cells, 2))//', expected '//itoa(nper)// &
        ' x '//itoa(ne))
    else if (any(cells < 1 .or. cells > np)) then
      e = findloc(any(cells < 1 .or. cells > np, dim=1), .true., dim=1)
      call set_error(err, "body '"//trim(name)//"': "//what//" element "//itoa(e)// &
        ' names a node outside 1..'//itoa(np))
    end if
  end subroutine check_cells
end module mesh_cells_m
