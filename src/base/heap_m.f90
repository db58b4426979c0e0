!> Freed small blocks given back to the system (heap.c): a builder that frees many blocks
!! below the mmap threshold calls heap_return before it allocates its large arrays, so that
!! their freed pages do not count in its peak (doc/parallel.md, "Bodies made per rank").
module heap_m
  use, intrinsic :: iso_c_binding, only: c_int
  implicit none
  private
  public :: heap_return

  interface
    function c_heap_return() bind(c, name='mfcd_heap_return') result(rc)
      import :: c_int
      integer(c_int) :: rc
    end function c_heap_return
  end interface

contains

  !> The heap's free pages back to the system (glibc's malloc_trim; elsewhere nothing).
  subroutine heap_return()
    integer(c_int) :: rc
    rc = c_heap_return()
  end subroutine heap_return
end module heap_m
