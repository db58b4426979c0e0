!> The files of a dynamic run: the HDF5 file (header, deck, bodies, snapshots, history,
!! summary) and its XDMF companion for ParaView, rewritten at every snapshot so that a run
!! stopped at any point leaves readable files. They are written under this run's temporary
!! names and renamed at the end (output_path_m): onto the deck's names when the run
!! completed, onto the failed-run names when it did not. Checkpoints (run_checkpoint_m) are
!! written beside them and renamed over the previous one at once; a run restarted from a
!! checkpoint starts its files with the checkpoint's history.
module run_files_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error, exit_run_failed
  use strings_m, only: itoa, rtoa
  use deck_m, only: deck_t
  use body_m, only: body_t
  use solid_m, only: solid_t
  use contact_pair_m, only: contact_pair_t
  use hdf5_io_m, only: h5file_t, h5_close, h5_group, h5_attr
  use run_output_m, only: write_header, write_bodies
  use output_path_m, only: output_path_t, output_open, output_commit, output_files_text, &
    base_name, checkpoint_commit
  use run_checkpoint_m, only: checkpoint_write
  use dynamic_output_m, only: history_t, history_create, history_flush, snapshot_write, &
    history_geometry, &
    xdmf_write, xdmf_body_t, rigid_snapshot_write
  use run_report_m, only: run_record_t, det_fields_out
  use log_m, only: log_print
  use file_system_m, only: remove_file
  implicit none
  private
  public :: run_files_t, run_files_open, snapshot_due, snapshot_others, failure_snapshot, &
    run_files_close, run_files_names, run_files_resume, run_files_checkpoint, &
    snapshot_needs_state, run_files_checkpoint_commit, run_files_checkpoint_failed

  type :: run_files_t
    type(h5file_t) :: f
    type(history_t) :: hist
    type(output_path_t) :: path                  !< final, failed and temporary names
    character(len=8), allocatable :: labels(:)   !< snapshots written
    real(wp), allocatable :: times(:)            !< their times (s)
    integer :: nsnap_done = 0                    !< deck snapshot times passed
    !> times of the deck snapshots written before a restart (in the earlier run's files)
    real(wp), allocatable :: earlier_times(:)
    integer :: checkpoint_step = -1              !< step of the last checkpoint (-1: none)
    character(len=:), allocatable :: checkpoint  !< and its file
    type(xdmf_body_t), allocatable :: rigid(:)   !< the rigid bodies, for the XDMF file
    !> the run's deck, for its checkpoints (a copy taken when the files are opened)
    type(deck_t), allocatable :: deck
  end type run_files_t

contains

  !> Make the directory and create this run's HDF5 file (temporary name) with its header,
  !! the deck, the bodies and the empty history. Called when set-up is done: a deck or body
  !! error found before leaves nothing behind. restart: the checkpoint a restarted run
  !! continues from.
  subroutine run_files_open(deck, bodies, out, err, restart)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(run_files_t), intent(out) :: out
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: restart
    integer :: k
    allocate(out%labels(0), out%times(0), out%earlier_times(0), out%rigid(0))
    out%deck = deck
    do k = 1, size(bodies)
      if (deck%bodies(k)%role /= 'rigid') cycle
      out%rigid = [out%rigid, xdmf_body_t(name=bodies(k)%name, np=bodies(k)%np, &
        ne=0, ndim=bodies(k)%ndim)]
      associate (rb => out%rigid(size(out%rigid)))
        if (allocated(bodies(k)%cells)) rb%ne = size(bodies(k)%cells, 2)
        ! a ram: moves at its prescribed velocity, written in every snapshot
        rb%vel = deck%bodies(k)%velocity
        rb%moving = any(rb%vel(1:rb%ndim) /= 0.0_wp)
        if (rb%moving) rb%x = bodies(k)%x
      end associate
    end do
    call output_open(deck, .true., out%path, out%f, err, restart)
    if (allocated(err)) return
    call write_header(out%f, deck, err)
    if (.not. allocated(err)) call write_bodies(out%f, bodies, deck, err)
    if (.not. allocated(err)) call h5_group(out%f, '/snapshots', err)
    if (.not. allocated(err)) call history_create(out%f, out%hist, &
      pack(deck%bodies(1:deck%nbodies)%name, deck%bodies(1:deck%nbodies)%role /= 'rigid'), &
      deck%ncontacts, deck%nbcs, history_geometry(deck%run%ndim, &
      deck%run%geometry == 'axisymmetric'), err)
    if (allocated(err)) call abandon(out, err)
  end subroutine run_files_open

  !> A run restarted from the checkpoint at path, written at step r%n (checkpoint_read gave
  !! hist, nsnap_done, times): the history so far goes into the new file with its next
  !! flush, the deck's snapshots go on after the nsnap_done already written (they stay in
  !! the earlier run's files), and root attributes say where the run was restarted.
  subroutine run_files_resume(out, path, r, hist, nsnap_done, times, err)
    type(run_files_t), intent(inout) :: out
    character(len=*), intent(in) :: path
    type(run_record_t), intent(in) :: r
    type(history_t), intent(inout) :: hist
    integer, intent(in) :: nsnap_done
    real(wp), intent(in) :: times(:)
    type(error_t), allocatable, intent(inout) :: err
    call move_alloc(hist%rows, out%hist%rows)
    out%hist%n = hist%n
    out%hist%nflushed = 0
    out%nsnap_done = nsnap_done
    out%earlier_times = times
    out%checkpoint_step = r%n
    out%checkpoint = path
    call h5_attr(out%f, '/', 'restarted_from', path, err)
    if (.not. allocated(err)) call h5_attr(out%f, '/', 'restart_step', r%n, err)
    if (.not. allocated(err)) call h5_attr(out%f, '/', 'restart_time', r%t, err)
    if (.not. allocated(err)) call h5_attr(out%f, '/', 'snapshots_before_restart', &
      nsnap_done, err)
    if (allocated(err)) call abandon(out, err)
  end subroutine run_files_resume

  !> A checkpoint of the run after step r%n: written under its temporary name, then renamed
  !! over the previous checkpoint (output_path_m, checkpoint_commit). t_loop: seconds spent
  !! in the time loop so far. A failure fails the run (exit 1) and leaves the previous
  !! checkpoint as it was. fields = .false.: without the solids' state fields and not
  !! renamed (on MPI ranks, which write the fields, then run_files_checkpoint_commit).
  subroutine run_files_checkpoint(out, bodies, r, solids, pairs, t_loop, err, fields)
    type(run_files_t), intent(inout) :: out
    type(body_t), intent(in) :: bodies(:)
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(in) :: solids(:)
    type(contact_pair_t), intent(in) :: pairs(:)
    real(wp), intent(in) :: t_loop
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: fields
    call checkpoint_write(out%path%tmp_checkpoint, out%deck, bodies, r, solids, pairs, &
      out%hist, out%nsnap_done, [out%earlier_times, pack(out%times, out%labels /= 'failure')], &
      t_loop, err, fields)
    if (allocated(err)) then
      call run_files_checkpoint_failed(out, r, err)
      return
    end if
    if (present(fields)) then
      if (.not. fields) return
    end if
    call run_files_checkpoint_commit(out, r, err)
  end subroutine run_files_checkpoint

  !> The checkpoint written under its temporary name renamed over the previous one.
  subroutine run_files_checkpoint_commit(out, r, err)
    type(run_files_t), intent(inout) :: out
    type(run_record_t), intent(in) :: r
    type(error_t), allocatable, intent(inout) :: err
    call checkpoint_commit(out%path, err)
    if (allocated(err)) return
    out%checkpoint_step = r%n
    out%checkpoint = out%path%checkpoint
    call log_print('dynamic: checkpoint at step '//itoa(r%n)//', t = '//rtoa(r%t)//' s: '// &
      out%path%checkpoint)
  end subroutine run_files_checkpoint_commit

  !> A checkpoint that could not be written: its temporary file removed, the run failed
  !! (exit 1), the previous checkpoint unchanged.
  subroutine run_files_checkpoint_failed(out, r, err)
    type(run_files_t), intent(inout) :: out
    type(run_record_t), intent(in) :: r
    type(error_t), allocatable, intent(inout) :: err
    logical :: ok
    ok = remove_file(out%path%tmp_checkpoint)
    err%message = 'checkpoint at step '//itoa(r%n)//': '//err%message// &
      '; the previous checkpoint is unchanged'
    err%code = exit_run_failed
  end subroutine run_files_checkpoint_failed

  !> A write failed before the run started: the files go to the failed-run names.
  subroutine abandon(out, err)
    type(run_files_t), intent(inout) :: out
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: e2
    character(len=:), allocatable :: note
    call h5_close(out%f, e2)
    if (allocated(e2)) deallocate(e2)
    call output_commit(out%path, .false., note, e2)
    err%message = err%message//'; the files of the run are '//note
    if (allocated(e2)) err%message = err%message//'; '//e2%message
    err%code = exit_run_failed
  end subroutine abandon

  !> The label ('0001', ...) of the deck's next snapshot if it is due by the record's time
  !! (counted as done), else ''. Every rank keeps the count.
  function snapshot_due(out, deck, r) result(lab)
    type(run_files_t), intent(inout) :: out
    type(deck_t), intent(in) :: deck
    type(run_record_t), intent(in) :: r
    character(len=8) :: lab
    lab = ''
    if (out%nsnap_done >= deck%solver%nsnap) return
    if (deck%solver%snapshot_times(out%nsnap_done + 1) > r%t + 0.5_wp*r%dt) return
    out%nsnap_done = out%nsnap_done + 1
    write(lab, '(i4.4)') out%nsnap_done
  end function snapshot_due

  !> Snapshot lab after its solids' datasets (snapshot_write, written already): the moving
  !! rigid bodies, the det(M) fields when the deck asks (from the whole solids' state),
  !! the history so far, and the XDMF file.
  subroutine snapshot_others(out, deck, lab, r, pairs, solids, err)
    type(run_files_t), intent(inout) :: out
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: lab
    type(run_record_t), intent(in) :: r
    type(contact_pair_t), intent(in) :: pairs(:)
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=80) :: line
    call rigid_snapshot_write(out%f, trim(lab), r%t, out%rigid, err)
    if (allocated(err)) return
    if (deck%output%det_fields) call det_fields_out(out%f, trim(lab), pairs, solids, &
      deck%output%det_grid_lo, deck%output%det_grid_hi, deck%output%det_grid_n, err)
    if (allocated(err)) return
    out%labels = [character(len=8) :: out%labels, lab]
    out%times = [out%times, r%t]
    call history_flush(out%f, out%hist, err)
    if (allocated(err)) return
    call xdmf_write(out%path%tmp_xdmf, base_name(out%path%tmp_h5), out%labels, out%times, &
      solids, out%rigid)
    write(line, '(a,es12.5,a)') 'dynamic: snapshot '//trim(lab)//' at t = ', r%t, ' s'
    call log_print(trim(line))
  end subroutine snapshot_others

  !> Whether a snapshot needs the whole solids' state besides their own datasets: the
  !! det(M) fields on a plane grid the deck asks for.
  pure logical function snapshot_needs_state(deck) result(yes)
    type(deck_t), intent(in) :: deck
    yes = deck%output%det_fields
  end function snapshot_needs_state

  !> The diagnostic snapshot of a failed run, /snapshots/failure, after its solids'
  !! datasets: the moving rigid bodies, and its XDMF entry.
  subroutine failure_snapshot(out, r, solids, err)
    type(run_files_t), intent(inout) :: out
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(inout) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    ! (its solids' datasets are written already, snapshot_write: on ranks from the parts)
    call rigid_snapshot_write(out%f, 'failure', r%t, out%rigid, err)
    out%labels = [character(len=8) :: out%labels, 'failure']
    out%times = [out%times, r%t]
    call xdmf_write(out%path%tmp_xdmf, base_name(out%path%tmp_h5), out%labels, out%times, &
      solids, out%rigid)
  end subroutine failure_snapshot

  !> The end of the run, however it ends: close the HDF5 file, write the XDMF file naming
  !! the HDF5 file as it will be called, and rename both onto the final names when the run
  !! completed (r not failed, no error). Otherwise they go to the failed-run names and err
  !! says why the run stopped and where its files are, with exit code 1: output was written.
  subroutine run_files_close(out, r, solids, err)
    type(run_files_t), intent(inout) :: out
    type(run_record_t), intent(in) :: r
    type(solid_t), intent(in) :: solids(:)
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: e2
    character(len=:), allocatable :: note
    logical :: completed
    completed = .not. (r%failed .or. allocated(err))
    call h5_close(out%f, e2)
    if (allocated(e2)) completed = .false.
    if (allocated(e2) .and. .not. allocated(err)) call move_alloc(e2, err)
    ! the XDMF file names the HDF5 file as it is called after the rename, relative to it
    if (completed) then
      call xdmf_write(out%path%tmp_xdmf, base_name(out%path%h5), out%labels, out%times, &
        solids, out%rigid)
    else
      call xdmf_write(out%path%tmp_xdmf, base_name(out%path%failed_h5), out%labels, &
        out%times, solids, out%rigid)
    end if
    call output_commit(out%path, completed, note, e2)
    if (allocated(e2)) then
      if (allocated(err)) e2%message = err%message//'; '//e2%message
      call move_alloc(e2, err)
      return
    end if
    if (completed) return
    if (.not. allocated(err)) call set_error(err, 'run failed at '//r%reason// &
      '; diagnostic snapshot /snapshots/failure')
    err%message = err%message//'; the files of the run are '//note
    if (out%checkpoint_step >= 0) err%message = err%message//'; the last checkpoint, '// &
      'step '//itoa(out%checkpoint_step)//', is '//out%checkpoint
    err%code = exit_run_failed
  end subroutine run_files_close

  !> The files this run leaves: 'out/run.h5 and out/run.xdmf', or the failed-run names.
  function run_files_names(out, failed) result(s)
    type(run_files_t), intent(in) :: out
    logical, intent(in) :: failed
    character(len=:), allocatable :: s
    s = output_files_text(out%path, .not. failed)
  end function run_files_names
end module run_files_m
