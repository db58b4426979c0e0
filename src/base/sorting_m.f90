!> Index sort (heap sort, O(n log n), no recursion, no allocation beyond the result).
module sorting_m
  use kinds_m, only: wp
  implicit none
  private
  public :: sort_index, sorted_place, radix_index, incidence_csr

contains

  !> idx such that key(idx) is non-decreasing.
  pure subroutine sort_index(key, idx)
    real(wp), intent(in) :: key(:)
    integer, intent(out) :: idx(:)
    integer :: n, i, t, last
    n = size(key)
    idx = [(i, i = 1, n)]
    do i = n/2, 1, -1
      call sift(key, idx, i, n)
    end do
    do last = n, 2, -1
      t = idx(1)
      idx(1) = idx(last)
      idx(last) = t
      call sift(key, idx, 1, last - 1)
    end do
  end subroutine sort_index

  pure subroutine sift(key, idx, start, fin)
      real(wp), intent(in) :: key(:)
      integer, intent(inout) :: idx(:)
      integer, intent(in) :: start, fin
      integer :: root, child, tmp
      root = start
      do
        child = 2*root
        if (child > fin) exit
        if (child < fin) then
          if (key(idx(child + 1)) > key(idx(child))) child = child + 1
        end if
        if (key(idx(root)) >= key(idx(child))) exit
        tmp = idx(root)
        idx(root) = idx(child)
        idx(child) = tmp
        root = child
      end do
  end subroutine sift

  !> idx such that a(idx) is non-decreasing, for non-negative integers: a stable radix sort
  !! in two passes of 16 bits (O(n), where sort_index's heap sort is O(n log n) and walks
  !! memory at random: the sets of node numbers a mesh file read per part sorts, tet_file_m).
  pure subroutine radix_index(a, idx)
    integer, intent(in) :: a(:)
    integer, intent(out) :: idx(:)
    integer, allocatable :: tmp(:), cnt(:)
    integer :: n, i, pass, d, shift
    n = size(a)
    allocate(tmp(n), cnt(0:65536))
    idx = [(i, i = 1, n)]
    do pass = 1, 2
      shift = 16*(pass - 1)
      cnt = 0
      do i = 1, n
        d = iand(ishft(a(idx(i)), -shift), 65535)
        cnt(d + 1) = cnt(d + 1) + 1
      end do
      do d = 1, 65536
        cnt(d) = cnt(d) + cnt(d - 1)
      end do
      do i = 1, n
        d = iand(ishft(a(idx(i)), -shift), 65535)
        cnt(d) = cnt(d) + 1
        tmp(cnt(d)) = idx(i)
      end do
      idx = tmp
    end do
  end subroutine radix_index

  !> The elements of each node of a mesh (a counting sort of the element numbers by node):
  !! node i's are idx(ptr(i) : ptr(i + 1) - 1), ascending; conn (nv, ne) the elements'
  !! nodes, 1 ... nn.
  pure subroutine incidence_csr(conn, nn, ptr, idx)
    integer, intent(in) :: conn(:, :), nn
    integer, allocatable, intent(out) :: ptr(:), idx(:)
    integer :: e, k, i
    allocate(ptr(nn + 1), idx(size(conn)))
    ptr = 0
    do e = 1, size(conn, 2)
      do k = 1, size(conn, 1)
        ptr(conn(k, e) + 1) = ptr(conn(k, e) + 1) + 1
      end do
    end do
    ptr(1) = 1
    do i = 1, nn
      ptr(i + 1) = ptr(i + 1) + ptr(i)
    end do
    do e = 1, size(conn, 2)
      do k = 1, size(conn, 1)
        i = conn(k, e)
        idx(ptr(i)) = e
        ptr(i) = ptr(i) + 1
      end do
    end do
    do i = nn, 1, -1
      ptr(i + 1) = ptr(i)
    end do
    ptr(1) = 1
  end subroutine incidence_csr

  !> The place k of v in the ascending array a (a(k) == v), 0 when v is not in it: a
  !! bisection, so that a map from global numbers to local places needs no array over the
  !! global numbering.
  pure integer function sorted_place(a, v) result(k)
    integer, intent(in) :: a(:), v
    integer :: lo, hi, mid
    lo = 1
    hi = size(a)
    k = 0
    do while (lo <= hi)
      mid = lo + (hi - lo)/2
      if (a(mid) == v) then
        k = mid
        return
      else if (a(mid) < v) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function sorted_place
end module sorting_m
