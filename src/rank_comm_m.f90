!> What contact needs of the ranks of a distributed run (issue 12, doc/parallel.md), without
!! naming MPI: the layers below the MPI driver see only this interface, and the MPI build
!! extends it (mpi_comm_m, library mfcd_parallel). single_rank_t is the one-rank case, for
!! the serial build's tests of the distributed paths.
module rank_comm_m
  use kinds_m, only: wp, i64
  implicit none
  private
  public :: rank_comm_t, single_rank_t

  !> The ranks: this one (me, from 0) of nranks. Every procedure is collective.
  type, abstract :: rank_comm_t
    integer :: me = 0
    integer :: nranks = 1
    integer(i64) :: bytes = 0   !< bytes this rank sent through sparse_exchange
  contains
    !> v(:) becomes its largest value over the ranks, entry by entry.
    procedure(max_i), deferred :: max_real
    !> all(:, r + 1) becomes rank r's mine(:) (the same length on every rank).
    procedure(allgather_i), deferred :: allgather_real
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
    subroutine allgather_i(c, mine, all)
      import :: rank_comm_t, wp
      class(rank_comm_t), intent(inout) :: c
      real(wp), intent(in) :: mine(:)
      real(wp), intent(out) :: all(:, :)
    end subroutine allgather_i
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
    procedure :: allgather_real => single_allgather
    procedure :: sparse_exchange => single_sparse
  end type single_rank_t

contains

  subroutine single_max(c, v)
    class(single_rank_t), intent(inout) :: c
    real(wp), intent(inout) :: v(:)
    ! one rank's values are the largest
    if (size(v) < 0 .or. c%nranks /= 1) continue
  end subroutine single_max

  subroutine single_allgather(c, mine, all)
    class(single_rank_t), intent(inout) :: c
    real(wp), intent(in) :: mine(:)
    real(wp), intent(out) :: all(:, :)
    all(:, c%me + 1) = mine
  end subroutine single_allgather

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
end module rank_comm_m
