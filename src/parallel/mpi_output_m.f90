!> The run's HDF5 file opened on every rank with MPI-IO (HDF5's parallel library, Debian's
!! libhdf5-openmpi-dev): for a snapshot's solids' datasets, which every rank writes
!! collectively, each its own rows in global order (dynamic_output_m snapshot_write,
!! hdf5_io_m h5_write_rows), so that no rank holds the whole state. Rank 0 keeps the file
!! open by itself between such phases (the history, the det(M) fields, the summary): it
!! closes it, every rank opens it together, writes and closes it, and rank 0 opens it again.
module mpi_output_m
  use mpi_f08, only: MPI_Comm, MPI_INFO_NULL
  use hdf5, only: hid_t, h5open_f, h5pcreate_f, h5pclose_f, h5pset_fapl_mpio_f, &
    h5pset_dxpl_mpio_f, H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, H5FD_MPIO_COLLECTIVE_F
  use errors_m, only: error_t, set_error
  use hdf5_io_m, only: h5file_t, h5_open_rw, h5_close
  implicit none
  private
  public :: h5_open_collective, h5_close_collective

contains

  !> Open the existing file path on every rank of comm (collective), its row writes
  !! collective.
  subroutine h5_open_collective(f, path, comm, err)
    type(h5file_t), intent(out) :: f
    character(len=*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    type(error_t), allocatable, intent(inout) :: err
    integer(hid_t) :: fapl, xfer
    integer :: st, s2
    ! (the library's constants are set by h5open_f: ranks other than 0 open no file before)
    call h5open_f(st)
    if (st == 0) call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, st)
    if (st == 0) call h5pset_fapl_mpio_f(fapl, comm%MPI_VAL, MPI_INFO_NULL%MPI_VAL, st)
    if (st /= 0) then
      call set_error(err, "output file '"//path//"': HDF5's MPI-IO driver failed to start", 1)
      return
    end if
    call h5_open_rw(f, path, err, fapl)
    call h5pclose_f(fapl, s2)
    if (allocated(err)) return
    call h5pcreate_f(H5P_DATASET_XFER_F, xfer, st)
    if (st == 0) call h5pset_dxpl_mpio_f(xfer, H5FD_MPIO_COLLECTIVE_F, st)
    if (st /= 0) then
      call set_error(err, "output file '"//path//"': collective transfers not available", 1)
      return
    end if
    f%xfer = xfer
  end subroutine h5_open_collective

  !> Close a file opened by h5_open_collective (collective).
  subroutine h5_close_collective(f, err)
    type(h5file_t), intent(inout) :: f
    type(error_t), allocatable, intent(inout) :: err
    integer :: st
    if (f%xfer >= 0) call h5pclose_f(f%xfer, st)
    f%xfer = -1
    call h5_close(f, err)
  end subroutine h5_close_collective
end module mpi_output_m
