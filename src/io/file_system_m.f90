!> The file system through libc, never through a shell: directories made one level at a
!! time with mkdir(2) (like mkdir -p), names resolved with realpath(3), files moved with
!! rename(2) or link(2). A path from the deck is only ever an argument of these calls, so
!! no character in it ($, `, ;, quotes) has any meaning but its own.
module file_system_m
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_ptr, c_null_char, c_associated, &
    c_long_long
  use confine_m, only: errno_text
  implicit none
  private
  public :: make_dirs, is_dir, writable_dir, path_exists, real_path, rename_file, &
    link_file, remove_file, process_id, read_plain_file, fs_refusal, same_out_err

  integer(c_int), parameter :: f_ok = 0, w_ok = 2, x_ok = 1   !< access(2) modes (POSIX)
  !> Permissions of a new directory before the umask: rwx for all, as mkdir(1) gives.
  integer(c_int), parameter :: dir_mode = int(o'777', c_int)
  !> Longest path realpath(3) returns (PATH_MAX on Linux, with room for the NUL).
  integer, parameter :: path_max = 4096

  interface
    ! mode_t is an unsigned int on Linux (32 bits), passed by value like a C int
    function c_mkdir(path, mode) bind(c, name='mkdir') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int) :: rc
    end function c_mkdir
    function c_access(path, mode) bind(c, name='access') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int) :: rc
    end function c_access
    function c_realpath(path, resolved) bind(c, name='realpath') result(p)
      import :: c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(out) :: resolved(*)
      type(c_ptr) :: p
    end function c_realpath
    function c_rename(old, new) bind(c, name='rename') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: rc
    end function c_rename
    function c_link(old, new) bind(c, name='link') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
      integer(c_int) :: rc
    end function c_link
    function c_unlink(path) bind(c, name='unlink') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: rc
    end function c_unlink
    function c_getpid() bind(c, name='getpid') result(pid)
      import :: c_int
      integer(c_int) :: pid
    end function c_getpid
    function c_open_regular(path, nofollow, max_bytes, size, kind, err_no) &
      bind(c, name='mfcd_open_regular') result(fd)
      import :: c_char, c_int, c_long_long
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: nofollow
      integer(c_long_long), value :: max_bytes
      integer(c_long_long), intent(out) :: size
      integer(c_int), intent(out) :: kind, err_no
      integer(c_int) :: fd
    end function c_open_regular
    function c_read_fd(fd, buf, n) bind(c, name='mfcd_read_fd') result(got)
      import :: c_char, c_int, c_long_long
      integer(c_int), value :: fd
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_long_long), value :: n
      integer(c_long_long) :: got
    end function c_read_fd
    function c_fs_refuses(path) bind(c, name='mfcd_fs_refuses') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: rc
    end function c_fs_refuses
    function c_same_out_err() bind(c, name='mfcd_same_out_err') result(rc)
      import :: c_int
      integer(c_int) :: rc
    end function c_same_out_err
    function c_close(fd) bind(c, name='close') result(rc)
      import :: c_int
      integer(c_int), value :: fd
      integer(c_int) :: rc
    end function c_close
  end interface

contains

  !> Create directory dir and its missing parents (mkdir -p), mode 0777 less the umask.
  !! On failure ok is .false. and failed names the first directory that could not be made.
  subroutine make_dirs(dir, ok, failed)
    character(len=*), intent(in) :: dir
    logical, intent(out) :: ok
    character(len=:), allocatable, intent(out) :: failed
    integer :: k
    integer(c_int) :: rc
    ok = .true.
    failed = ''
    do k = 1, len(dir)
      ! every prefix that ends a component: 'a', 'a/b', 'a/b/c' of 'a/b/c'
      if (k < len(dir)) then
        if (dir(k + 1:k + 1) /= '/') cycle
      end if
      if (dir(k:k) == '/') cycle
      if (is_dir(dir(1:k))) cycle
      rc = c_mkdir(dir(1:k)//c_null_char, dir_mode)
      ! another process may have made it meanwhile: only a missing directory is a failure
      if (rc == 0) cycle
      if (.not. is_dir(dir(1:k))) then
        ok = .false.
        failed = dir(1:k)
        return
      end if
    end do
  end subroutine make_dirs

  !> True when path is a directory (or a link to one).
  logical function is_dir(path)
    character(len=*), intent(in) :: path
    is_dir = c_access(path//'/.'//c_null_char, f_ok) == 0
  end function is_dir

  !> True when this process may create and remove entries in directory path.
  logical function writable_dir(path)
    character(len=*), intent(in) :: path
    writable_dir = c_access(path//c_null_char, ior(w_ok, x_ok)) == 0
  end function writable_dir

  !> True when something is at path (links followed: a dangling link reads as absent).
  logical function path_exists(path)
    character(len=*), intent(in) :: path
    path_exists = c_access(path//c_null_char, f_ok) == 0
  end function path_exists

  !> The absolute path with every link, '.' and '..' resolved, or '' when path does not
  !! exist: two names of one file give the same real path.
  function real_path(path) result(rp)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: rp
    character(kind=c_char, len=path_max + 1) :: buf
    integer :: n
    rp = ''
    if (.not. c_associated(c_realpath(path//c_null_char, buf))) return
    n = index(buf, c_null_char) - 1
    if (n > 0) rp = buf(1:n)
  end function real_path

  !> rename(2): old replaces new atomically (both in one directory here).
  logical function rename_file(old, new) result(ok)
    character(len=*), intent(in) :: old, new
    ok = c_rename(old//c_null_char, new//c_null_char) == 0
  end function rename_file

  !> link(2): a second name new for old; fails, changing nothing, when new exists.
  logical function link_file(old, new) result(ok)
    character(len=*), intent(in) :: old, new
    ok = c_link(old//c_null_char, new//c_null_char) == 0
  end function link_file

  !> unlink(2). Only ever called on names this run created.
  logical function remove_file(path) result(ok)
    character(len=*), intent(in) :: path
    ok = c_unlink(path//c_null_char) == 0
  end function remove_file

  !> The bytes of the plain file at path, read once, when it has at most max_bytes of
  !! them: opened without blocking and judged by the open descriptor, so a FIFO, a device,
  !! a directory or a socket is refused without being read, and what the caller checks is
  !! exactly what it uses (the size is 64-bit: a file of 2^31 bytes or more is too large,
  !! not unread). A symbolic link as the path's last component is followed only when
  !! follow_links is given and true (the deck the user names), never for a file a deck
  !! names (so a link named like a script cannot make mfcd read another file). problem is
  !! '' on success; otherwise it says what the path is or why it
  !! cannot be read (e.g. 'is a FIFO (named pipe), not a plain file'), and text is ''.
  subroutine read_plain_file(path, max_bytes, text, problem, follow_links)
    character(len=*), intent(in) :: path
    integer, intent(in) :: max_bytes
    character(len=:), allocatable, intent(out) :: text
    character(len=:), allocatable, intent(out) :: problem
    logical, intent(in), optional :: follow_links
    character(len=*), parameter :: kinds(0:7) = [character(len=40) :: 'a plain file', &
      'a directory', 'a FIFO (named pipe)', 'a character device', 'a block device', &
      'a socket', 'not a plain file', 'a symbolic link']
    integer(c_long_long) :: size, got
    integer(c_int) :: fd, kind, err_no, rc, nofollow
    text = ''
    problem = ''
    nofollow = 1
    if (present(follow_links)) then
      if (follow_links) nofollow = 0
    end if
    fd = c_open_regular(path//c_null_char, nofollow, int(max_bytes, c_long_long), size, &
      kind, err_no)
    if (fd < 0) then
      if (err_no /= 0) then
        problem = 'cannot be opened: '//errno_text(int(err_no))
      else if (kind /= 0) then
        problem = 'is '//trim(kinds(max(0, min(7, int(kind)))))//', not a plain file'
      else
        problem = 'holds '//ltoa(size)//' bytes, more than the '//ltoa(int(max_bytes, &
          c_long_long))//' read'
      end if
      return
    end if
    ! one byte more than the size, to see a file that grew meanwhile
    deallocate(text)
    allocate(character(len=int(size) + 1) :: text)
    got = c_read_fd(fd, text, size + 1)
    rc = c_close(fd)
    if (got < 0) then
      problem = 'cannot be read: '//errno_text(int(-got))
      text = ''
    else if (got > size) then
      problem = 'grew while it was read'
      text = ''
    else
      text = text(1:int(got))
    end if
  contains
    function ltoa(n) result(t)
      integer(c_long_long), intent(in) :: n
      character(len=:), allocatable :: t
      character(len=24) :: buf
      write(buf, '(i0)') n
      t = trim(buf)
    end function ltoa
  end subroutine read_plain_file

  !> Why no output can go to directory path ('' when it can): on a read-only file system,
  !! or on a pseudo file system of the kernel such as /proc (src/io/file_system.c), which
  !! write permission alone does not tell for root.
  function fs_refusal(path) result(why)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: why
    select case (c_fs_refuses(path//c_null_char))
    case (1)
      why = 'is on a read-only file system'
    case (2)
      why = "is on a pseudo file system of the kernel (such as /proc or /sys), where no "// &
        "file can be made"
    case default
      why = ''
    end select
  end function fs_refusal

  !> This process's id, for names no other run uses at the same time.
  integer function process_id()
    process_id = int(c_getpid())
  end function process_id
  !> Are standard output and standard error the same file (a terminal, or one log for
  !! both)? Then a message written to both is read twice.
  logical function same_out_err()
    same_out_err = c_same_out_err() /= 0
  end function same_out_err
end module file_system_m
