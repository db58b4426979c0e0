!> The run log on standard output, one line at a time and flushed as it is written. When
!! stdout is a file or a pipe gfortran buffers it: without the flush a long run shows nothing
!! for minutes, and the error message on stderr lands above the log lines that led to it.
!! Modules that format a line with a write(output_unit, fmt) of their own flush after it.
module log_m
  use, intrinsic :: iso_fortran_env, only: output_unit
  implicit none
  private
  public :: log_print, log_flush

contains

  !> Write line to the log and flush it.
  subroutine log_print(line)
    character(len=*), intent(in) :: line
    write(output_unit, '(a)') line
    flush(output_unit)
  end subroutine log_print

  !> Flush the log after a formatted write(output_unit, ...).
  subroutine log_flush()
    flush(output_unit)
  end subroutine log_flush
end module log_m
