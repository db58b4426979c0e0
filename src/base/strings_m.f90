!> Small string helpers for messages and names.
module strings_m
  use kinds_m, only: wp
  implicit none
  private
  public :: lower, itoa, rtoa, join_names, edit_distance

contains

  !> Levenshtein distance between s and t (insertions, deletions, substitutions), for the
  !! nearest valid name in a message.
  pure integer function edit_distance(s, t) result(d)
    character(len=*), intent(in) :: s, t
    integer :: row(0:len(t)), prev, tmp, i, j
    row = [(j, j = 0, len(t))]
    do i = 1, len(s)
      prev = row(0)
      row(0) = i
      do j = 1, len(t)
        tmp = row(j)
        row(j) = min(row(j) + 1, row(j - 1) + 1, prev + merge(0, 1, s(i:i) == t(j:j)))
        prev = tmp
      end do
    end do
    d = row(len(t))
  end function edit_distance

  !> 'a, b, c' from a list of names.
  pure function join_names(names) result(s)
    character(len=*), intent(in) :: names(:)
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//trim(names(k))
    end do
  end function join_names

  !> Lower-case copy (ASCII).
  pure function lower(s) result(r)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: r
    integer :: k, c
    r = s
    do k = 1, len(s)
      c = iachar(s(k:k))
      if (c >= iachar('A') .and. c <= iachar('Z')) r(k:k) = achar(c + 32)
    end do
  end function lower

  !> Integer as text.
  pure function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function itoa

  !> Real as text with 6 significant digits.
  pure function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write(buf, '(g0.6)') x
    s = trim(adjustl(buf))
  end function rtoa
end module strings_m
