!> A task run in a confined thread, with limits on its time and memory (src/io/confine.c):
!! the task reads files but creates, changes or removes none, starts no process, opens no
!! socket and reads nothing from standard input; it runs with / as its working directory
!! and /dev/null as HOME, and what it changes of the process (directory, environment,
!! locale, signal dispositions, stack limit) is put back after it. Past its wall-clock
!! limit, or when the process's resident memory has grown by more than its memory limit,
!! the process ends at once with exit code 2 and the caller's message, written as the
!! program writes a bad-input error (stderr) and the log's last line (stdout); so does a
!! crash of the task (msg_crash). mfcd runs gmsh this way (gmsh_mesh_m).
module confine_m
  use, intrinsic :: iso_c_binding, only: c_funptr, c_ptr, c_double, c_long_long, c_int, &
    c_char, c_null_char
  use kinds_m, only: wp, i64
  implicit none
  private
  public :: confine_limits_t, confined_run, errno_text

  !> The limits of a confined task, and what the process says when it ends it.
  type :: confine_limits_t
    real(wp) :: seconds = 600.0_wp          !< wall-clock time, s
    integer(i64) :: max_growth = 0_i64      !< resident memory growth, bytes (<= 0: none)
    character(len=:), allocatable :: msg_time, msg_memory, msg_crash
  end type confine_limits_t

  !> The thread's stack: deep recursion in a mesher needs more than a default 8 MiB (only
  !! the pages touched take memory).
  integer(c_long_long), parameter :: stack_bytes = 256_c_long_long*1024*1024

  interface
    function c_confined_run(fn, arg, seconds, max_growth, stack, msg_time, len_time, &
      msg_memory, len_memory, msg_crash, len_crash) bind(c, name='mfcd_confined_run') &
      result(rc)
      import :: c_funptr, c_ptr, c_double, c_long_long, c_int, c_char
      type(c_funptr), value :: fn
      type(c_ptr), value :: arg
      real(c_double), value :: seconds
      integer(c_long_long), value :: max_growth, stack
      character(kind=c_char), intent(in) :: msg_time(*), msg_memory(*), msg_crash(*)
      integer(c_int), value :: len_time, len_memory, len_crash
      integer(c_int) :: rc
    end function c_confined_run
    subroutine c_errno_text(e, buf, n) bind(c, name='mfcd_errno_text')
      import :: c_int, c_char
      integer(c_int), value :: e, n
      character(kind=c_char), intent(out) :: buf(*)
    end subroutine c_errno_text
  end interface

contains

  !> Run the C-callable subroutine fn (bind(C), one type(c_ptr) argument, by value) on arg
  !! in a confined thread within limits (the module's header). failure is '' when the task
  !! ran; otherwise the task did not run, and failure says why (no confinement on this
  !! system, or no thread).
  subroutine confined_run(fn, arg, limits, failure)
    type(c_funptr), intent(in) :: fn
    type(c_ptr), intent(in) :: arg
    type(confine_limits_t), intent(in) :: limits
    character(len=:), allocatable, intent(out) :: failure
    character(len=:), allocatable, target :: mt, mm, mc
    integer(c_int) :: rc
    mt = 'the task took longer than its time limit'
    mm = 'the task grew past its memory limit'
    mc = 'the task crashed'
    if (allocated(limits%msg_time)) mt = limits%msg_time
    if (allocated(limits%msg_memory)) mm = limits%msg_memory
    if (allocated(limits%msg_crash)) mc = limits%msg_crash
    ! the messages stay allocated until the task ends (the C side keeps pointers to them)
    mt = mt//c_null_char
    mm = mm//c_null_char
    mc = mc//c_null_char
    rc = c_confined_run(fn, arg, real(limits%seconds, c_double), &
      int(limits%max_growth, c_long_long), stack_bytes, mt, int(len(mt) - 1, c_int), mm, &
      int(len(mm) - 1, c_int), mc, int(len(mc) - 1, c_int))
    failure = ''
    if (rc /= 0) failure = errno_text(int(rc))
  end subroutine confined_run

  !> The system's text of errno e.
  function errno_text(e) result(t)
    integer, intent(in) :: e
    character(len=:), allocatable :: t
    character(kind=c_char) :: buf(256)
    integer :: i
    call c_errno_text(int(e, c_int), buf, int(size(buf), c_int))
    t = ''
    do i = 1, size(buf)
      if (buf(i) == c_null_char) exit
      t = t//buf(i)
    end do
  end function errno_text
end module confine_m
