!> The program mfcd: meshfree contact detection (Li, Qian, Liu, Belytschko, CMAME 190, 2001).
!! Usage: mfcd [--check] [--restart checkpoint.h5] deck.nml | --help | --version.
!! Exit codes: 0 success, 2 bad input (nothing written), 1 a run that failed.
!! The log (stdout) is flushed line by line; its last line says how the run ended.
program mfcd
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use errors_m, only: error_t, exit_bad_input
  use strings_m, only: itoa
  use version_m, only: code_name, code_version, git_commit
  use deck_m, only: deck_t, read_deck
  use body_m, only: body_t
  use body_setup_m, only: build_bodies
  use setup_memory_m, only: check_memory
  use run_output_m, only: timestamp
  use output_path_m, only: check_output_path, output_result_text
  use file_system_m, only: same_out_err
  use run_checkpoint_m, only: checkpoint_check, checkpoint_info_t, body_fingerprints
  use rank_comm_m, only: single_rank_t
  use log_m, only: log_print, log_flush
  use detect_run_m, only: run_detect
  use explicit_driver_m, only: run_dynamic
  use run_domain_m, only: serial_domain_t, serial_domain_init
  use dynamic_setup_m, only: dynamic_setup_t, setup_dynamic
  use thread_policy_m, only: thread_policy_apply, thread_policy_text
  use memory_policy_m, only: memory_policy_apply
  use gmsh_mesh_m, only: gmsh_built_in, gmsh_version
  use omp_lib, only: omp_get_max_threads
  implicit none
  type(deck_t) :: deck
  type(body_t), allocatable :: bodies(:)
  type(dynamic_setup_t) :: su
  type(error_t), allocatable :: err
  character(len=:), allocatable :: deck_path, restart_path
  character(len=1024) :: arg
  logical :: check_only, restart_next
  integer :: i, nargs
  type(checkpoint_info_t) :: ckpt
  !> one rank: the run's parts are its solids
  type(serial_domain_t), target :: one
  type(single_rank_t) :: one_rank

  ! first, before anything is printed: a short spin for waiting OpenMP threads (it may run
  ! this program again with GOMP_SPINCOUNT set; thread_policy_m says why)
  call thread_policy_apply()
  ! freed large blocks go back to the system (memory_policy_m)
  call memory_policy_apply()
  check_only = .false.
  restart_next = .false.
  nargs = command_argument_count()
  deck_path = ''
  restart_path = ''
  do i = 1, nargs
    call get_command_argument(i, arg)
    if (restart_next) then
      restart_path = trim(arg)
      restart_next = .false.
      cycle
    end if
    if (arg(1:10) == '--restart=') then
      restart_path = trim(arg(11:))
      restart_next = len(restart_path) == 0
      if (restart_next) exit
      cycle
    end if
    select case (trim(arg))
    case ('-h', '--help')
      call usage(output_unit)
      stop
    case ('-V', '--version')
      write(output_unit, '(a)') code_name//' '//code_version//' (git '//git_commit//')'
      if (gmsh_built_in) then
        write(output_unit, '(a)') 'gmsh '//gmsh_version()//": &body shape = 'geo' "// &
          "meshes .geo scripts in memory"
      else
        write(output_unit, '(a)') "gmsh: not built in (&body shape = 'geo' is refused; "// &
          "bash tools/setup.sh --gmsh, then rebuild)"
      end if
      stop
    case ('--check')
      check_only = .true.
    case ('--restart')
      restart_next = .true.
    case default
      if (arg(1:1) == '-') then
        write(error_unit, '(a)') 'mfcd: error: unknown option '//trim(arg)
        call usage(error_unit)
        stop exit_bad_input, quiet=.true.
      end if
      if (len(deck_path) > 0) then
        write(error_unit, '(a)') 'mfcd: error: give one deck only (got '''//deck_path// &
          ''' and '''//trim(arg)//''')'
        stop exit_bad_input, quiet=.true.
      end if
      deck_path = trim(arg)
    end select
  end do
  if (restart_next) then
    write(error_unit, '(a)') 'mfcd: error: --restart needs the checkpoint file: '// &
      'mfcd --restart run.checkpoint.h5 deck.nml'
    stop exit_bad_input, quiet=.true.
  end if
  if (len(deck_path) == 0) then
    write(error_unit, '(a)') 'mfcd: error: no deck given'
    call usage(error_unit)
    stop exit_bad_input, quiet=.true.
  end if

  call log_print(code_name//' '//code_version//' (git '//git_commit//') '// &
    timestamp()//' deck '//deck_path)
  call log_print('threads: '//itoa(omp_get_max_threads())//' (OMP_NUM_THREADS); waiting '// &
    'threads: '//thread_policy_text())
  call read_deck(deck_path, deck, err)
  if (.not. allocated(err)) call echo_deck(deck)
  if (.not. allocated(err)) call check_memory(deck, err)
  if (.not. allocated(err)) call build_bodies(deck, bodies, err)
  ! (what a checkpoint recognises its bodies by: exact sums, the same on any rank count)
  if (.not. allocated(err)) call body_fingerprints(bodies, one_rank)
  ! again with the particle files read: the tables of the set-up are still to come
  if (.not. allocated(err)) call check_memory(deck, err, bodies)
  ! the set-up of a dynamic run has checks of its own: made before anything is written, by a
  ! run (which then steps from it) and by --check alike
  if (.not. allocated(err) .and. deck%run%mode == 'dynamic') &
    call setup_dynamic(deck, bodies, su, err)
  if (.not. allocated(err) .and. len(restart_path) > 0) call check_restart()
  ! the output destination too: --check makes every check the run makes before it writes
  if (.not. allocated(err)) call check_output_path(deck, err, restart_path)
  if (allocated(err)) call fail(err)
  if (check_only) then
    write(output_unit, '(a)') 'mfcd: deck '''//deck_path//''' is valid'
    stop
  end if

  select case (trim(deck%run%mode))
  case ('detect')
    call run_detect(deck, bodies, err)
  case ('dynamic')
    call serial_domain_init(one)
    if (len(restart_path) > 0) then
      call run_dynamic(deck, bodies, su, one, err, restart_path)
    else
      call run_dynamic(deck, bodies, su, one, err)
    end if
  end select
  if (allocated(err)) call fail(err)
  call log_print('mfcd: completed: wrote '//output_result_text(deck))

contains

  !> The checkpoint given to --restart must be one this deck's run wrote (run_checkpoint_m).
  subroutine check_restart()
    call checkpoint_check(restart_path, deck, bodies, ckpt, err)
    if (.not. allocated(err)) call log_print("restart: checkpoint '"//restart_path// &
      "' of this deck, step "//itoa(ckpt%step)//", is valid")
  end subroutine check_restart

  !> Stop with the error: on stderr after every log line before it, then the log's last
  !! line saying how the run ended, so a log file read alone tells it too. Where the log
  !! and stderr are one file (a terminal, a batch log taking both), the message is not
  !! repeated: the last line points at it.
  subroutine fail(e)
    type(error_t), intent(in) :: e
    character(len=:), allocatable :: what
    call log_flush()
    write(error_unit, '(a)') 'mfcd: error: '//e%message
    flush(error_unit)
    what = ': '//e%message
    if (same_out_err()) what = ' (the error above)'
    if (e%code == exit_bad_input) then
      call log_print('mfcd: bad input (exit 2), nothing written'//what)
      stop exit_bad_input, quiet=.true.
    end if
    call log_print('mfcd: failed (exit 1)'//what)
    stop 1, quiet=.true.
  end subroutine fail

  subroutine echo_deck(d)
    type(deck_t), intent(in) :: d
    integer :: a, z
    a = 1
    do while (a <= len(d%text))
      z = index(d%text(a:), new_line('a'))
      if (z == 0) then
        call log_print('deck| '//d%text(a:))
        exit
      end if
      call log_print('deck| '//d%text(a:a + z - 2))
      a = a + z
    end do
  end subroutine echo_deck

  subroutine usage(u)
    integer, intent(in) :: u
    write(u, '(a)') 'usage: mfcd [--check] [--restart CHECKPOINT.h5] DECK.nml'
    write(u, '(a)') '       mfcd --help | --version'
    write(u, '(a)') ''
    write(u, '(a)') 'Runs the namelist deck DECK.nml (groups &run, &body, &detection, &output;'
    write(u, '(a)') 'see doc/deck.md) and writes one HDF5 file (doc/output.md).'
    write(u, '(a)') '  --check     read and validate the deck, build the bodies and (mode'
    write(u, '(a)') '              dynamic) the set-up of the first step (and the checkpoint'
    write(u, '(a)') '              with --restart), check the output destination; write'
    write(u, '(a)') '              nothing'
    write(u, '(a)') '  --restart F continue the dynamic run of DECK.nml from its checkpoint F'
    write(u, '(a)') '              (written with &output checkpoint_every; the deck must be'
    write(u, '(a)') '              the one that wrote it, unchanged)'
    write(u, '(a)') '  --help      this text'
    write(u, '(a)') '  --version   code version and git commit, and whether gmsh is built in'
    write(u, '(a)') 'Threads: OMP_NUM_THREADS; waiting threads spin GOMP_SPINCOUNT=1000 times'
    write(u, '(a)') 'unless OMP_WAIT_POLICY or GOMP_SPINCOUNT is set (doc/benchmarks.md).'
    write(u, '(a)') 'Exit codes: 0 ok, 2 bad input (nothing'
    write(u, '(a)') 'written), 1 run failed (its files kept as <stem>.failed.h5 and .xdmf).'
  end subroutine usage
end program mfcd
