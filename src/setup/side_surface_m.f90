!> The part of a 3D body's closed surface that a rank's contact sides take at the set-up of
!! mfcd_mpi, when no rank holds the body whole (an extruded body made per rank, a mesh file
!! read per part) and the body is a deforming master or in a self-contact: every facet with
!! a vertex among the rank's region of the body, with its number in the whole surface, its
!! edges' partners (numbers in the whole surface), its vertices' positions, and the whole
!! surface's bins' cell size and counts. That is all the sides read of the surface before
!! the split cuts them to the rank's own particles (contact_pair_m self_candidates, the
!! split's vertex owners, contact_dist_sm own_facets: the facets with an own vertex and
!! their partners), so no rank holds the whole surface.
!!
!! Found over the ranks from the rows of the surface each rank holds (body_t facet0 ...):
!! each row goes to the home of each of its vertices (the rank whose share_first range of
!! the particle numbers holds it), so a vertex's home lists every facet around it; each
!! rank asks the homes of its region's particles for theirs. The cell size, the mean of
!! the facets' longest edges, is an exact sum over the rows (surface3d_m
!! surface3d_longest), the serial surface3d_build's to the bit. Every message is
!! part-sized: a rank sends its rows (three times), its region's numbers, and the facets
!! it is asked for.
module side_surface_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use rank_comm_m, only: rank_comm_t, share_first, share_rank, route_columns
  use sorting_m, only: radix_index, sorted_place
  use exact_sum_m, only: exact_sum_t, exact_allmerge, exact_value
  use body_m, only: body_t
  use generators_m, only: extruded_particle
  use tet_file_m, only: tet_file_positions
  use surface3d_m, only: surface3d_t, surface3d_part, surface3d_vertices, surface3d_longest
  implicit none
  private
  public :: side_surface, vertex_positions

contains

  !> The part s of body b's closed surface (surface3d_m surface3d_part) with every facet
  !! that has a vertex among inner (ascending particle numbers of the whole body: the
  !! rank's region of it), from the rows of the facets the ranks hold (b%facets, the
  !! facets facet0 ... of nfacets; facet0 = 0: every rank holds them all, and each takes
  !! its share_first rows). b: the rank's share of the body, made from its recipe or read
  !! from its mesh file (the vertices' positions are made or read here). An error (the
  !! file, a surface that is not closed) is this rank's; the ranks go through every
  !! exchange all the same. Collective.
  subroutine side_surface(comm, b, inner, s, err)
    class(rank_comm_t), intent(inout) :: comm
    type(body_t), intent(in) :: b
    integer, intent(in) :: inner(:)
    type(surface3d_t), intent(out) :: s
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: rows(:, :), rv(:), tv(:, :), dest(:), buf(:, :), dir(:, :), &
      src(:), req(:, :), got(:, :), order(:), tri(:, :), fid(:), vid(:)
    real(wp), allocatable :: xr(:, :), x(:, :)
    type(exact_sum_t) :: acc
    integer(i64) :: nvw(1)
    integer :: f0, nfw, n, j, k, i, m, q, p, me, np
    me = comm%me
    np = comm%nranks
    if (size(inner) > 1) then
      if (any(inner(2:) <= inner(:size(inner) - 1))) error stop &
        'side_surface: inner is not ascending'
    end if
    ! the rows this rank holds
    nfw = b%nfacets
    if (b%facet0 > 0) then
      f0 = b%facet0
      rows = b%facets
    else
      nfw = size(b%facets, 2)
      f0 = share_first(nfw, me, np)
      rows = b%facets(:, f0:share_first(nfw, me + 1, np) - 1)
    end if
    n = size(rows, 2)
    ! the cell size: the rows' longest edges, summed exactly over the ranks
    rv = surface3d_vertices(rows)
    call vertex_positions(b, rv, xr, err)
    if (.not. allocated(err)) then
      allocate(tv(3, n))
      do j = 1, n
        do k = 1, 3
          tv(k, j) = sorted_place(rv, rows(k, j))
        end do
      end do
      acc = surface3d_longest(xr, tv)
      deallocate(tv)
    end if
    deallocate(xr, rv)
    acc = exact_allmerge(acc, comm)
    ! each row to the homes of its vertices: (vertex, facet, its three vertices)
    allocate(dest(3*n), buf(5, 3*n))
    m = 0
    do j = 1, n
      do k = 1, 3
        ! (a vertex once a facet)
        if (any(rows(k, j) == rows(1:k - 1, j))) cycle
        m = m + 1
        dest(m) = share_rank(rows(k, j), b%np, np)
        buf(:, m) = [rows(k, j), f0 + j - 1, rows(:, j)]
      end do
    end do
    call route_columns(comm, dest(1:m), buf(:, 1:m), dir)
    deallocate(dest, buf, rows)
    ! the home's list, by vertex (radix_index is stable: each vertex's facets ascending
    ! in rank order, then row order), and its distinct vertices counted over the ranks
    allocate(order(size(dir, 2)))
    call radix_index(dir(1, :), order)
    dir = dir(:, order)
    deallocate(order)
    nvw = 0
    do i = 1, size(dir, 2)
      if (i > 1) then
        if (dir(1, i) == dir(1, i - 1)) cycle
      end if
      nvw = nvw + 1
    end do
    call comm%sum_i8(nvw)
    ! the region's particles to their homes, which answer with their facets
    allocate(dest(size(inner)))
    do i = 1, size(inner)
      dest(i) = share_rank(inner(i), b%np, np)
    end do
    call route_columns(comm, dest, reshape(inner, [1, size(inner)]), req, src)
    deallocate(dest)
    ! (the answers: each facet listed at a vertex asked for, to the rank that asked)
    m = 0
    do p = 1, 2
      do i = 1, size(req, 2)
        j = first_at(req(1, i))
        if (j == 0) cycle
        do while (j <= size(dir, 2))
          if (dir(1, j) /= req(1, i)) exit
          m = m + 1
          if (p == 2) then
            dest(m) = src(i)
            buf(:, m) = dir(2:5, j)
          end if
          j = j + 1
        end do
      end do
      if (p == 1) allocate(dest(m), buf(4, m))
      m = 0
    end do
    deallocate(dir, req, src)
    call route_columns(comm, dest, buf, got)
    deallocate(dest, buf)
    ! the facets asked for, once each, ascending
    allocate(order(size(got, 2)))
    call radix_index(got(1, :), order)
    allocate(fid(size(order)), tri(3, size(order)))
    n = 0
    do i = 1, size(order)
      q = order(i)
      if (n > 0) then
        if (got(1, q) == fid(n)) cycle
      end if
      n = n + 1
      fid(n) = got(1, q)
      tri(:, n) = got(2:4, q)
    end do
    fid = fid(1:n)
    tri = tri(:, 1:n)
    deallocate(got, order)
    if (allocated(err)) return
    vid = surface3d_vertices(tri)
    call vertex_positions(b, vid, x, err)
    if (allocated(err)) return
    call surface3d_part(s, x, tri, fid, inner, exact_value(acc)/real(max(nfw, 1), wp), &
      nfw, int(nvw(1)), err)

  contains

    !> The first place in dir (by vertex) of vertex v, 0 when it has none
    integer function first_at(v) result(j)
      integer, intent(in) :: v
      integer :: lo, hi, mid
      lo = 1
      hi = size(dir, 2)
      j = 0
      do while (lo <= hi)
        mid = (lo + hi)/2
        if (dir(1, mid) < v) then
          lo = mid + 1
        else
          if (dir(1, mid) == v) j = mid
          hi = mid - 1
        end if
      end do
    end function first_at
  end subroutine side_surface

  !> The reference positions x (3, size(g)) (m) of the particles g (ascending) of body b,
  !! the rank's share of a body no rank holds whole: made from its recipe (generators_m
  !! extruded_particle) or read from its mesh file (tet_file_m tet_file_positions), as the
  !! whole body has them, to the bit.
  subroutine vertex_positions(b, g, x, err)
    type(body_t), intent(in) :: b
    integer, intent(in) :: g(:)
    real(wp), allocatable, intent(out) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer :: j, i, k
    real(wp) :: vol
    logical :: bnd
    if (allocated(b%mfile)) then
      call tet_file_positions(b, g, x, err)
      return
    end if
    if (.not. allocated(b%ext)) then
      call set_error(err, "body '"//trim(b%name)//"': no recipe to make its surface's "// &
        "vertices from")
      allocate(x(3, 0))
      return
    end if
    allocate(x(3, size(g)))
    do j = 1, size(g)
      i = g(j) - 1
      k = i/b%ext%n2
      call extruded_particle(b%ext, i - k*b%ext%n2 + 1, k + 1, x(:, j), vol, bnd)
    end do
  end subroutine vertex_positions
end module side_surface_m
