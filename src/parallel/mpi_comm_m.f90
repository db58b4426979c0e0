!> The ranks of an MPI communicator (rank_comm_m): reductions, broadcasts, the allgather of
!! contact's ghost refresh, and point-to-point messages to chosen ranks only.
module mpi_comm_m
  use mpi_f08
  use kinds_m, only: wp, i64
  use rank_comm_m, only: rank_comm_t
  implicit none
  private
  public :: mpi_ranks_t, mpi_ranks_init

  type, extends(rank_comm_t) :: mpi_ranks_t
    type(MPI_Comm) :: comm
    type(MPI_Request), allocatable :: req(:)
    real(wp) :: empty(1) = 0.0_wp   !< the buffer of an empty message
  contains
    procedure :: max_real => ranks_max
    procedure :: sum_real => ranks_sum
    procedure :: sum_i8 => ranks_sum_i8
    procedure :: min_int => ranks_min_int
    procedure :: bcast_text => ranks_bcast_text
    procedure :: allgather_real => ranks_allgather
    procedure :: alltoall_int => ranks_alltoall
    procedure :: sparse_exchange => ranks_sparse
  end type mpi_ranks_t

  !> the tag of sparse_exchange's messages
  integer, parameter :: tag_sparse = 7101

contains

  subroutine mpi_ranks_init(c, comm)
    type(mpi_ranks_t), intent(out) :: c
    type(MPI_Comm), intent(in) :: comm
    c%comm = comm
    call MPI_Comm_rank(comm, c%me)
    call MPI_Comm_size(comm, c%nranks)
    allocate(c%req(c%nranks))
  end subroutine mpi_ranks_init

  subroutine ranks_max(c, v)
    class(mpi_ranks_t), intent(inout) :: c
    real(wp), intent(inout) :: v(:)
    call MPI_Allreduce(MPI_IN_PLACE, v, size(v), MPI_DOUBLE_PRECISION, MPI_MAX, c%comm)
  end subroutine ranks_max

  subroutine ranks_sum(c, v)
    class(mpi_ranks_t), intent(inout) :: c
    real(wp), intent(inout) :: v(:)
    call MPI_Allreduce(MPI_IN_PLACE, v, size(v), MPI_DOUBLE_PRECISION, MPI_SUM, c%comm)
  end subroutine ranks_sum

  subroutine ranks_sum_i8(c, v)
    class(mpi_ranks_t), intent(inout) :: c
    integer(i64), intent(inout) :: v(:)
    call MPI_Allreduce(MPI_IN_PLACE, v, size(v), MPI_INTEGER8, MPI_SUM, c%comm)
  end subroutine ranks_sum_i8

  subroutine ranks_min_int(c, v)
    class(mpi_ranks_t), intent(inout) :: c
    integer, intent(inout) :: v(:)
    call MPI_Allreduce(MPI_IN_PLACE, v, size(v), MPI_INTEGER, MPI_MIN, c%comm)
  end subroutine ranks_min_int

  subroutine ranks_bcast_text(c, from, text)
    class(mpi_ranks_t), intent(inout) :: c
    integer, intent(in) :: from
    character(len=:), allocatable, intent(inout) :: text
    integer :: n
    n = 0
    if (c%me == from) n = len(text)
    call MPI_Bcast(n, 1, MPI_INTEGER, from, c%comm)
    if (c%me /= from) then
      if (allocated(text)) deallocate(text)
      allocate(character(len=n) :: text)
    end if
    call MPI_Bcast(text, n, MPI_CHARACTER, from, c%comm)
  end subroutine ranks_bcast_text

  subroutine ranks_allgather(c, mine, all)
    class(mpi_ranks_t), intent(inout) :: c
    real(wp), intent(in) :: mine(:)
    real(wp), intent(out) :: all(:, :)
    call MPI_Allgather(mine, size(mine), MPI_DOUBLE_PRECISION, all, size(mine), &
      MPI_DOUBLE_PRECISION, c%comm)
  end subroutine ranks_allgather

  subroutine ranks_alltoall(c, mine, got)
    class(mpi_ranks_t), intent(inout) :: c
    integer, intent(in) :: mine(:)
    integer, intent(out) :: got(:)
    call MPI_Alltoall(mine, 1, MPI_INTEGER, got, 1, MPI_INTEGER, c%comm)
  end subroutine ranks_alltoall

  !> Nonblocking sends to the ranks of to; from each rank of from, in turn, the message's
  !! length is probed and it is received into rbuf.
  subroutine ranks_sparse(c, to, sptr, sbuf, from, rptr, rbuf)
    class(mpi_ranks_t), intent(inout) :: c
    integer, intent(in) :: to(:), sptr(:), from(:)
    real(wp), intent(in) :: sbuf(:)
    integer, intent(out) :: rptr(:)
    real(wp), allocatable, intent(inout) :: rbuf(:)
    type(MPI_Status) :: st
    real(wp), allocatable :: tmp(:)
    integer :: k, n
    do k = 1, size(to)
      ! (an empty message too: the receiver waits for one from each rank it listed)
      n = sptr(k + 1) - sptr(k)
      if (n > 0) then
        call MPI_Isend(sbuf(sptr(k)), n, MPI_DOUBLE_PRECISION, to(k), tag_sparse, c%comm, &
          c%req(k))
      else
        call MPI_Isend(c%empty, 0, MPI_DOUBLE_PRECISION, to(k), tag_sparse, c%comm, c%req(k))
      end if
      c%bytes = c%bytes + 8_i64*n
    end do
    if (.not. allocated(rbuf)) allocate(rbuf(0))
    rptr(1) = 1
    do k = 1, size(from)
      call MPI_Probe(from(k), tag_sparse, c%comm, st)
      call MPI_Get_count(st, MPI_DOUBLE_PRECISION, n)
      if (size(rbuf) < rptr(k) - 1 + n) then
        allocate(tmp(max(2*size(rbuf), rptr(k) - 1 + n)))
        tmp(1:rptr(k) - 1) = rbuf(1:rptr(k) - 1)
        call move_alloc(tmp, rbuf)
      end if
      if (n > 0) then
        call MPI_Recv(rbuf(rptr(k)), n, MPI_DOUBLE_PRECISION, from(k), tag_sparse, c%comm, &
          MPI_STATUS_IGNORE)
      else
        call MPI_Recv(c%empty, 0, MPI_DOUBLE_PRECISION, from(k), tag_sparse, c%comm, &
          MPI_STATUS_IGNORE)
      end if
      rptr(k + 1) = rptr(k) + n
    end do
    call MPI_Waitall(size(to), c%req(1:size(to)), MPI_STATUSES_IGNORE)
  end subroutine ranks_sparse
end module mpi_comm_m
