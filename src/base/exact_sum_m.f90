!> Sums of reals that are the same to the bit whatever the order of their terms and however
!! the terms are split among ranks (doc/parallel.md): each term is added exactly into a
!! long fixed-point accumulator (Kulisch's), integer limbs of 32 bits that cover every
!! exponent a double has, and the exact total is rounded once, when it is read.
!!
!! A double is m 2^e with an integer |m| < 2^53 (read from its bits, subnormals too);
!! limb k weighs 2^(32 k + emin). Adding m 2^e puts its 85 bits at most into three limbs,
!! each gets less than 2^33 in magnitude, so an int64 limb takes 2^29 terms before its carries
!! must be pushed up (exact_normalize, done then by exact_add itself). Normalized, every limb
!! but the top one lies in [0, 2^32) and the top one holds the sign: the one representation
!! of the exact sum, so limbs from different ranks add as integers (comm%sum_i8) and the
!! value read from them is the same on every rank and for every split.
!!
!! Reading rounds the exact sum from its top 96 bits, the rest only as a sticky bit: the
!! value is within one unit in the last place of the exact sum (faithful), and it depends on
!! the exact sum only. A term that is not finite makes the value NaN.
module exact_sum_m
  use kinds_m, only: wp, i64
  use rank_comm_m, only: rank_comm_t
  implicit none
  private
  public :: exact_sum_t, exact_add, exact_merge, exact_value, exact_normalize, exact_allsum, &
    exact_allsum_many, exact_allmerge, exact_pack, exact_unpack, exact_pack_size

  !> limbs: 72 of 32 bits from 2^-1152 (below the smallest subnormal's 2^-1074, with room for
  !! a 53-bit mantissa's shift) to 2^1152 (above huge's 2^1024, with room for carries)
  integer, parameter :: nlimb = 72
  !> the integers of exact_pack
  integer, parameter :: exact_pack_size = nlimb + 1
  integer, parameter :: emin = -1152
  integer, parameter :: limb_bits = 32
  integer(i64), parameter :: mask = 2_i64**limb_bits - 1
  !> terms added between two normalizations: each adds less than 2^33 to a limb
  integer, parameter :: renorm_every = 2**29

  !> An exact sum: limb(k) weighs 2^(32 k + emin); nonfinite counts the terms that were not
  !! finite; nadd the terms since the last normalization.
  type :: exact_sum_t
    integer(i64) :: limb(0:nlimb - 1) = 0
    integer(i64) :: nonfinite = 0
    integer :: nadd = 0
  end type exact_sum_t

contains

  !> a = a + x, exactly. x's fields are read from its bits (integer operations only: no
  !! intrinsic that touches the floating-point state, about 2 ns a term).
  subroutine exact_add(a, x)
    type(exact_sum_t), intent(inout) :: a
    real(wp), intent(in) :: x
    integer(i64) :: bits, m, lo, hi, s
    integer :: e, off, k, r
    bits = transfer(x, bits)
    e = int(iand(ishft(bits, -52), 2047_i64))
    m = iand(bits, 2_i64**52 - 1)
    if (e == 2047) then
      ! infinite or NaN
      a%nonfinite = a%nonfinite + 1
      return
    end if
    if (e == 0) then
      ! zero or subnormal: m 2^-1074
      if (m == 0) return
      e = -1074
    else
      m = ior(m, 2_i64**52)
      e = e - 1075
    end if
    off = e - emin
    k = off/limb_bits
    r = mod(off, limb_bits)
    s = merge(-1_i64, 1_i64, bits < 0)
    lo = ishft(iand(m, mask), r)               ! < 2^63
    hi = ishft(ishft(m, -limb_bits), r)        ! < 2^52
    a%limb(k) = a%limb(k) + s*iand(lo, mask)
    a%limb(k + 1) = a%limb(k + 1) + s*(ishft(lo, -limb_bits) + iand(hi, mask))
    a%limb(k + 2) = a%limb(k + 2) + s*ishft(hi, -limb_bits)
    a%nadd = a%nadd + 1
    if (a%nadd >= renorm_every) call exact_normalize(a)
  end subroutine exact_add

  !> The carries pushed up: every limb but the top one in [0, 2^32), the same value.
  pure subroutine exact_normalize(a)
    type(exact_sum_t), intent(inout) :: a
    integer(i64) :: carry, v
    integer :: k
    carry = 0
    do k = 0, nlimb - 2
      v = a%limb(k) + carry
      carry = shifta(v, limb_bits)             ! floor(v / 2^32)
      a%limb(k) = iand(v, mask)
    end do
    a%limb(nlimb - 1) = a%limb(nlimb - 1) + carry
    a%nadd = 0
  end subroutine exact_normalize

  !> The sum, rounded once (faithfully: within one unit in the last place).
  function exact_value(a) result(x)
    type(exact_sum_t), intent(in) :: a
    real(wp) :: x
    type(exact_sum_t) :: b
    integer :: k, top
    real(wp) :: sgn, t
    if (a%nonfinite > 0) then
      x = ieee_nan()
      return
    end if
    b = a
    call exact_normalize(b)
    sgn = 1.0_wp
    if (b%limb(nlimb - 1) < 0) then
      ! the magnitude: all limbs negated, then normalized again (the top one turns >= 0)
      b%limb = -b%limb
      call exact_normalize(b)
      sgn = -1.0_wp
    end if
    top = -1
    do k = nlimb - 1, 0, -1
      if (b%limb(k) /= 0) then
        top = k
        exit
      end if
    end do
    x = 0.0_wp
    if (top < 0) return
    ! the top three limbs (96 bits, exact as an integer below 2^96 needs more than a double
    ! holds, so added from the lowest, each sum rounded once), the rest as a sticky bit
    t = 0.0_wp
    if (top >= 2) then
      t = real(b%limb(top - 2), wp)
      if (top >= 3) then
        if (any(b%limb(0:top - 3) /= 0)) t = t + 0.5_wp
      end if
    end if
    if (top >= 1) t = t*2.0_wp**(-limb_bits) + real(b%limb(top - 1), wp)
    t = t*2.0_wp**(-limb_bits) + real(b%limb(top), wp)
    x = sgn*scale(t, limb_bits*top + emin)
  end function exact_value

  !> a = a + b, exactly (what exact_allsum does between ranks, one rank's sum into another's).
  pure subroutine exact_merge(a, b)
    type(exact_sum_t), intent(inout) :: a
    type(exact_sum_t), intent(in) :: b
    type(exact_sum_t) :: c
    c = b
    call exact_normalize(c)
    call exact_normalize(a)
    a%limb = a%limb + c%limb
    a%nonfinite = a%nonfinite + c%nonfinite
  end subroutine exact_merge

  !> The exact sum over the ranks of comm of each rank's a (collective), read once: the same
  !! bits on every rank and for any number of ranks holding any split of the terms.
  function exact_allsum(a, comm) result(x)
    type(exact_sum_t), intent(in) :: a
    class(rank_comm_t), intent(inout) :: comm
    real(wp) :: x
    real(wp) :: xs(1)
    xs = exact_allsum_many([a], comm)
    x = xs(1)
  end function exact_allsum

  !> exact_allsum of each of the sums a(:) (collective; one reduction for all of them).
  function exact_allsum_many(a, comm) result(x)
    type(exact_sum_t), intent(in) :: a(:)
    class(rank_comm_t), intent(inout) :: comm
    real(wp) :: x(size(a))
    type(exact_sum_t) :: b
    ! (on the stack: on ranks the contact sums of every step come here)
    integer(i64) :: v((nlimb + 1)*size(a))
    integer :: k, o
    do k = 1, size(a)
      b = a(k)
      call exact_normalize(b)
      o = (k - 1)*(nlimb + 1)
      v(o + 1:o + nlimb) = b%limb
      v(o + nlimb + 1) = b%nonfinite
    end do
    ! (normalized limbs are below 2^32: 2^31 ranks' sums fit an int64)
    if (comm%nranks > 1) call comm%sum_i8(v)
    do k = 1, size(a)
      o = (k - 1)*(nlimb + 1)
      b%limb = v(o + 1:o + nlimb)
      b%nonfinite = v(o + nlimb + 1)
      b%nadd = 0
      x(k) = exact_value(b)
    end do
  end function exact_allsum_many

  !> The exact sum over the ranks of comm of each rank's a (collective), as an exact sum
  !! (normalized): the same on every rank, to go on adding to (a checkpoint's).
  function exact_allmerge(a, comm) result(b)
    type(exact_sum_t), intent(in) :: a
    class(rank_comm_t), intent(inout) :: comm
    type(exact_sum_t) :: b
    integer(i64) :: v(exact_pack_size)
    v = exact_pack(a)
    if (comm%nranks > 1) call comm%sum_i8(v)
    b = exact_unpack(v)
  end function exact_allmerge

  !> The exact sum a as nlimb + 1 integers (its normalized limbs, then the count of terms
  !! that were not finite): the one representation of its value, to store and restore
  !! (exact_unpack) without rounding.
  pure function exact_pack(a) result(v)
    type(exact_sum_t), intent(in) :: a
    integer(i64) :: v(exact_pack_size)
    type(exact_sum_t) :: b
    b = a
    call exact_normalize(b)
    v(1:nlimb) = b%limb
    v(nlimb + 1) = b%nonfinite
  end function exact_pack

  !> The exact sum exact_pack gave v for.
  pure function exact_unpack(v) result(a)
    integer(i64), intent(in) :: v(:)
    type(exact_sum_t) :: a
    a%limb = v(1:nlimb)
    a%nonfinite = v(nlimb + 1)
    a%nadd = 0
  end function exact_unpack

  !> A quiet NaN.
  function ieee_nan() result(x)
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    real(wp) :: x
    x = ieee_value(x, ieee_quiet_nan)
  end function ieee_nan
end module exact_sum_m
