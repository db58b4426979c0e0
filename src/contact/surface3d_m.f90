!> A 3D master's boundary surface for the gap and the normal of Section 5 in three
!! dimensions (issue 23, item 3): the body's facets (body_t%facets, triangles over its
!! particles, counter-clockwise from outside), and for a point p the closest point q on the
!! surface, the signed gap g = +-|p - q| (negative inside) and the outward normal.
!!
!! The sign comes from the angle-weighted pseudo-normal of the feature q lies on (Baerentzen
!! and Aanaes, IEEE TVCG 11 (2005)): the facet's normal inside a facet, the sum of the two
!! facets' normals on an edge, the angle-weighted sum of the facets' normals at a vertex.
!! With it the sign of (p - q) . n is the inside/outside of any point of a closed surface,
!! also where q is an edge or a vertex (a facet normal alone can give the wrong sign there,
!! at convex and concave edges alike). The closest point on a triangle is Ericson's
!! (Real-Time Collision Detection, 2005, Section 5.1.5), by the Voronoi regions of its
!! vertices, edges and face.
!!
!! Search: the facets are binned by their boxes on a uniform grid (cells about the mean
!! facet size, at most bin_cap cells a facet); a query visits the cells in rings of growing
!! Chebyshev distance r around p's cell and stops when the best distance found is below
!! r cells, closer than any facet outside the rings visited. The facet chosen is the
!! brute-force search's (the smallest squared distance, the lowest facet number among
!! equal ones): the stop is strict, so every facet not visited lies farther, and equal
!! distances compare by number. Within the rings a facet whose bounding sphere lies
!! strictly farther than the best distance so far is not examined (it can neither be
!! closer nor tie), and a ring visits only its shell's cells. A deforming master's surface
!! is moved each step by surface3d_update, which bins the facets again on the same cell
!! size (the grid's arrays grow only when it needs more cells or entries than it had).
module surface3d_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use sorting_m, only: sort_index, sorted_place
  use exact_sum_m, only: exact_sum_t, exact_add, exact_value
  use geometry_m, only: cross => cross3
  implicit none
  private
  public :: surface3d_t, surface3d_build, surface3d_update, surface3d_gap, surface3d_of
  public :: surface3d_vertices, surface3d_part, surface3d_longest

  type :: surface3d_t
    integer :: nf = 0
    integer, allocatable :: tri(:, :)        !< (3, nf) vertex numbers, CCW from outside
    !> the vertices: their numbers (nv, ascending; the particles the facets touch, not
    !! every particle of the body) and each facet's vertices' places among them (3, nf)
    integer, allocatable :: vid(:), tv(:, :)
    real(wp), allocatable :: x(:, :)         !< (3, nv) vertex positions (m)
    real(wp), allocatable :: fn(:, :)        !< (3, nf) unit facet normals
    real(wp), allocatable :: en(:, :, :)     !< (3, 3, nf) pseudo-normal of edge k of facet
                                             !! (from its vertex k to k + 1)
    real(wp), allocatable :: vn(:, :)        !< (3, nv) vertex pseudo-normals
    integer, allocatable :: partner(:, :)    !< (3, nf) the other facet of edge k of facet
                                             !! (0 in a subset without it: surface3d_of)
    !> a part of a larger surface (surface3d_part: a rank's at the set-up): its facets'
    !! numbers in the whole, ascending (partner then holds numbers in the whole, 0 for an
    !! edge whose other facet is not in the part); the whole's facets and vertices (a
    !! whole surface's own: nf and size(vid))
    integer, allocatable :: fid(:)
    integer :: nf_whole = 0, nv_whole = 0
    !> the bins: the grid's corner lo (m), its cell size (m) and cells per axis, and the
    !! facets whose boxes touch cell c, cfac(cptr(c) : cptr(c + 1) - 1) (c numbered x
    !! fastest from 1)
    real(wp) :: lo(3) = 0.0_wp, cell = 1.0_wp
    integer :: nc(3) = 1
    integer, allocatable :: cptr(:), cfac(:)
    !> each facet's bounding sphere in the current configuration: centre fc (3, nf) (m) and
    !! radius fr (nf) (m), grown by a relative 1e-9 and 1e-9 cells so that rounding never
    !! lets it cut the facet: the search skips a facet whose sphere lies farther than the
    !! best distance found (it cannot be closer, nor equal and win on its number)
    real(wp), allocatable :: fc(:, :), fr(:)
  end type surface3d_t

  !> The most grid cells per facet (the cell size grows for a sparse surface in a large box)
  integer, parameter :: bin_cap = 8

contains

  !> The surface of the facets tri (3, nf) over the vertices x (3, np): normals and the
  !! pseudo-normals of edges and vertices. at_vertices (.false. by default): x (3, nv)
  !! holds the facets' distinct vertices' positions only, in ascending number (a body no
  !! rank holds whole: its surface's vertices made from its recipe). lean (.false. by
  !! default): the facets, vertices, edge partners, positions and cell size only, without
  !! normals or bins (a whole surface on a rank before the split, which takes its subset
  !! from these and frees it: a quarter of the memory). err: an edge not shared by
  !! exactly two facets (the surface is not closed).
  subroutine surface3d_build(s, x, tri, err, at_vertices, lean)
    type(surface3d_t), intent(out) :: s
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tri(:, :)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: at_vertices, lean
    logical :: at_v, geometry
    at_v = .false.
    if (present(at_vertices)) at_v = at_vertices
    geometry = .true.
    if (present(lean)) geometry = .not. lean
    s%nf = size(tri, 2)
    s%tri = tri
    call vertices_of(s)
    if (at_v) then
      if (size(x, 2) /= size(s%vid)) error stop 'surface3d_build: x is not at the vertices'
      s%x = x
    else
      s%x = x(:, s%vid)
    end if
    if (geometry) allocate(s%fn(3, s%nf), s%en(3, 3, s%nf), s%vn(3, size(s%vid)))
    ! edges: each undirected edge (smaller, larger vertex) must appear in two facets
    call match_edges(tri, s%partner, err)
    if (allocated(err)) return
    ! the bins' cell size: the mean of the facets' longest edges in this configuration,
    ! their sum exact (so a part's, surface3d_part, is the same from the ranks' rows)
    s%cell = exact_value(surface3d_longest(s%x, s%tv))/real(max(s%nf, 1), wp)
    s%nf_whole = s%nf
    s%nv_whole = size(s%vid)
    if (geometry) call surface3d_refresh(s)
  end subroutine surface3d_build

  !> The facets tri (3, nf) (vertex numbers) of a larger closed surface, its facets fid
  !! (ascending) there, as a lean surface of their own (surface3d_build's lean: facets,
  !! vertices, positions, partners, cell; no normals or bins) over their vertices'
  !! positions x (3, nv) (surface3d_vertices(tri)'s, in that order): the part of a body's
  !! surface a rank's contact sides take at the set-up, every facet with a vertex in the
  !! rank's region. The partners are numbers in the whole surface: an edge both of whose
  !! vertices are among inner (ascending: the region's particles, all of whose facets are
  !! in tri) must be in two facets here, as surface3d_build checks of every edge; another
  !! gets 0 when its other facet is not here. cell, nf_whole and nv_whole: the whole
  !! surface's (found over the ranks).
  subroutine surface3d_part(s, x, tri, fid, inner, cell, nf_whole, nv_whole, err)
    type(surface3d_t), intent(out) :: s
    real(wp), intent(in) :: x(:, :), cell
    integer, intent(in) :: tri(:, :), fid(:), inner(:), nf_whole, nv_whole
    type(error_t), allocatable, intent(inout) :: err
    integer :: m, k
    s%nf = size(tri, 2)
    s%tri = tri
    s%fid = fid
    call vertices_of(s)
    if (size(x, 2) /= size(s%vid)) error stop 'surface3d_part: x is not at the vertices'
    s%x = x
    call match_edges(tri, s%partner, err, inner)
    if (allocated(err)) return
    do m = 1, s%nf
      do k = 1, 3
        if (s%partner(k, m) > 0) s%partner(k, m) = fid(s%partner(k, m))
      end do
    end do
    s%cell = cell
    s%nf_whole = nf_whole
    s%nv_whole = nv_whole
  end subroutine surface3d_part

  !> The exact sum of the longest edges of the facets tv (3, nf: places in x (3, :), m):
  !! the bins' cell size times the facets' count (surface3d_build), summed the same from
  !! the ranks' rows of the facets (surface3d_part's cell).
  function surface3d_longest(x, tv) result(a)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tv(:, :)
    type(exact_sum_t) :: a
    integer :: m
    do m = 1, size(tv, 2)
      call exact_add(a, max(norm2(x(:, tv(2, m)) - x(:, tv(1, m))), &
        norm2(x(:, tv(3, m)) - x(:, tv(2, m))), norm2(x(:, tv(1, m)) - x(:, tv(3, m)))))
    end do
  end function surface3d_longest

  !> Each edge's other facet among the facets tri (3, nf) (partner (3, nf): places in
  !! tri), by sorting the undirected edges (smaller, larger vertex): an edge must be in two
  !! facets (err: the surface is not closed), with inner (ascending vertex numbers) an
  !! edge both of whose vertices are among inner only (another, in one facet here, gets 0).
  subroutine match_edges(tri, partner, err, inner)
    integer, intent(in) :: tri(:, :)
    integer, allocatable, intent(out) :: partner(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: inner(:)
    integer :: m, k, a, b, ne, i, n
    integer, allocatable :: order(:), ea(:), eb(:), ef(:), ek(:)
    real(wp), allocatable :: key(:)
    real(wp) :: top
    logical :: whole
    allocate(partner(3, size(tri, 2)))
    partner = 0
    ne = 3*size(tri, 2)
    allocate(ea(ne), eb(ne), ef(ne), ek(ne), key(ne), order(ne))
    ! (any factor above the largest number orders the edges alike)
    top = 1.0_wp
    if (size(tri) > 0) top = real(maxval(tri) + 1, wp)
    i = 0
    do m = 1, size(tri, 2)
      do k = 1, 3
        i = i + 1
        a = tri(k, m)
        b = tri(modulo(k, 3) + 1, m)
        ea(i) = min(a, b)
        eb(i) = max(a, b)
        ef(i) = m
        ek(i) = k
        key(i) = real(ea(i), wp)*top + real(eb(i), wp)
      end do
    end do
    call sort_index(key, order)
    i = 1
    do while (i <= ne)
      ! (the run of facets of this edge)
      n = 1
      do while (i + n <= ne)
        if (key(order(i + n)) /= key(order(i))) exit
        n = n + 1
      end do
      whole = .true.
      if (present(inner)) whole = sorted_place(inner, ea(order(i))) > 0 .and. &
        sorted_place(inner, eb(order(i))) > 0
      if (n == 1 .and. whole .and. i == ne) then
        call set_error(err, 'the surface is not closed: an edge belongs to one facet')
        return
      end if
      if (n > 2 .or. (n == 1 .and. whole)) then
        call set_error(err, 'the surface is not closed: edge '//'of one or of three facets')
        return
      end if
      if (n == 2) then
        partner(ek(order(i)), ef(order(i))) = ef(order(i + 1))
        partner(ek(order(i + 1)), ef(order(i + 1))) = ef(order(i))
      end if
      i = i + n
    end do
  end subroutine match_edges

  !> Some facets of a larger surface as a surface of their own over the vertices'
  !! positions x (3, :) (m): a rank's share of a deforming master on ranks
  !! (contact_dist_sm: the facets whose three vertices the rank holds, in the whole
  !! surface's order). tri (3, nf): each facet's vertices' places in x; partner (3, nf):
  !! each edge's other facet's place among these, 0 when left out; cell: the whole
  !! surface's bins' cell size (m). A vertex or an edge whose facets are not all kept gets
  !! a partial pseudo-normal, so only a point whose closest point and the facets around
  !! that point's features are all kept gets the whole surface's gap, normal, facet
  !! (numbered among these, in the whole surface's order, so that ties fall the same way)
  !! and barycentric coordinates, to the bit.
  subroutine surface3d_of(tri, partner, cell, x, s)
    integer, intent(in) :: tri(:, :), partner(:, :)
    real(wp), intent(in) :: cell, x(:, :)
    type(surface3d_t), intent(inout) :: s
    integer :: n
    n = size(tri, 2)
    s%nf = n
    if (allocated(s%tri)) deallocate(s%tri, s%partner, s%fn, s%en)
    allocate(s%fn(3, n), s%en(3, 3, n))
    s%tri = tri
    s%partner = partner
    call vertices_of(s)
    if (allocated(s%vn)) deallocate(s%vn)
    allocate(s%vn(3, size(s%vid)))
    s%cell = cell
    call surface3d_update(s, x)
  end subroutine surface3d_of

  !> The distinct vertex numbers of the facets tri (3, nf), ascending, by sorting the
  !! facets' corners (no array over the body's particles, whose numbers they are).
  function surface3d_vertices(tri) result(vid)
    integer, intent(in) :: tri(:, :)
    integer, allocatable :: vid(:)
    real(wp), allocatable :: key(:)
    integer, allocatable :: order(:), c(:)
    integer :: i, n
    c = reshape(tri, [size(tri)])
    allocate(key(size(c)), order(size(c)), vid(size(c)))
    key = real(c, wp)
    call sort_index(key, order)
    n = 0
    do i = 1, size(c)
      if (n > 0) then
        if (vid(n) == c(order(i))) cycle
      end if
      n = n + 1
      vid(n) = c(order(i))
    end do
    vid = vid(1:n)
  end function surface3d_vertices

  !> The vertices of s's facets (s%tri): their numbers, ascending (vid), and each facet's
  !! vertices' places among them (tv), by sorting the facets' corners: no array over the
  !! body's particles, whose numbers they are.
  subroutine vertices_of(s)
    type(surface3d_t), intent(inout) :: s
    integer :: m, k
    if (allocated(s%vid)) deallocate(s%vid)
    s%vid = surface3d_vertices(s%tri)
    if (allocated(s%tv)) deallocate(s%tv)
    allocate(s%tv(3, s%nf))
    do m = 1, s%nf
      do k = 1, 3
        s%tv(k, m) = sorted_place(s%vid, s%tri(k, m))
      end do
    end do
  end subroutine vertices_of

  !> The facets binned by their boxes in the current configuration s%x (surface3d_m's
  !! header): the grid over the facets' box, cells of s%cell grown until there are at
  !! most bin_cap per facet.
  subroutine bin_facets(s)
    type(surface3d_t), intent(inout) :: s
    real(wp) :: hi(3), bl(3), bh(3), h
    integer :: m, i, j, k, c, ncell, il(3), ih(3), n
    ! (the box of the facets' vertices: a subset's vertex array holds other points too)
    s%lo = huge(1.0_wp)
    hi = -huge(1.0_wp)
    do m = 1, s%nf
      do k = 1, 3
        s%lo = min(s%lo, s%x(:, s%tv(k, m)))
        hi = max(hi, s%x(:, s%tv(k, m)))
      end do
    end do
    if (s%nf == 0) then
      s%lo = 0.0_wp
      hi = 0.0_wp
    end if
    h = s%cell
    if (.not. (h > 0.0_wp)) h = max(maxval(hi - s%lo), tiny(1.0_wp))
    do
      s%nc = max(1, ceiling((hi - s%lo)/h))
      if (real(s%nc(1), wp)*real(s%nc(2), wp)*real(s%nc(3), wp) <= &
        real(bin_cap, wp)*real(max(s%nf, 1), wp)) exit
      h = 1.5_wp*h
    end do
    s%cell = h
    ncell = s%nc(1)*s%nc(2)*s%nc(3)
    if (allocated(s%cptr)) then
      if (size(s%cptr) < ncell + 1) deallocate(s%cptr)
    end if
    if (.not. allocated(s%cptr)) allocate(s%cptr(ncell + 1))
    s%cptr(1:ncell + 1) = 0
    ! count, then fill (cptr(c + 1) counts cell c's facets, then becomes its start)
    do n = 1, 2
      do m = 1, s%nf
        bl = min(s%x(:, s%tv(1, m)), s%x(:, s%tv(2, m)), s%x(:, s%tv(3, m)))
        bh = max(s%x(:, s%tv(1, m)), s%x(:, s%tv(2, m)), s%x(:, s%tv(3, m)))
        il = cell_of(s, bl)
        ih = cell_of(s, bh)
        do k = il(3), ih(3)
          do j = il(2), ih(2)
            do i = il(1), ih(1)
              c = i + s%nc(1)*((j - 1) + s%nc(2)*(k - 1))
              if (n == 1) then
                s%cptr(c + 1) = s%cptr(c + 1) + 1
              else
                s%cfac(s%cptr(c)) = m
                s%cptr(c) = s%cptr(c) + 1
              end if
            end do
          end do
        end do
      end do
      if (n == 1) then
        s%cptr(1) = 1
        do c = 1, ncell
          s%cptr(c + 1) = s%cptr(c + 1) + s%cptr(c)
        end do
        if (allocated(s%cfac)) then
          if (size(s%cfac) < s%cptr(ncell + 1) - 1) deallocate(s%cfac)
        end if
        if (.not. allocated(s%cfac)) allocate(s%cfac(s%cptr(ncell + 1) - 1))
      end if
    end do
    ! the fill moved each cell's start to the next cell's: move them back
    do c = ncell, 2, -1
      s%cptr(c) = s%cptr(c - 1)
    end do
    s%cptr(1) = 1
    if (allocated(s%fr)) then
      if (size(s%fr) /= s%nf) deallocate(s%fc, s%fr)
    end if
    if (.not. allocated(s%fr)) allocate(s%fc(3, s%nf), s%fr(s%nf))
    do m = 1, s%nf
      s%fc(:, m) = (s%x(:, s%tv(1, m)) + s%x(:, s%tv(2, m)) + s%x(:, s%tv(3, m)))/3.0_wp
      h = 0.0_wp
      do k = 1, 3
        h = max(h, norm2(s%x(:, s%tv(k, m)) - s%fc(:, m)))
      end do
      s%fr(m) = h*(1.0_wp + 1.0e-9_wp) + 1.0e-9_wp*s%cell
    end do
  end subroutine bin_facets

  !> The grid cell (i, j, k) holding point p, clamped to the grid.
  pure function cell_of(s, p) result(ijk)
    type(surface3d_t), intent(in) :: s
    real(wp), intent(in) :: p(3)
    integer :: ijk(3)
    ijk = min(s%nc, max(1, 1 + floor((p - s%lo)/s%cell)))
  end function cell_of

  !> The normals and pseudo-normals of surface s (surface3d_build) at the vertices' new
  !! positions x (3, np) (m): a deforming master's surface, moved each step without
  !! allocating (its facets and their edge partners stay).
  subroutine surface3d_update(s, x)
    type(surface3d_t), intent(inout) :: s
    real(wp), intent(in) :: x(:, :)
    ! (the vertices' positions only, not every particle's)
    s%x = x(:, s%vid)
    call surface3d_refresh(s)
  end subroutine surface3d_update

  !> surface3d_update's normals, pseudo-normals and bins at the vertices' positions s%x.
  subroutine surface3d_refresh(s)
    type(surface3d_t), intent(inout) :: s
    integer :: m, k
    real(wp) :: e1(3), e2(3), ang, u(3), v(3)
    s%vn = 0.0_wp
    do m = 1, s%nf
      e1 = s%x(:, s%tv(2, m)) - s%x(:, s%tv(1, m))
      e2 = s%x(:, s%tv(3, m)) - s%x(:, s%tv(1, m))
      s%fn(:, m) = cross(e1, e2)
      s%fn(:, m) = s%fn(:, m)/norm2(s%fn(:, m))
      ! the facet's angle at each vertex weights its normal there
      do k = 1, 3
        u = s%x(:, s%tv(modulo(k, 3) + 1, m)) - s%x(:, s%tv(k, m))
        v = s%x(:, s%tv(modulo(k + 1, 3) + 1, m)) - s%x(:, s%tv(k, m))
        ang = acos(max(-1.0_wp, min(1.0_wp, dot_product(u, v)/(norm2(u)*norm2(v)))))
        s%vn(:, s%tv(k, m)) = s%vn(:, s%tv(k, m)) + ang*s%fn(:, m)
      end do
    end do
    ! an edge's pseudo-normal: the sum of its two facets' normals (in a subset, an edge
    ! whose other facet is left out takes its one facet's)
    do m = 1, s%nf
      do k = 1, 3
        if (s%partner(k, m) > 0) then
          s%en(:, k, m) = s%fn(:, m) + s%fn(:, s%partner(k, m))
        else
          s%en(:, k, m) = s%fn(:, m)
        end if
      end do
    end do
    call bin_facets(s)
  end subroutine surface3d_refresh

  !> The closest point of surface s to p: the signed gap g (m, < 0 inside), the outward unit
  !! normal nrm ((p - q)/|p - q| turned outward; the feature's pseudo-normal when p lies on
  !! the surface), the facet jf and the barycentric coordinates bary of q on it. every
  !! (optional, .false. by default): search every facet instead of the bins (the reference
  !! the bins must give bit for bit, test_surface3d).
  !! Self-contact: with xr (3, np) (the reference positions of the vertices), xc and rex, a
  !! facet is left out when one of its vertices lies within rex of xc in the reference
  !! configuration (the point's own neighbourhood, Sections 1 and 7), or within the
  !! vertex's own radius rexv (np) when given, the larger (the symmetric neighbour relation
  !! of det(M)'s, rk_cloud_m cloud_set_reference); the sign still comes from the whole
  !! surface's pseudo-normals.
  pure subroutine surface3d_gap(s, p, g, nrm, jf, bary, every, xr, xc, rex, sure, rexv)
    type(surface3d_t), intent(in) :: s
    real(wp), intent(in) :: p(3)
    real(wp), intent(out) :: g, nrm(3), bary(3)
    integer, intent(out) :: jf
    logical, intent(in), optional :: every
    real(wp), intent(in), optional :: xr(:, :), xc(3), rex
    !> with the exclusion: is the sign of g sure? The pseudo-normal tells inside from
    !! outside for the closest point of the whole surface, or of the facets around its
    !! feature; when q lies on an edge or a vertex one of whose facets was left out, p may
    !! lie on the outer side of the facets kept and still get g < 0 (at a fold's tip,
    !! beside the end of another layer): sure is then .false. (.true. without exclusion)
    logical, intent(out), optional :: sure
    real(wp), intent(in), optional :: rexv(:)
    integer :: m, rbest, r, i, j, k, c, l, ijk(3), rmax, istep
    real(wp) :: best, qbest(3), pn(3), dist
    logical :: excl
    excl = present(xr) .and. present(xc) .and. present(rex)
    best = huge(1.0_wp)
    jf = 0
    rbest = 0
    bary = 0.0_wp
    qbest = p
    ijk = cell_of(s, p)
    rmax = maxval(max(ijk - 1, s%nc - ijk))
    if (present(every)) then
      if (every) then
        rmax = -1
        do m = 1, s%nf
          if (excl) then
            if (near_vertex(m)) cycle
          end if
          call try_facet(s, p, m, best, jf, qbest, bary, rbest)
        end do
      end if
    end if
    ! rings of cells at Chebyshev distance r from p's cell; every facet outside rings
    ! 0 .. r lies at least r cells from p (also from a p outside the grid: its cell is
    ! clamped), so the search stops once the best distance is strictly below that
    do r = 0, rmax
      do k = max(1, ijk(3) - r), min(s%nc(3), ijk(3) + r)
        do j = max(1, ijk(2) - r), min(s%nc(2), ijk(2) + r)
          ! (off the shell in y and z, only the shell's two cells in x: i steps by 2r)
          istep = 1
          if (max(abs(j - ijk(2)), abs(k - ijk(3))) < r) istep = 2*r
          do i = ijk(1) - r, ijk(1) + r, istep
            if (i < 1 .or. i > s%nc(1)) cycle
            c = i + s%nc(1)*((j - 1) + s%nc(2)*(k - 1))
            do l = s%cptr(c), s%cptr(c + 1) - 1
              ! (the sphere test first: cheaper than the exclusion and the closest point,
              ! it leaves out most facets once one is found; the brute-force search above,
              ! every, makes no such test and must give the same facet, test_surface3d)
              if (skip_facet(s, p, s%cfac(l), best)) cycle
              if (excl) then
                if (near_vertex(s%cfac(l))) cycle
              end if
              call try_facet(s, p, s%cfac(l), best, jf, qbest, bary, rbest)
            end do
          end do
        end do
      end do
      if (jf > 0 .and. best < (real(r, wp)*s%cell)**2) exit
    end do
    g = huge(1.0_wp)
    nrm = 0.0_wp
    if (present(sure)) sure = .true.
    if (jf == 0) return
    if (present(sure) .and. excl) sure = feature_kept()
    ! the pseudo-normal of the feature: region 0 the face, 1-3 vertex k, 4-6 edge k
    select case (rbest)
    case (1:3)
      pn = s%vn(:, s%tv(rbest, jf))
    case (4:6)
      pn = s%en(:, rbest - 3, jf)
    case default
      pn = s%fn(:, jf)
    end select
    dist = sqrt(best)
    g = dist
    if (dot_product(p - qbest, pn) < 0.0_wp) g = -dist
    if (dist > 0.0_wp) then
      nrm = (p - qbest)/dist
      if (g < 0.0_wp) nrm = -nrm
    else
      nrm = pn/norm2(pn)
    end if

  contains

    !> Are all the facets around the closest point's feature kept (none left out by the
    !! exclusion)? The face: its facet; an edge: its two facets; a vertex: the fan of facets
    !! around it, walked across the edges from it (a facet whose edge partner is missing, in
    !! a rank's subset, ends the walk: the ranks hold every facet around a feature they use).
    pure logical function feature_kept() result(kept)
      integer :: v, mm, kk, n
      kept = .true.
      select case (rbest)
      case (4:6)
        mm = s%partner(rbest - 3, jf)
        if (mm > 0) kept = .not. near_vertex(mm)
      case (1:3)
        v = s%tri(rbest, jf)
        mm = jf
        kk = rbest
        do n = 1, 4*s%nf
          ! leave facet mm across its edge from v to the next vertex; in the next facet
          ! (oriented alike) that edge ends at v, so its edge from v is the next to cross
          mm = s%partner(kk, mm)
          if (mm == 0 .or. mm == jf) exit
          if (near_vertex(mm)) then
            kept = .false.
            exit
          end if
          kk = findloc(s%tri(:, mm), v, dim=1)
        end do
      end select
    end function feature_kept

    !> Has facet m a vertex within rex (or its own rexv, the larger) of xc in the
    !! reference configuration?
    pure logical function near_vertex(m)
      integer, intent(in) :: m
      integer :: kk, v
      real(wp) :: r
      near_vertex = .false.
      do kk = 1, 3
        v = s%tri(kk, m)
        r = rex
        if (present(rexv)) r = max(rex, rexv(v))
        if (sum((xr(:, v) - xc)**2) < r*r) then
          near_vertex = .true.
          return
        end if
      end do
    end function near_vertex
  end subroutine surface3d_gap

  !> Facet m of s against the best so far for point p (squared distance best, facet jf,
  !! closest point qbest, its barycentric coordinates bary and Voronoi region rbest): the
  !! smallest squared distance wins, then the lowest facet number (the brute-force search's
  !! choice, whatever order the bins give).
  pure subroutine try_facet(s, p, m, best, jf, qbest, bary, rbest)
    type(surface3d_t), intent(in) :: s
    real(wp), intent(in) :: p(3)
    integer, intent(in) :: m
    real(wp), intent(inout) :: best, qbest(3), bary(3)
    integer, intent(inout) :: jf, rbest
    real(wp) :: q(3), bb(3), d2
    integer :: region
    call closest_on_triangle(p, s%x(:, s%tv(1, m)), s%x(:, s%tv(2, m)), &
      s%x(:, s%tv(3, m)), q, bb, region)
    d2 = sum((p - q)**2)
    if (d2 < best .or. (d2 == best .and. m < jf)) then
      best = d2
      jf = m
      qbest = q
      bary = bb
      rbest = region
    end if
  end subroutine try_facet

  !> Can facet m of s be left out for p, the best squared distance so far being best? Its
  !! bounding sphere lies strictly farther than sqrt(best) (s%fr is grown against rounding).
  pure logical function skip_facet(s, p, m, best) result(skip)
    type(surface3d_t), intent(in) :: s
    real(wp), intent(in) :: p(3), best
    integer, intent(in) :: m
    skip = .false.
    if (.not. (best < huge(1.0_wp))) return
    skip = sum((p - s%fc(:, m))**2) > (s%fr(m) + sqrt(best))**2
  end function skip_facet

  !> The point q of triangle (a, b, c) closest to p, its barycentric coordinates (of a, b,
  !! c) and its Voronoi region: 0 the face, k = 1, 2, 3 vertex k, 3 + k the edge from vertex
  !! k to vertex k + 1 (Ericson 2005, 5.1.5).
  pure subroutine closest_on_triangle(p, a, b, c, q, bary, region)
    real(wp), intent(in) :: p(3), a(3), b(3), c(3)
    real(wp), intent(out) :: q(3), bary(3)
    integer, intent(out) :: region
    real(wp) :: ab(3), ac(3), ap(3), bp(3), cp(3), d1, d2, d3, d4, d5, d6, va, vb, vc, &
      v, w, den
    ab = b - a
    ac = c - a
    ap = p - a
    d1 = dot_product(ab, ap)
    d2 = dot_product(ac, ap)
    if (d1 <= 0.0_wp .and. d2 <= 0.0_wp) then
      q = a
      bary = [1.0_wp, 0.0_wp, 0.0_wp]
      region = 1
      return
    end if
    bp = p - b
    d3 = dot_product(ab, bp)
    d4 = dot_product(ac, bp)
    if (d3 >= 0.0_wp .and. d4 <= d3) then
      q = b
      bary = [0.0_wp, 1.0_wp, 0.0_wp]
      region = 2
      return
    end if
    vc = d1*d4 - d3*d2
    if (vc <= 0.0_wp .and. d1 >= 0.0_wp .and. d3 <= 0.0_wp) then
      v = d1/(d1 - d3)
      q = a + v*ab
      bary = [1.0_wp - v, v, 0.0_wp]
      region = 4          ! edge a-b
      return
    end if
    cp = p - c
    d5 = dot_product(ab, cp)
    d6 = dot_product(ac, cp)
    if (d6 >= 0.0_wp .and. d5 <= d6) then
      q = c
      bary = [0.0_wp, 0.0_wp, 1.0_wp]
      region = 3
      return
    end if
    vb = d5*d2 - d1*d6
    if (vb <= 0.0_wp .and. d2 >= 0.0_wp .and. d6 <= 0.0_wp) then
      w = d2/(d2 - d6)
      q = a + w*ac
      bary = [1.0_wp - w, 0.0_wp, w]
      region = 6          ! edge c-a (vertex 3 to vertex 1)
      return
    end if
    va = d3*d6 - d5*d4
    if (va <= 0.0_wp .and. (d4 - d3) >= 0.0_wp .and. (d5 - d6) >= 0.0_wp) then
      w = (d4 - d3)/((d4 - d3) + (d5 - d6))
      q = b + w*(c - b)
      bary = [0.0_wp, 1.0_wp - w, w]
      region = 5          ! edge b-c
      return
    end if
    den = 1.0_wp/(va + vb + vc)
    v = vb*den
    w = vc*den
    q = a + ab*v + ac*w
    bary = [1.0_wp - v - w, v, w]
    region = 0
  end subroutine closest_on_triangle
end module surface3d_m
