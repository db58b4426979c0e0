!> Freed memory returned to the system (memory_policy.c says why): a rank's peak resident
!! memory then holds the arrays alive at its peak, not the pages of whole-body arrays freed
!! before it. Measured (doc/parallel.md, "Weak scaling of the set-up"): the 3D Taylor bar,
!! 30 mm a rank on 8 ranks, peak per rank 0.94-0.96 -> 0.87-0.90 GB.
module memory_policy_m
  use, intrinsic :: iso_c_binding, only: c_int, c_long_long
  use kinds_m, only: i64
  implicit none
  private
  public :: memory_policy_apply, mapped_bytes, resident_kib, memory_trim, read_bytes

  interface
    function c_memory_policy() bind(c, name='mfcd_memory_policy') result(rc)
      import :: c_int
      integer(c_int) :: rc
    end function c_memory_policy
    function c_memory_trim() bind(c, name='mfcd_memory_trim') result(rc)
      import :: c_int
      integer(c_int) :: rc
    end function c_memory_trim
    function c_mapped_bytes() bind(c, name='mfcd_mapped_bytes') result(n)
      import :: c_long_long
      integer(c_long_long) :: n
    end function c_mapped_bytes
  end interface

contains

  !> Set the policy once, before the first large allocation; set: whether it was (not when
  !! the user's MALLOC_MMAP_THRESHOLD_ or another C library leaves it as it is).
  subroutine memory_policy_apply(set)
    logical, intent(out), optional :: set
    logical :: done
    done = c_memory_policy() == 1_c_int
    if (present(set)) set = done
  end subroutine memory_policy_apply

  !> The free pages the C library still holds returned to the system (glibc's
  !! malloc_trim): after gmsh has meshed a whole model in its thread (mfcd_mpi's rank 0),
  !! whose arena keeps the pages of its freed small blocks otherwise.
  subroutine memory_trim()
    integer(c_int) :: rc
    rc = c_memory_trim()
  end subroutine memory_trim

  !> The bytes the C library holds in blocks mapped apart (glibc's mallinfo2 hblkhd), -1
  !! where it does not tell (the test of the policy).
  integer(i64) function mapped_bytes() result(n)
    n = int(c_mapped_bytes(), i64)
  end function mapped_bytes

  !> This process's resident memory now and its peak so far (VmRSS and VmHWM of
  !! /proc/self/status, KiB), -1 each where the system does not tell (not Linux).
  subroutine resident_kib(now, peak)
    integer(i64), intent(out) :: now, peak
    character(len=256) :: line
    integer :: u, ios
    now = -1_i64
    peak = -1_i64
    open(newunit=u, file='/proc/self/status', action='read', status='old', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, 'VmRSS:') == 1) read(line(7:), *, iostat=ios) now
      if (index(line, 'VmHWM:') == 1) read(line(7:), *, iostat=ios) peak
      if (ios /= 0) exit
    end do
    close(u)
  end subroutine resident_kib

  !> The bytes this process has read so far through read calls (rchar of /proc/self/io:
  !! files, the page cache's too, pipes), -1 where the system does not tell (not Linux):
  !! what a rank of mfcd_mpi reads of a mesh file (doc/parallel.md).
  integer(i64) function read_bytes() result(n)
    character(len=256) :: line
    integer :: u, ios
    n = -1_i64
    open(newunit=u, file='/proc/self/io', action='read', status='old', iostat=ios)
    if (ios /= 0) return
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (index(line, 'rchar:') == 1) then
        read(line(7:), *, iostat=ios) n
        exit
      end if
    end do
    close(u)
  end function read_bytes
end module memory_policy_m
