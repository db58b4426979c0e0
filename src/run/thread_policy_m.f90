!> OpenMP threads that share a machine gracefully.
!!
!! GNU OpenMP (libgomp) lets a thread that waits at a barrier spin up to 300,000 times before
!! it sleeps. On a machine whose cores are all busy (a neighbour's job, a second mfcd run)
!! the spinning thread holds a core the thread it waits for needs, and a 2-thread run
!! becomes several times slower than a 1-thread one (doc/benchmarks.md, "Sharing a
!! machine"). A short spin (1,000) keeps an idle machine's speed and lets a busy one's
!! threads sleep. libgomp reads its settings from the environment once, when the program
!! loads, before the first statement of the program runs; so when the user has set neither
!! OMP_WAIT_POLICY nor GOMP_SPINCOUNT, mfcd sets GOMP_SPINCOUNT and executes itself again
!! (execv of /proc/self/exe with the same arguments). Any setting of those two variables by
!! the user is kept as it is (OMP_WAIT_POLICY=active restores libgomp's default spin).
module thread_policy_m
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_ptr, c_null_char, c_null_ptr, &
    c_loc, c_associated
  use strings_m, only: itoa
  implicit none
  private
  public :: thread_policy_apply, thread_policy_text, spin_default

  !> Spins before a waiting thread sleeps: libgomp's own value for oversubscribed runs
  !! ("throttled"). Measured on the free-bar benchmark (doc/benchmarks.md): idle machine
  !! within noise of the full spin, with one busy neighbour 1.1x the 1-thread time
  !! instead of 1.3x, with two busy neighbours 1.2x instead of 1.6x.
  integer, parameter :: spin_default = 1000

  interface
    function c_getenv(name) bind(c, name='getenv') result(p)
      import :: c_char, c_ptr
      character(kind=c_char), intent(in) :: name(*)
      type(c_ptr) :: p
    end function c_getenv
    function c_setenv(name, value, overwrite) bind(c, name='setenv') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value :: overwrite
      integer(c_int) :: rc
    end function c_setenv
    function c_execv(path, argv) bind(c, name='execv') result(rc)
      import :: c_char, c_int, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(in) :: argv(*)
      integer(c_int) :: rc
    end function c_execv
  end interface

contains

  !> When neither OMP_WAIT_POLICY nor GOMP_SPINCOUNT is set: set GOMP_SPINCOUNT to
  !! spin_default and run this program again with the same arguments. Returns (and the run
  !! goes on with libgomp's defaults) only when a variable is set or the execv fails.
  !! Call it first, before anything is printed or opened.
  subroutine thread_policy_apply()
    character(kind=c_char), allocatable, target :: buf(:)
    type(c_ptr), allocatable :: argv(:)
    character(len=:), allocatable :: arg
    integer :: i, n, na, k, total, rc
    if (is_set('OMP_WAIT_POLICY')) return
    if (is_set('GOMP_SPINCOUNT')) return
    if (c_setenv('GOMP_SPINCOUNT'//c_null_char, itoa(spin_default)//c_null_char, &
      1_c_int) /= 0) return
    na = command_argument_count()
    total = 0
    do i = 0, na
      call get_command_argument(i, length=n)
      total = total + n + 1
    end do
    allocate(buf(total), argv(na + 2))
    k = 1
    do i = 0, na
      call get_command_argument(i, length=n)
      allocate(character(len=n) :: arg)
      call get_command_argument(i, arg)
      buf(k:k + n - 1) = transfer(arg, buf(1:n))
      buf(k + n) = c_null_char
      argv(i + 1) = c_loc(buf(k))
      k = k + n + 1
      deallocate(arg)
    end do
    argv(na + 2) = c_null_ptr
    rc = c_execv('/proc/self/exe'//c_null_char, argv)
    ! execv returns only on failure: go on in this process with libgomp's defaults
  end subroutine thread_policy_apply

  !> How waiting threads behave in this run, for the log.
  function thread_policy_text() result(s)
    character(len=:), allocatable :: s
    if (is_set('OMP_WAIT_POLICY')) then
      s = 'OMP_WAIT_POLICY='//env('OMP_WAIT_POLICY')
      if (is_set('GOMP_SPINCOUNT')) s = s//', GOMP_SPINCOUNT='//env('GOMP_SPINCOUNT')
    else if (is_set('GOMP_SPINCOUNT')) then
      s = 'GOMP_SPINCOUNT='//env('GOMP_SPINCOUNT')
    else
      s = "libgomp's default spin"
    end if
  end function thread_policy_text

  logical function is_set(name)
    character(len=*), intent(in) :: name
    is_set = c_associated(c_getenv(name//c_null_char))
  end function is_set

  function env(name) result(v)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: v
    integer :: n
    call get_environment_variable(name, length=n)
    allocate(character(len=n) :: v)
    if (n > 0) call get_environment_variable(name, v)
  end function env
end module thread_policy_m
