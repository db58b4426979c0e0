!> Error reporting: library routines return an allocatable error_t instead of stopping.
!! Only the program prints and chooses the exit code (2 bad input, 1 failed run).
module errors_m
  implicit none
  private
  public :: error_t, set_error, exit_bad_input, exit_run_failed

  integer, parameter :: exit_bad_input = 2   !< deck or input file is wrong
  integer, parameter :: exit_run_failed = 1  !< the computation itself failed

  !> An error with its message (naming file, group, variable, value and fix) and exit code.
  type :: error_t
    character(len=:), allocatable :: message
    integer :: code = exit_bad_input
  end type error_t

contains

  !> Allocate err with message msg and (optional) exit code.
  subroutine set_error(err, msg, code)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in) :: msg
    integer, intent(in), optional :: code
    if (allocated(err)) deallocate(err)
    allocate(err)
    err%message = msg
    if (present(code)) err%code = code
  end subroutine set_error
end module errors_m
