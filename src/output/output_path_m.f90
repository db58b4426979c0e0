!> Where a run's results go, and the rules that keep every other file safe (doc/deck.md,
!! "What mfcd writes, and what it never touches"):
!!  - check_output_path, before the run, only looks: it creates nothing, and it refuses
!!    (exit 2) an output that would land on the deck, on a particle file, on a directory,
!!    or, with overwrite = .false., on any existing file;
!!  - output_open, just before the first write, makes the directory (mkdir -p through libc)
!!    and creates this run's own files under names nobody else uses, exclusively (O_EXCL):
!!    <dir>/.<name>.tmp-<pid> and <dir>/.<stem>.xdmf.tmp-<pid>;
!!  - output_commit, at the end, renames them onto the final names <name> and <stem>.xdmf
!!    when the run completed, and onto <stem>.failed<ext> and <stem>.failed.xdmf when it did
!!    not, so an earlier result under the final names survives a failed run;
!!  - checkpoint_commit, at each checkpoint of a dynamic run (&output checkpoint_every),
!!    renames the checkpoint just written (<dir>/.<stem>.checkpoint.h5.tmp-<pid>) over
!!    <stem>.checkpoint.h5: a crash while it is written leaves the previous one intact.
!! mfcd never opens an existing file for writing, and removes only names it created.
module output_path_m
  use errors_m, only: error_t, set_error, exit_run_failed
  use strings_m, only: itoa, lower
  use deck_m, only: deck_t
  use hdf5_io_m, only: h5file_t, h5_create
  use file_system_m, only: make_dirs, is_dir, writable_dir, path_exists, real_path, &
    rename_file, link_file, remove_file, process_id, fs_refusal
  use log_m, only: log_print
  implicit none
  private
  public :: output_path_t, output_names, check_output_path, output_open, output_commit, &
    output_files_text, output_result_text, base_name, checkpoint_commit, scratch_name

  !> The names of one run's output.
  type :: output_path_t
    character(len=:), allocatable :: dir                  !< directory ('.' when none)
    character(len=:), allocatable :: h5, xdmf             !< final names, run completed
    character(len=:), allocatable :: failed_h5, failed_xdmf   !< names of a failed run
    character(len=:), allocatable :: tmp_h5, tmp_xdmf     !< this run's files while it runs
    character(len=:), allocatable :: checkpoint           !< <stem>.checkpoint.h5
    character(len=:), allocatable :: tmp_checkpoint       !< a checkpoint while it is written
    character(len=:), allocatable :: restart              !< real path of --restart's file, or ''
    logical :: with_xdmf = .false.                        !< dynamic runs have an XDMF file
    logical :: with_checkpoint = .false.                  !< dynamic, checkpoint_every > 0
    logical :: own_checkpoint = .false.                   !< this run has written a checkpoint
    logical :: overwrite = .true.                         !< &output overwrite
  end type output_path_t

  !> Tries at a free temporary name when stale ones of an earlier process with our id lie
  !! in the directory.
  integer, parameter :: max_tries = 100

contains

  !> The names that go with &output file = path: its directory, <stem>.xdmf, the
  !! failed-run names <stem>.failed<ext>, <stem>.failed.xdmf and the checkpoint
  !! <stem>.checkpoint.h5 (stem: the name up to its last '.', ext: the rest).
  pure function output_names(path, with_xdmf) result(p)
    character(len=*), intent(in) :: path
    logical, intent(in) :: with_xdmf
    type(output_path_t) :: p
    character(len=:), allocatable :: lead, name, stem, ext
    integer :: k, j
    k = index(path, '/', back=.true.)
    lead = path(1:k)
    name = path(k + 1:)
    p%dir = '.'
    if (k == 1) p%dir = '/'
    if (k > 1) p%dir = path(1:k - 1)
    j = index(name, '.', back=.true.)
    stem = name
    ext = ''
    if (j > 1) then
      stem = name(1:j - 1)
      ext = name(j:)
    end if
    p%h5 = path
    p%xdmf = lead//stem//'.xdmf'
    p%failed_h5 = lead//stem//'.failed'//ext
    p%failed_xdmf = lead//stem//'.failed.xdmf'
    p%checkpoint = lead//stem//'.checkpoint.h5'
    p%restart = ''
    p%with_xdmf = with_xdmf
  end function output_names

  !> Before any work, without creating anything: the output names a file, its directory
  !! exists or can be made (the deepest existing part is a writable directory), and none of
  !! the names the run may write (final and failed, HDF5 and XDMF, and the checkpoint when
  !! the deck asks for checkpoints) is the deck, a particle file, a directory, or, with
  !! overwrite = .false., an existing file: the one exception is the checkpoint given to
  !! --restart (restart, its path), which the continued run replaces by its own. Real paths
  !! are compared, so './deck.nml' or a link to the deck's directory is the deck too.
  subroutine check_output_path(deck, err, restart)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: restart
    type(output_path_t) :: p
    character(len=:), allocatable :: where, top, rp, name, d, sep
    integer :: k, m, nnames
    p = output_names(trim(deck%output%file), deck%run%mode == 'dynamic')
    where = "deck '"//deck%path//"', group &output, variable file = '"//p%h5//"': "
    name = base_name(p%h5)
    if (is_dir(p%h5)) name = ''
    if (name == '' .or. name == '.' .or. name == '..') then
      sep = '/'
      if (p%h5(len(p%h5):) == '/') sep = ''
      call set_error(err, where//"this is a directory; give a file name such as '"// &
        p%h5//sep//"run.h5'")
      return
    end if
    if (p%with_xdmf .and. lower(p%h5) == lower(p%xdmf)) then
      call set_error(err, where//"the XDMF file written beside it would have the same "// &
        "name; give a name ending in .h5")
      return
    end if
    top = existing_part(p%dir)
    if (.not. is_dir(top)) then
      call set_error(err, where//"'"//top//"' is not a directory, so directory '"//p%dir// &
        "' cannot be made; give a path in a writable directory")
      return
    end if
    if (.not. writable_dir(top)) then
      call set_error(err, where//"directory '"//top//"' is not writable; give a writable path")
      return
    end if
    if (len(fs_refusal(top)) > 0) then
      call set_error(err, where//"directory '"//top//"' "//fs_refusal(top)//"; give a "// &
        "path on a writable file system")
      return
    end if
    nnames = merge(4, 2, p%with_xdmf)
    if (p%with_xdmf .and. deck%output%checkpoint_every > 0) nnames = 5
    do k = 1, nnames
      ! every name the run may write: HDF5 and failed HDF5, the two XDMF files, and the
      ! checkpoint
      select case (k)
      case (1)
        d = p%h5
      case (2)
        d = p%failed_h5
      case (3)
        d = p%xdmf
      case (4)
        d = p%failed_xdmf
      case default
        d = p%checkpoint
      end select
      if (is_dir(d)) then
        call set_error(err, where//"'"//d//"', a name this run may write, is a "// &
          "directory; give another output name")
        return
      end if
      if (.not. path_exists(d)) cycle
      rp = real_path(d)
      if (rp == real_path(deck%path)) then
        call set_error(err, where//"'"//d//"' is the deck itself ("//rp//"); writing "// &
          "there would destroy it: give another output name")
        return
      end if
      do m = 1, deck%nbodies
        if (len_trim(deck%bodies(m)%file) == 0) cycle
        if (rp /= real_path(trim(deck%bodies(m)%file))) cycle
        call set_error(err, where//"'"//d//"' is the "//trim(merge('gmsh script  ', &
          'particle file', deck%bodies(m)%shape == 'geo'))//" of &body '"// &
          trim(deck%bodies(m)%name)//"' ("//rp//"); give another output name")
        return
      end do
      if (k == 5 .and. present(restart)) then
        ! the checkpoint this run continues from: replaced by the run's own checkpoints
        if (rp == real_path(restart)) cycle
      end if
      if (.not. deck%output%overwrite) then
        call set_error(err, where//"'"//d//"' exists and overwrite = .false.; remove "// &
          "or rename it, give another output name, or set overwrite = .true.")
        return
      end if
    end do
  end subroutine check_output_path

  !> Just before the first write: make the directory, pick this run's temporary names and
  !! create its files there exclusively (the HDF5 file f, open, and an empty XDMF file when
  !! with_xdmf). Nothing existing is opened, truncated or replaced. A dynamic run (with_xdmf)
  !! whose deck asks for checkpoints also gets a free temporary checkpoint name; restart is
  !! the checkpoint it continues from, if any.
  subroutine output_open(deck, with_xdmf, p, f, err, restart)
    type(deck_t), intent(in) :: deck
    logical, intent(in) :: with_xdmf
    type(output_path_t), intent(out) :: p
    type(h5file_t), intent(out) :: f
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: restart
    character(len=:), allocatable :: where, failed, tag
    character(len=512) :: msg
    logical :: ok
    integer :: try, u, ios
    p = output_names(trim(deck%output%file), with_xdmf)
    p%overwrite = deck%output%overwrite
    p%with_checkpoint = with_xdmf .and. deck%output%checkpoint_every > 0
    if (present(restart)) p%restart = real_path(restart)
    where = "deck '"//deck%path//"', group &output, variable file = '"//p%h5//"': "
    call make_dirs(p%dir, ok, failed)
    if (.not. ok) then
      call set_error(err, where//"directory '"//failed//"' cannot be created; give a "// &
        "writable path", exit_run_failed)
      return
    end if
    do try = 0, max_tries
      tag = itoa(process_id())
      if (try > 0) tag = tag//'-'//itoa(try)
      p%tmp_h5 = temp_name(p%h5, tag)
      p%tmp_xdmf = temp_name(p%xdmf, tag)
      p%tmp_checkpoint = temp_name(p%checkpoint, tag)
      if (path_exists(p%tmp_h5)) cycle
      if (p%with_checkpoint) then
        if (path_exists(p%tmp_checkpoint)) cycle
      end if
      if (.not. with_xdmf) exit
      if (path_exists(p%tmp_xdmf)) cycle
      ! status = 'new' is open(2) with O_CREAT | O_EXCL: the name is ours or the open fails
      open(newunit=u, file=p%tmp_xdmf, status='new', action='write', iostat=ios, iomsg=msg)
      if (ios == 0) then
        ! valid from the start: an empty series until the first snapshot rewrites it
        write(u, '(a)') '<?xml version="1.0" ?>', '<Xdmf Version="3.0"><Domain>', &
          '<Grid Name="mfcd" GridType="Collection" CollectionType="Temporal">', &
          '</Grid></Domain></Xdmf>'
        close(u)
        exit
      end if
      if (.not. path_exists(p%tmp_xdmf)) then
        call set_error(err, where//"cannot create '"//p%tmp_xdmf//"' ("//trim(msg)// &
          "); give a writable path", exit_run_failed)
        return
      end if
    end do
    if (try > max_tries) then
      call set_error(err, where//"no free temporary name beside it ('"//p%tmp_h5// &
        "' and "//itoa(max_tries)//" more exist); remove the stale .tmp- files", &
        exit_run_failed)
      return
    end if
    call h5_create(f, p%tmp_h5, err)
    if (allocated(err)) then
      if (with_xdmf) ok = remove_file(p%tmp_xdmf)
      return
    end if
    call log_print('output: writing '//output_files_text(p, .true., temporary=.true.)// &
      '; renamed to '//output_files_text(p, .true.)//' when the run completes, to '// &
      output_files_text(p, .false.)//' if it fails')
  end subroutine output_open

  !> At the end of the run (its files closed): rename this run's files onto the final names
  !! when completed, onto the failed-run names otherwise. With overwrite = .false. a name
  !! that appeared during the run is not replaced (link(2) then unlink(2): link fails when
  !! the name exists) and the file keeps its temporary name. note says where the files are.
  subroutine output_commit(p, completed, note, err)
    type(output_path_t), intent(in) :: p
    logical, intent(in) :: completed
    character(len=:), allocatable, intent(out) :: note
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: dst_h5, dst_xdmf, kept, why
    logical :: earlier
    earlier = path_exists(p%h5)
    dst_h5 = p%failed_h5
    dst_xdmf = p%failed_xdmf
    if (completed) then
      dst_h5 = p%h5
      dst_xdmf = p%xdmf
    end if
    kept = ''
    ! the HDF5 file first; should it stay behind, its XDMF file stays with it
    if (.not. move(p%tmp_h5, dst_h5)) then
      kept = p%tmp_h5
      if (p%with_xdmf) kept = kept//' and '//p%tmp_xdmf
    else if (p%with_xdmf) then
      if (.not. move(p%tmp_xdmf, dst_xdmf)) kept = p%tmp_xdmf
    end if
    if (len(kept) > 0) then
      why = 'rename(2) failed'
      if (.not. p%overwrite) why = 'a file of that name appeared during the run, and '// &
        'overwrite = .false.'
      note = kept
      call set_error(err, "output: cannot rename "//kept//" to "// &
        output_files_text(p, completed)//" ("//why//"); the results are in "//kept, &
        exit_run_failed)
      return
    end if
    note = output_files_text(p, completed)
    if (.not. completed .and. earlier) note = note//'; the earlier result '//p%h5// &
      ' is untouched'
  contains
    logical function move(tmp, dst) result(ok)
      character(len=*), intent(in) :: tmp, dst
      ok = move_file(tmp, dst, p%overwrite)
    end function move
  end subroutine output_commit

  !> Move this run's file tmp onto dst: rename(2) when replace, else link(2) and unlink(2),
  !! which never replace dst (rename is the fallback on file systems without hard links,
  !! when dst is still absent).
  logical function move_file(tmp, dst, replace) result(ok)
    character(len=*), intent(in) :: tmp, dst
    logical, intent(in) :: replace
    if (replace) then
      ok = rename_file(tmp, dst)
    else if (link_file(tmp, dst)) then
      ok = .true.
      ! should unlink fail, tmp stays as a second name of the result: harmless
      if (.not. remove_file(tmp)) ok = .true.
    else
      ok = .false.
      if (.not. path_exists(dst)) ok = rename_file(tmp, dst)
    end if
  end function move_file

  !> The checkpoint just written and closed at p%tmp_checkpoint takes the name
  !! p%checkpoint in one rename(2), replacing the previous checkpoint: this run's own, the
  !! one the run was restarted from, or (overwrite = .true.) an earlier run's. With
  !! overwrite = .false. a checkpoint that is neither is never replaced (checked before the
  !! run; should one appear meanwhile the commit fails). On failure the temporary file is
  !! removed and the previous checkpoint stays as it was (err, exit 1).
  subroutine checkpoint_commit(p, err)
    type(output_path_t), intent(inout) :: p
    type(error_t), allocatable, intent(inout) :: err
    logical :: replace, ok
    character(len=:), allocatable :: why
    replace = p%overwrite .or. p%own_checkpoint
    if (.not. replace .and. len(p%restart) > 0) then
      if (path_exists(p%checkpoint)) replace = real_path(p%checkpoint) == p%restart
    end if
    if (.not. move_file(p%tmp_checkpoint, p%checkpoint, replace)) then
      ok = remove_file(p%tmp_checkpoint)
      why = 'rename(2) failed'
      if (.not. replace) why = 'a file of that name appeared during the run, and '// &
        'overwrite = .false.'
      call set_error(err, "output: cannot rename the checkpoint "//p%tmp_checkpoint// &
        " to "//p%checkpoint//" ("//why//"); the previous checkpoint is unchanged", &
        exit_run_failed)
      return
    end if
    p%own_checkpoint = .true.
  end subroutine checkpoint_commit

  !> 'out/run.h5 and out/run.xdmf': the files of a completed (or failed) run, or their
  !! temporary names while it runs.
  function output_files_text(p, completed, temporary) result(s)
    type(output_path_t), intent(in) :: p
    logical, intent(in) :: completed
    logical, intent(in), optional :: temporary
    character(len=:), allocatable :: s
    logical :: tmp
    tmp = .false.
    if (present(temporary)) tmp = temporary
    if (tmp) then
      s = p%tmp_h5
      if (p%with_xdmf) s = s//' and '//p%tmp_xdmf
    else if (completed) then
      s = p%h5
      if (p%with_xdmf) s = s//' and '//p%xdmf
    else
      s = p%failed_h5
      if (p%with_xdmf) s = s//' and '//p%failed_xdmf
    end if
  end function output_files_text

  !> The files a completed run of deck leaves: what the program's last line names.
  function output_result_text(deck) result(s)
    type(deck_t), intent(in) :: deck
    character(len=:), allocatable :: s
    s = output_files_text(output_names(trim(deck%output%file), &
      deck%run%mode == 'dynamic'), .true.)
  end function output_result_text

  !> The last component of path (what an XDMF file in the same directory calls it).
  pure function base_name(path) result(s)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: s
    s = path(index(path, '/', back=.true.) + 1:)
  end function base_name

  !> <dir>/.<name>.tmp-<tag> for <dir>/<name>: hidden, and never a name mfcd's results or
  !! a user's files have.
  pure function temp_name(path, tag) result(s)
    character(len=*), intent(in) :: path, tag
    character(len=:), allocatable :: s
    integer :: k
    k = index(path, '/', back=.true.)
    s = path(1:k)//'.'//path(k + 1:)//'.tmp-'//tag
  end function temp_name

  !> A scratch file's name for the run of deck, tagged tag (a process id and what it
  !! holds): hidden beside the output file's name, as its temporary names are, in the
  !! deepest part of the output's directory that exists (checked writable by
  !! check_output_path; nothing is made before the output is). The caller creates it
  !! exclusively and removes it.
  function scratch_name(deck, tag) result(s)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: tag
    character(len=:), allocatable :: s
    type(output_path_t) :: p
    p = output_names(trim(deck%output%file), .false.)
    s = temp_name(existing_part(p%dir)//'/'//base_name(p%h5), tag)
  end function scratch_name

  !> The deepest part of directory dir that exists ('.' or '/' at worst).
  function existing_part(dir) result(d)
    character(len=*), intent(in) :: dir
    character(len=:), allocatable :: d
    integer :: k
    d = dir
    do while (.not. path_exists(d))
      if (d == '.' .or. d == '/') exit
      k = index(d, '/', back=.true.)
      if (k == 0) then
        d = '.'
      else if (k == 1) then
        d = '/'
      else
        d = d(1:k - 1)
      end if
    end do
  end function existing_part
end module output_path_m
