!> The halo exchanges of a decomposed solid over MPI (issue 12; doc/parallel.md): which
!! owned values each neighbour rank needs, and the exchanges themselves.
!!
!! Built once from a rank's local_part_t (decomposition_m), with the owners of every node
!! and point (node_part, point_part): a rank asks each owner for the ghost nodes and ghost
!! points it holds (one MPI_Alltoall of counts and one MPI_Alltoallv of global numbers, at
!! set-up only); the answers are its send lists. An exchange then sends each neighbour the
!! owned values it asked for and receives the ghosts' values, packed in global order, with
!! nonblocking point-to-point messages to the neighbours only.
module halo_m
  use mpi_f08
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use decomposition_m, only: local_part_t
  use sorting_m, only: sorted_place
  implicit none
  private
  public :: halo_plan_t, halo_plan_build, halo_nodes, halo_points

  !> One exchange pattern (nodes or points): per neighbour rank, the local numbers sent and
  !! received, CSR by neighbour.
  type :: halo_side_t
    integer :: nnb = 0
    integer, allocatable :: nb(:)                  !< neighbour ranks (0-based)
    integer, allocatable :: sptr(:), slist(:)      !< owned entries each neighbour gets
    integer, allocatable :: rptr(:), rlist(:)      !< ghost entries each neighbour sends
    real(wp), allocatable :: sbuf(:), rbuf(:)      !< packed values (grown to the widest use)
    type(MPI_Request), allocatable :: req(:)
  end type halo_side_t

  !> Values per entry the buffers first hold (d, v, a together: 6); a wider exchange grows
  !! them once.
  integer, parameter :: first_values = 8

  type :: halo_plan_t
    type(MPI_Comm) :: comm
    type(halo_side_t) :: nodes, points
    integer(8) :: bytes_nodes = 0, bytes_points = 0  !< per exchange of one value each
  end type halo_plan_t

contains

  !> The plan of rank lp%rank - 1 (parts are numbered from 1, MPI ranks from 0);
  !! node_part(k), point_part(k): the parts owning lp's local node k and local point k
  !! (lp%nglob and lp%qglob the global numbers: no array over the whole solid).
  subroutine halo_plan_build(comm, lp, node_part, point_part, plan, err)
    type(MPI_Comm), intent(in) :: comm
    type(local_part_t), intent(in) :: lp
    integer, intent(in) :: node_part(:), point_part(:)
    type(halo_plan_t), intent(out) :: plan
    type(error_t), allocatable, intent(inout) :: err
    plan%comm = comm
    call side_build(comm, lp%nglob, node_part, plan%nodes, err)
    if (.not. allocated(err)) call side_build(comm, lp%qglob, point_part, plan%points, err)
  end subroutine halo_plan_build

  !> The local entries with global numbers glob (ascending) and owning parts owner
  !! (1-based). Entries owned elsewhere are asked from their owners.
  subroutine side_build(comm, glob, owner, h, err)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: glob(:), owner(:)
    type(halo_side_t), intent(out) :: h
    type(error_t), allocatable, intent(inout) :: err
    integer :: nranks, me, k, r, n
    integer, allocatable :: nask(:), ngive(:), sdisp(:), rdisp(:), ask(:), give(:), fill(:)
    call MPI_Comm_size(comm, nranks)
    call MPI_Comm_rank(comm, me)
    allocate(nask(0:nranks - 1), ngive(0:nranks - 1), sdisp(0:nranks - 1), &
      rdisp(0:nranks - 1), fill(0:nranks - 1))
    nask = 0
    do k = 1, size(glob)
      r = owner(k) - 1
      if (r /= me) nask(r) = nask(r) + 1
    end do
    call MPI_Alltoall(nask, 1, MPI_INTEGER, ngive, 1, MPI_INTEGER, comm)
    sdisp(0) = 0
    rdisp(0) = 0
    do r = 1, nranks - 1
      sdisp(r) = sdisp(r - 1) + nask(r - 1)
      rdisp(r) = rdisp(r - 1) + ngive(r - 1)
    end do
    allocate(ask(sum(nask)), give(sum(ngive)))
    ! what this rank asks each owner for, in global order (glob is ascending)
    fill = 0
    do k = 1, size(glob)
      r = owner(k) - 1
      if (r == me) cycle
      ask(sdisp(r) + fill(r) + 1) = glob(k)
      fill(r) = fill(r) + 1
    end do
    call MPI_Alltoallv(ask, nask, sdisp, MPI_INTEGER, give, ngive, rdisp, MPI_INTEGER, comm)
    ! local numbers of the global ones this rank holds: their places in glob (ascending),
    ! by bisection (no array over the global numbering, whose size is the whole solid's)
    h%nnb = count(nask > 0 .or. ngive > 0)
    allocate(h%nb(h%nnb), h%sptr(h%nnb + 1), h%rptr(h%nnb + 1), h%slist(size(give)), &
      h%rlist(size(ask)))
    n = 0
    h%sptr(1) = 1
    h%rptr(1) = 1
    do r = 0, nranks - 1
      if (nask(r) == 0 .and. ngive(r) == 0) cycle
      n = n + 1
      h%nb(n) = r
      do k = 1, ngive(r)
        h%slist(h%sptr(n) + k - 1) = sorted_place(glob, give(rdisp(r) + k))
      end do
      h%sptr(n + 1) = h%sptr(n) + ngive(r)
      do k = 1, nask(r)
        h%rlist(h%rptr(n) + k - 1) = sorted_place(glob, ask(sdisp(r) + k))
      end do
      h%rptr(n + 1) = h%rptr(n) + nask(r)
    end do
    ! (the parts of every rank come from the same decomposition: a miss is a bug upstream)
    if (any(h%slist == 0)) then
      call set_error(err, 'halo plan of rank '//itoa(me)//': asked for an entry it does '// &
        'not hold (the ranks disagree on the decomposition)')
      return
    end if
    allocate(h%sbuf(first_values*size(h%slist)), h%rbuf(first_values*size(h%rlist)), &
      h%req(2*h%nnb))
  end subroutine side_build

  !> The owners' values v(m, np_local) of the ghost nodes, into v.
  subroutine halo_nodes(plan, v)
    type(halo_plan_t), intent(inout) :: plan
    real(wp), intent(inout) :: v(:, :)
    call exchange(plan%comm, plan%nodes, v, plan%bytes_nodes)
  end subroutine halo_nodes

  !> The owners' values v(m, nq_local) of the ghost points, into v.
  subroutine halo_points(plan, v)
    type(halo_plan_t), intent(inout) :: plan
    real(wp), intent(inout) :: v(:, :)
    call exchange(plan%comm, plan%points, v, plan%bytes_points)
  end subroutine halo_points

  subroutine exchange(comm, h, v, bytes)
    type(MPI_Comm), intent(in) :: comm
    type(halo_side_t), intent(inout) :: h
    real(wp), intent(inout) :: v(:, :)
    integer(8), intent(inout) :: bytes
    integer :: n, m, k, ns, nr, c
    m = size(v, 1)
    ns = h%sptr(h%nnb + 1) - 1
    nr = h%rptr(h%nnb + 1) - 1
    if (m*ns > size(h%sbuf)) then
      deallocate(h%sbuf)
      allocate(h%sbuf(m*ns))
    end if
    if (m*nr > size(h%rbuf)) then
      deallocate(h%rbuf)
      allocate(h%rbuf(m*nr))
    end if
    do k = 1, ns
      h%sbuf(m*(k - 1) + 1:m*k) = v(:, h%slist(k))
    end do
    h%req = MPI_REQUEST_NULL
    ! (the first element of each neighbour's slice: its address and the count are what MPI
    ! uses, and no temporary copy of a section can stand in for the buffer)
    do n = 1, h%nnb
      c = m*(h%rptr(n + 1) - h%rptr(n))
      if (c > 0) call MPI_Irecv(h%rbuf(m*(h%rptr(n) - 1) + 1), c, MPI_DOUBLE_PRECISION, &
        h%nb(n), 11, comm, h%req(n))
    end do
    do n = 1, h%nnb
      c = m*(h%sptr(n + 1) - h%sptr(n))
      if (c > 0) call MPI_Isend(h%sbuf(m*(h%sptr(n) - 1) + 1), c, MPI_DOUBLE_PRECISION, &
        h%nb(n), 11, comm, h%req(h%nnb + n))
    end do
    call MPI_Waitall(2*h%nnb, h%req, MPI_STATUSES_IGNORE)
    do k = 1, nr
      v(:, h%rlist(k)) = h%rbuf(m*(k - 1) + 1:m*k)
    end do
    bytes = bytes + 8_8*m*ns
  end subroutine exchange
end module halo_m
