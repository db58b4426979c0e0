!> Hash maps from names and from integer tags to integers, so that a reader of user text
!! (the gmsh script subset of geo_script_m) stays linear in the size of its input however
!! many distinct names or tags it holds: open addressing with linear probing, the table
!! doubled at half load, a polynomial hash for names and a multiplicative one for tags.
!! Keys are never removed.
module hash_map_m
  use kinds_m, only: i64
  implicit none
  private
  public :: name_map_t, tag_map_t

  !> Names (any characters, compared exactly) to integer values.
  type :: name_map_t
    private
    character(len=:), allocatable :: chars   !< every key, one after another
    integer :: nchars = 0
    integer, allocatable :: first(:), length(:), value(:)   !< per entry
    integer :: n = 0
    integer, allocatable :: slot(:)   !< entry in each slot of the table, 0 if empty
  contains
    procedure :: get => name_get
    procedure :: put => name_put
    procedure :: size => name_size
  end type name_map_t

  !> Integer tags to integer values.
  type :: tag_map_t
    private
    integer, allocatable :: key(:), value(:)   !< per slot
    logical, allocatable :: used(:)
    integer :: n = 0
  contains
    procedure :: get => tag_get
    procedure :: put => tag_put
    procedure :: size => tag_size
  end type tag_map_t

  integer, parameter :: first_size = 64   !< slots of a new table (a power of two)

contains

  !> A polynomial hash of the key's characters modulo the prime 2^31 - 1 (no intermediate
  !! exceeds 2^39, so nothing overflows).
  pure integer(i64) function name_hash(key) result(h)
    character(len=*), intent(in) :: key
    integer(i64), parameter :: p = 2147483647_i64
    integer :: i
    h = 5381_i64
    do i = 1, len(key)
      h = mod(h*131_i64 + int(ichar(key(i:i)), i64), p)
    end do
  end function name_hash

  !> The table slot (1-based) to start probing at for hash h in a table of m slots.
  pure integer function start_slot(h, m)
    integer(i64), intent(in) :: h
    integer, intent(in) :: m
    start_slot = int(iand(ieor(h, ishft(h, -17)), int(m - 1, i64))) + 1
  end function start_slot

  !> The value of key, and found = .false. (value 0) when it is not in the map.
  integer function name_get(this, key, found) result(v)
    class(name_map_t), intent(in) :: this
    character(len=*), intent(in) :: key
    logical, intent(out) :: found
    integer :: s, e
    v = 0
    found = .false.
    if (this%n == 0) return
    s = start_slot(name_hash(key), size(this%slot))
    do
      e = this%slot(s)
      if (e == 0) return
      if (this%length(e) == len(key)) then
        if (this%chars(this%first(e):this%first(e) + len(key) - 1) == key) then
          v = this%value(e)
          found = .true.
          return
        end if
      end if
      s = merge(1, s + 1, s == size(this%slot))
    end do
  end function name_get

  !> Set key's value (added when new).
  subroutine name_put(this, key, v)
    class(name_map_t), intent(inout) :: this
    character(len=*), intent(in) :: key
    integer, intent(in) :: v
    integer :: s, e
    if (.not. allocated(this%slot)) then
      allocate(this%slot(first_size), source=0)
      allocate(this%first(first_size/2), this%length(first_size/2), this%value(first_size/2))
      allocate(character(len=256) :: this%chars)
    end if
    s = start_slot(name_hash(key), size(this%slot))
    do
      e = this%slot(s)
      if (e == 0) exit
      if (this%length(e) == len(key)) then
        if (this%chars(this%first(e):this%first(e) + len(key) - 1) == key) then
          this%value(e) = v
          return
        end if
      end if
      s = merge(1, s + 1, s == size(this%slot))
    end do
    ! a new entry
    if (this%nchars + len(key) > len(this%chars)) call grow_chars(this, this%nchars + len(key))
    if (this%n == size(this%first)) call grow_entries(this)
    this%n = this%n + 1
    this%first(this%n) = this%nchars + 1
    this%length(this%n) = len(key)
    this%value(this%n) = v
    if (len(key) > 0) this%chars(this%nchars + 1:this%nchars + len(key)) = key
    this%nchars = this%nchars + len(key)
    if (2*this%n > size(this%slot)) then
      call rehash_names(this)
    else
      this%slot(s) = this%n
    end if
  end subroutine name_put

  pure integer function name_size(this)
    class(name_map_t), intent(in) :: this
    name_size = this%n
  end function name_size

  subroutine grow_chars(this, need)
    type(name_map_t), intent(inout) :: this
    integer, intent(in) :: need
    character(len=:), allocatable :: more
    allocate(character(len=max(2*len(this%chars), need)) :: more)
    more(1:this%nchars) = this%chars(1:this%nchars)
    call move_alloc(more, this%chars)
  end subroutine grow_chars

  subroutine grow_entries(this)
    type(name_map_t), intent(inout) :: this
    integer, allocatable :: t(:)
    integer :: m
    m = 2*size(this%first)
    allocate(t(m))
    t(1:this%n) = this%first(1:this%n)
    call move_alloc(t, this%first)
    allocate(t(m))
    t(1:this%n) = this%length(1:this%n)
    call move_alloc(t, this%length)
    allocate(t(m))
    t(1:this%n) = this%value(1:this%n)
    call move_alloc(t, this%value)
  end subroutine grow_entries

  !> Every entry into a table of twice the slots.
  subroutine rehash_names(this)
    type(name_map_t), intent(inout) :: this
    integer :: e, s, m
    m = 2*size(this%slot)
    deallocate(this%slot)
    allocate(this%slot(m), source=0)
    do e = 1, this%n
      s = start_slot(name_hash(this%chars(this%first(e):this%first(e) + this%length(e) - 1)), m)
      do while (this%slot(s) /= 0)
        s = merge(1, s + 1, s == m)
      end do
      this%slot(s) = e
    end do
  end subroutine rehash_names

  !> Knuth's multiplicative hash of a tag, its middle bits (|key| < 2^31 and the factor
  !! < 2^32, so the product fits in 64 bits).
  pure integer(i64) function tag_hash(key)
    integer, intent(in) :: key
    tag_hash = ishft(abs(int(key, i64))*2654435761_i64, -16)
  end function tag_hash

  !> The value of tag key, and found = .false. (value 0) when it is not in the map.
  integer function tag_get(this, key, found) result(v)
    class(tag_map_t), intent(in) :: this
    integer, intent(in) :: key
    logical, intent(out) :: found
    integer :: s
    v = 0
    found = .false.
    if (this%n == 0) return
    s = start_slot(tag_hash(key), size(this%key))
    do while (this%used(s))
      if (this%key(s) == key) then
        v = this%value(s)
        found = .true.
        return
      end if
      s = merge(1, s + 1, s == size(this%key))
    end do
  end function tag_get

  !> Set tag key's value (added when new).
  subroutine tag_put(this, key, v)
    class(tag_map_t), intent(inout) :: this
    integer, intent(in) :: key, v
    integer :: s
    if (.not. allocated(this%key)) then
      allocate(this%key(first_size), this%value(first_size))
      allocate(this%used(first_size), source=.false.)
    end if
    if (2*(this%n + 1) > size(this%key)) call rehash_tags(this)
    s = start_slot(tag_hash(key), size(this%key))
    do while (this%used(s))
      if (this%key(s) == key) then
        this%value(s) = v
        return
      end if
      s = merge(1, s + 1, s == size(this%key))
    end do
    this%used(s) = .true.
    this%key(s) = key
    this%value(s) = v
    this%n = this%n + 1
  end subroutine tag_put

  pure integer function tag_size(this)
    class(tag_map_t), intent(in) :: this
    tag_size = this%n
  end function tag_size

  subroutine rehash_tags(this)
    type(tag_map_t), intent(inout) :: this
    integer, allocatable :: k(:), v(:)
    logical, allocatable :: u(:)
    integer :: i, s, m
    call move_alloc(this%key, k)
    call move_alloc(this%value, v)
    call move_alloc(this%used, u)
    m = 2*size(k)
    allocate(this%key(m), this%value(m))
    allocate(this%used(m), source=.false.)
    do i = 1, size(k)
      if (.not. u(i)) cycle
      s = start_slot(tag_hash(k(i)), m)
      do while (this%used(s))
        s = merge(1, s + 1, s == m)
      end do
      this%used(s) = .true.
      this%key(s) = k(i)
      this%value(s) = v(i)
    end do
  end subroutine rehash_tags
end module hash_map_m
