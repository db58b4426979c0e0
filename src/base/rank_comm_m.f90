!> The ranks of a run (doc/parallel.md) as the layers below the program see them, without
!! naming MPI: reductions, broadcasts, the allgather of contact's ghost refresh,
!! point-to-point messages to chosen ranks and an all-to-all of counts. The MPI build
!! extends it (mpi_comm_m, library mfcd_parallel); single_rank_t is the one-rank case, a
!! serial run's, whose collectives leave every value as it is.
module rank_comm_m
  use kinds_m, only: wp, i64
  implicit none
  private
  public :: rank_comm_t, single_rank_t, share_first, share_rank, kth_smallest, route_columns

  !> The ranks: this one (me, from 0) of nranks. Every procedure is collective.
  type, abstract :: rank_comm_t
    integer :: me = 0
    integer :: nranks = 1
    integer(i64) :: bytes = 0   !< bytes this rank sent through sparse_exchange
  contains
    !> v(:) becomes its largest value over the ranks, entry by entry.
    procedure(max_i), deferred :: max_real
    !> v(:) becomes its sum over the ranks, entry by entry.
    procedure(max_i), deferred :: sum_real
    !> v(:) becomes its sum over the ranks, entry by entry.
    procedure(sum_i8_i), deferred :: sum_i8
    !> v(:) becomes its smallest value over the ranks, entry by entry.
    procedure(min_int_i), deferred :: min_int
    !> text becomes rank from's text (its length too).
    procedure(bcast_text_i), deferred :: bcast_text
    !> all(:, r + 1) becomes rank r's mine(:) (the same length on every rank).
    procedure(allgather_i), deferred :: allgather_real
    !> got(r + 1) becomes rank r's mine(me + 1) (one count to each rank and one from each:
    !! P numbers a rank, where an allgather of every rank's counts holds P^2).
    procedure(alltoall_i), deferred :: alltoall_int
    !> Messages between chosen ranks: sbuf(sptr(k) : sptr(k+1) - 1) goes to rank to(k);
    !! one message (of any length, empty too) comes from each rank of from(:), placed in
    !! rbuf(rptr(k) : rptr(k+1) - 1) in from's order (rbuf grows when short). Each rank of
    !! to(:) must list this rank in its from(:), and no rank lists itself.
    procedure(sparse_i), deferred :: sparse_exchange
  end type rank_comm_t

  abstract interface
    subroutine max_i(c, v)
      import :: rank_comm_t, wp
      class(rank_comm_t), intent(inout) :: c
      real(wp), intent(inout) :: v(:)
    end subroutine max_i
    subroutine sum_i8_i(c, v)
      import :: rank_comm_t, i64
      class(rank_comm_t), intent(inout) :: c
      integer(i64), intent(inout) :: v(:)
    end subroutine sum_i8_i
    subroutine min_int_i(c, v)
      import :: rank_comm_t
      class(rank_comm_t), intent(inout) :: c
      integer, intent(inout) :: v(:)
    end subroutine min_int_i
    subroutine bcast_text_i(c, from, text)
      import :: rank_comm_t
      class(rank_comm_t), intent(inout) :: c
      integer, intent(in) :: from
      character(len=:), allocatable, intent(inout) :: text
    end subroutine bcast_text_i
    subroutine allgather_i(c, mine, all)
      import :: rank_comm_t, wp
      class(rank_comm_t), intent(inout) :: c
      real(wp), intent(in) :: mine(:)
      real(wp), intent(out) :: all(:, :)
    end subroutine allgather_i
    subroutine alltoall_i(c, mine, got)
      import :: rank_comm_t
      class(rank_comm_t), intent(inout) :: c
      integer, intent(in) :: mine(:)
      integer, intent(out) :: got(:)
    end subroutine alltoall_i
    subroutine sparse_i(c, to, sptr, sbuf, from, rptr, rbuf)
      import :: rank_comm_t, wp
      class(rank_comm_t), intent(inout) :: c
      integer, intent(in) :: to(:), sptr(:), from(:)
      real(wp), intent(in) :: sbuf(:)
      integer, intent(out) :: rptr(:)
      real(wp), allocatable, intent(inout) :: rbuf(:)
    end subroutine sparse_i
  end interface

  !> One rank: nothing to reduce, gather or send.
  type, extends(rank_comm_t) :: single_rank_t
  contains
    procedure :: max_real => single_max
    procedure :: sum_real => single_max
    procedure :: sum_i8 => single_i8
    procedure :: min_int => single_int
    procedure :: bcast_text => single_text
    procedure :: allgather_real => single_allgather
    procedure :: alltoall_int => single_alltoall
    procedure :: sparse_exchange => single_sparse
  end type single_rank_t

contains

  !> The first of rank r's share of n items among nranks ranks, the contiguous runs
  !! n*r/nranks + 1 ... n*(r + 1)/nranks (n + 1 for r = nranks: the end of the last run).
  !! The shares a body's particles are split by before the bisection exists (its tree,
  !! its fingerprint, its rows in /bodies).
  pure integer function share_first(n, r, nranks) result(i)
    integer, intent(in) :: n, r, nranks
    i = int((int(n, i64)*r)/nranks) + 1
  end function share_first

  !> The rank (from 0, of nranks) whose share (share_first) of n items holds item i
  !! (1 ... n): the home of a number when the ranks split a range of numbers by it.
  pure integer function share_rank(i, n, nranks) result(r)
    integer, intent(in) :: i, n, nranks
    integer :: lo, hi, mid
    lo = 0
    hi = nranks - 1
    do while (lo < hi)
      mid = (lo + hi + 1)/2
      if (share_first(n, mid, nranks) <= i) then
        lo = mid
      else
        hi = mid - 1
      end if
    end do
    r = lo
  end function share_rank

  !> The k-th smallest (from 1) of the values v(:) >= 0 of every rank together, the same
  !! on every rank, without gathering them: a bisection over the doubles' bit patterns
  !! (for values >= 0, -0 taken as 0, they order as the values), one sum of a count over
  !! the ranks a step (at most 64). It is one of the values, bit for bit: the serial
  !! sorted list's k-th. 0 when k < 1 or the ranks hold fewer than k values. Collective.
  real(wp) function kth_smallest(c, v, k) result(x)
    class(rank_comm_t), intent(inout) :: c
    real(wp), intent(in) :: v(:)
    integer(i64), intent(in) :: k
    integer(i64) :: lo, hi, mid, n(1)
    integer(i64), allocatable :: bits(:)
    x = 0.0_wp
    n = size(v, kind=i64)
    call c%sum_i8(n)
    if (k < 1 .or. n(1) < k) return
    bits = transfer(merge(0.0_wp, v, v <= 0.0_wp), 0_i64, size(v))
    n = count(bits == 0, kind=i64)
    call c%sum_i8(n)
    if (n(1) >= k) return
    ! count(bits <= lo) < k <= count(bits <= hi) over the ranks (hi - lo without overflow)
    lo = 0
    hi = huge(0_i64)
    do while (hi - lo > 1)
      mid = lo + (hi - lo)/2
      n = count(bits <= mid, kind=i64)
      call c%sum_i8(n)
      if (n(1) >= k) then
        hi = mid
      else
        lo = mid
      end if
    end do
    x = transfer(hi, 0.0_wp)
  end function kth_smallest

  subroutine single_max(c, v)
    class(single_rank_t), intent(inout) :: c
    real(wp), intent(inout) :: v(:)
    ! one rank's values are the largest, and the sums
    if (size(v) < 0 .or. c%nranks /= 1) continue
  end subroutine single_max

  subroutine single_i8(c, v)
    class(single_rank_t), intent(inout) :: c
    integer(i64), intent(inout) :: v(:)
    ! one rank's values are the sums
    if (size(v) < 0 .or. c%nranks /= 1) continue
  end subroutine single_i8

  subroutine single_int(c, v)
    class(single_rank_t), intent(inout) :: c
    integer, intent(inout) :: v(:)
    ! one rank's values are the smallest
    if (size(v) < 0 .or. c%nranks /= 1) continue
  end subroutine single_int

  subroutine single_text(c, from, text)
    class(single_rank_t), intent(inout) :: c
    integer, intent(in) :: from
    character(len=:), allocatable, intent(inout) :: text
    ! the one rank has the text already
    if (from /= c%me .or. .not. allocated(text)) continue
  end subroutine single_text

  subroutine single_allgather(c, mine, all)
    class(single_rank_t), intent(inout) :: c
    real(wp), intent(in) :: mine(:)
    real(wp), intent(out) :: all(:, :)
    all(:, c%me + 1) = mine
  end subroutine single_allgather

  subroutine single_alltoall(c, mine, got)
    class(single_rank_t), intent(inout) :: c
    integer, intent(in) :: mine(:)
    integer, intent(out) :: got(:)
    got(c%me + 1) = mine(c%me + 1)
  end subroutine single_alltoall

  subroutine single_sparse(c, to, sptr, sbuf, from, rptr, rbuf)
    class(single_rank_t), intent(inout) :: c
    integer, intent(in) :: to(:), sptr(:), from(:)
    real(wp), intent(in) :: sbuf(:)
    integer, intent(out) :: rptr(:)
    real(wp), allocatable, intent(inout) :: rbuf(:)
    ! one rank sends to nobody and hears from nobody (no rank lists itself): to and from
    ! are empty, rbuf receives nothing
    rptr = 1
    if (.not. allocated(rbuf)) allocate(rbuf(0))
    if (size(to) + size(from) + size(sptr) + size(sbuf) < 0 .or. c%nranks /= 1) continue
  end subroutine single_sparse

  !> The columns buf (w, n) of integers, each to rank dest(j) (from 0), delivered: got (w,
  !! m) the columns sent to this rank, by the sending rank and in its order (this rank's
  !! own among them in turn), src (m) the rank each came from. An all-to-all of the
  !! counts (P numbers a rank), then point to point to the ranks that have some only.
  !! Collective.
  subroutine route_columns(comm, dest, buf, got, src)
    class(rank_comm_t), intent(inout) :: comm
    integer, intent(in) :: dest(:), buf(:, :)
    integer, allocatable, intent(out) :: got(:, :)
    integer, allocatable, intent(out), optional :: src(:)
    integer, allocatable :: cnt(:), num(:), to(:), from(:), sptr(:), rptr(:), at(:)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    integer :: w, np, me, r, j, m, i, k
    w = size(buf, 1)
    np = comm%nranks
    me = comm%me
    allocate(cnt(np), num(np))
    cnt = 0
    do j = 1, size(dest)
      cnt(dest(j) + 1) = cnt(dest(j) + 1) + 1
    end do
    call comm%alltoall_int(cnt, num)
    to = pack([(r, r = 0, np - 1)], cnt > 0 .and. [(r /= me, r = 0, np - 1)])
    from = pack([(r, r = 0, np - 1)], num > 0 .and. [(r /= me, r = 0, np - 1)])
    allocate(sptr(size(to) + 1), at(0:np - 1))
    sptr(1) = 1
    do r = 1, size(to)
      at(to(r)) = sptr(r)
      sptr(r + 1) = sptr(r) + w*cnt(to(r) + 1)
    end do
    allocate(sbuf(sptr(size(to) + 1) - 1))
    do j = 1, size(dest)
      r = dest(j)
      if (r == me) cycle
      sbuf(at(r):at(r) + w - 1) = real(buf(:, j), wp)
      at(r) = at(r) + w
    end do
    allocate(rptr(size(from) + 1), rbuf(0))
    call comm%sparse_exchange(to, sptr, sbuf, from, rptr, rbuf)
    deallocate(sbuf)
    allocate(got(w, sum(num)))
    if (present(src)) allocate(src(sum(num)))
    m = 0
    k = 1
    do r = 0, np - 1
      if (r == me) then
        do j = 1, size(dest)
          if (dest(j) /= me) cycle
          m = m + 1
          got(:, m) = buf(:, j)
          if (present(src)) src(m) = me
        end do
      else if (k <= size(from)) then
        if (from(k) /= r) cycle
        do i = rptr(k), rptr(k + 1) - 1, w
          m = m + 1
          got(:, m) = nint(rbuf(i:i + w - 1))
          if (present(src)) src(m) = r
        end do
        k = k + 1
      end if
    end do
  end subroutine route_columns
end module rank_comm_m
