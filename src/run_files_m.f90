!> The files of a dynamic run: the HDF5 file (header, deck, bodies, snapshots, history,
!! summary) and its XDMF companion for ParaView, rewritten at every snapshot so that a run
!! stopped at any point leaves readable files.
module run_files_m
  use, intrinsic :: iso_fortran_env, only: output_unit
  use kinds_m, only: wp
  use errors_m, only: error_t
  use deck_m, only: deck_t
  use body_m, only: body_t
  use solid_m, only: solid_t
  use contact_pair_m, only: contact_pair_t
  use hdf5_io_m, only: h5file_t, h5_create, h5_close, h5_group
  use run_output_m, only: write_header, write_bodies
  use dynamic_output_m, only: history_t, history_create, history_flush, snapshot_write, &
    xdmf_write
  use run_report_m, only: run_record_t, det_fields_out
  implicit none
  private
  public :: run_files_t, run_files_open, snapshots_due, failure_snapshot, run_files_close

  type :: run_files_t
    type(h5file_t) :: f
    type(history_t) :: hist
    character(len=:), allocatable :: xdmf        !< path of the XDMF companion
    character(len=:), allocatable :: h5name      !< the HDF5 file's name, as XDMF refers to it
    character(len=8), allocatable :: labels(:)   !< snapshots written
    real(wp), allocatable :: times(:)            !< their times (s)
    integer :: nsnap_done = 0                    !< deck snapshot times passed
  end type run_files_t

contains

  !> Create the HDF5 file with its header, the deck, the bodies and the empty history.
  subroutine run_files_open(deck, bodies, out, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(run_files_t), intent(out) :: out
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: path
    path = trim(deck%output%file)
    out%xdmf = path(1:index(path, '.', back=.true.) - 1)//'.xdmf'
    out%h5name = path(index(path, '/', back=.true.) + 1:)
    allocate(out%labels(0), out%times(0))
    call h5_create(out%f, path, err)
    if (allocated(err)) return
    call write_header(out%f, deck, err)
    if (.not. allocated(err)) call write_bodies(out%f, bodies, deck, err)
    if (.not. allocated(err)) call h5_group(out%f, '/snapshots', err)
    if (.not. allocated(err)) call history_create(out%f, out%hist, &
      deck%run%geometry /= 'axisymmetric', err)
  end subroutine run_files_open

  !> The deck's snapshots due by the record's time: the state of every solid, the det(M)
  !! fields when the deck asks, the history so far, and the XDMF file.
  subroutine snapshots_due(out, deck, r, pairs, solids, err)
    type(run_files_t), intent(inout) :: out
    type(deck_t), intent(in) :: deck
    type(run_record_t), intent(in) :: r
    type(contact_pair_t), intent(in) :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=8) :: lab
    do while (out%nsnap_done < deck%solver%nsnap)
      if (deck%solver%snapshot_times(out%nsnap_done + 1) > r%t + 0.5_wp*r%dt) exit
      out%nsnap_done = out%nsnap_done + 1
      write(lab, '(i4.4)') out%nsnap_done
      call snapshot_write(out%f, trim(lab), r%t, r%n, solids, err)
      if (allocated(err)) return
      if (deck%output%det_fields) call det_fields_out(out%f, trim(lab), pairs, solids, &
        deck%output%det_grid_lo, deck%output%det_grid_hi, deck%output%det_grid_n, err)
      if (allocated(err)) return
      out%labels = [character(len=8) :: out%labels, lab]
      out%times = [out%times, r%t]
      call history_flush(out%f, out%hist, err)
      if (allocated(err)) return
      call xdmf_write(out%xdmf, out%h5name, out%labels, out%times, solids)
      write(output_unit, '(a,es12.5,a)') 'dynamic: snapshot '//trim(lab)//' at t = ', r%t, ' s'
    end do
  end subroutine snapshots_due

  !> The diagnostic snapshot of a failed run, /snapshots/failure, with its XDMF entry.
  subroutine failure_snapshot(out, r, solids, err)
    type(run_files_t), intent(inout) :: out
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    write(output_unit, '(a)') 'dynamic: FAILED at '//r%reason
    call snapshot_write(out%f, 'failure', r%t, r%n, solids, err)
    out%labels = [character(len=8) :: out%labels, 'failure']
    out%times = [out%times, r%t]
    call xdmf_write(out%xdmf, out%h5name, out%labels, out%times, solids)
  end subroutine failure_snapshot

  subroutine run_files_close(out, err)
    type(run_files_t), intent(inout) :: out
    type(error_t), allocatable, intent(inout) :: err
    call h5_close(out%f, err)
  end subroutine run_files_close
end module run_files_m
