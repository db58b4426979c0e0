!> pfunit_lite's stand-in for pFUnit 4's `funit` module: the assertions that the `@assert...`
!> directives expand to, and the runner that the translated test programs call.
!>
!> Used only when pFUnit is not installed (see tests/pfunit_lite/README.md). It mirrors the
!> pFUnit 4 argument lists (expected, actual [, tolerance] [, message] [, location]) and
!> semantics; a .pf suite that compiles here should compile unchanged under pFUnit.
!>
!> Arrays are taken as assumed-rank dummies (ranks 0 to 7; a Fortran 2018 feature, so this file
!> is compiled with -std=f2018 even where the project uses f2008), so each generic needs one
!> specific per type/kind combination only; these are listed out near the end of the module and
!> all follow the same one-line pattern. Like pFUnit, an `expected` array must have the shape of
!> `actual`, and a scalar `expected` is compared with every element.
!>
!> Failures are recorded in module state (a log and a count), as pFUnit records them in its
!> exception list; the runner prints and clears the log after each test.
module funit
   use, intrinsic :: iso_fortran_env, only: int32, int64, real32, real64, output_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
   implicit none
   private

   public :: SourceLocation
   public :: anyExceptions
   public :: assertEqual, assertNotEqual
   public :: assertLessThan, assertLessThanOrEqual
   public :: assertGreaterThan, assertGreaterThanOrEqual
   public :: assertRelativelyEqual
   public :: assertTrue, assertFalse
   public :: assertAll, assertAny, assertNone, assertNotAll
   public :: assertIsFinite, assertIsNaN
   public :: assertFail
   ! Runner interface used by the programs that pf2f90.py generates.
   public :: funit_run_test, funit_skip_test, funit_finish
   public :: funit_num_failures, funit_failures, funit_clear_failures

   !> Where an assertion sits in the .pf file; pf2f90.py passes `location=SourceLocation(f, l)`.
   type :: SourceLocation
      character(len=255) :: fileName = '<unknown file>'
      integer :: lineNumber = -1
   end type SourceLocation

   integer, parameter :: OP_EQ = 1, OP_NE = 2, OP_LT = 3, OP_LE = 4, OP_GT = 5, OP_GE = 6
   integer, parameter :: OP_REL = 7
   integer, parameter :: MAX_RANK = 7
   character(len=*), parameter :: INDENT = '      '

   !> Like pFUnit's KeywordEnforcer: a private type for an optional dummy placed before
   !> `message` where pFUnit has one, so that `message` must be given by keyword there too.
   type :: keyword_enforcer
   end type keyword_enforcer

   ! Failures recorded since the last funit_clear_failures (the current test).
   integer :: n_recorded = 0
   character(len=:), allocatable :: failure_log
   ! Totals for the closing summary line.
   integer :: n_passed = 0, n_failed = 0, n_skipped = 0

   abstract interface
      subroutine funit_test_proc()
      end subroutine funit_test_proc
   end interface

   interface assertEqual
      module procedure eq_i32_r64
      module procedure eq_i32_r64_tol32
      module procedure eq_i32_r64_tol64
      module procedure eq_r32_r64
      module procedure eq_r32_r64_tol32
      module procedure eq_r32_r64_tol64
      module procedure eq_r64_r64
      module procedure eq_r64_r64_tol32
      module procedure eq_r64_r64_tol64
      module procedure eq_i32_r32
      module procedure eq_i32_r32_tol32
      module procedure eq_r32_r32
      module procedure eq_r32_r32_tol32
      module procedure eq_i32_i32
      module procedure eq_i64_i64
      module procedure eq_i32_i64
      module procedure eq_lgc_lgc
      module procedure eq_str_str
   end interface assertEqual

   interface assertNotEqual
      module procedure ne_i32_r64
      module procedure ne_i32_r64_tol32
      module procedure ne_i32_r64_tol64
      module procedure ne_r32_r64
      module procedure ne_r32_r64_tol32
      module procedure ne_r32_r64_tol64
      module procedure ne_r64_r64
      module procedure ne_r64_r64_tol32
      module procedure ne_r64_r64_tol64
      module procedure ne_i32_r32
      module procedure ne_i32_r32_tol32
      module procedure ne_r32_r32
      module procedure ne_r32_r32_tol32
      module procedure ne_i32_i32
      module procedure ne_i64_i64
      module procedure ne_i32_i64
      module procedure ne_lgc_lgc
   end interface assertNotEqual

   interface assertLessThan
      module procedure lt_i32_r64
      module procedure lt_i32_r64_tol32
      module procedure lt_i32_r64_tol64
      module procedure lt_r32_r64
      module procedure lt_r32_r64_tol32
      module procedure lt_r32_r64_tol64
      module procedure lt_r64_r64
      module procedure lt_r64_r64_tol32
      module procedure lt_r64_r64_tol64
      module procedure lt_i32_r32
      module procedure lt_i32_r32_tol32
      module procedure lt_r32_r32
      module procedure lt_r32_r32_tol32
      module procedure lt_i32_i32
      module procedure lt_i64_i64
      module procedure lt_i32_i64
   end interface assertLessThan

   interface assertLessThanOrEqual
      module procedure le_i32_r64
      module procedure le_i32_r64_tol32
      module procedure le_i32_r64_tol64
      module procedure le_r32_r64
      module procedure le_r32_r64_tol32
      module procedure le_r32_r64_tol64
      module procedure le_r64_r64
      module procedure le_r64_r64_tol32
      module procedure le_r64_r64_tol64
      module procedure le_i32_r32
      module procedure le_i32_r32_tol32
      module procedure le_r32_r32
      module procedure le_r32_r32_tol32
      module procedure le_i32_i32
      module procedure le_i64_i64
      module procedure le_i32_i64
   end interface assertLessThanOrEqual

   interface assertGreaterThan
      module procedure gt_i32_r64
      module procedure gt_i32_r64_tol32
      module procedure gt_i32_r64_tol64
      module procedure gt_r32_r64
      module procedure gt_r32_r64_tol32
      module procedure gt_r32_r64_tol64
      module procedure gt_r64_r64
      module procedure gt_r64_r64_tol32
      module procedure gt_r64_r64_tol64
      module procedure gt_i32_r32
      module procedure gt_i32_r32_tol32
      module procedure gt_r32_r32
      module procedure gt_r32_r32_tol32
      module procedure gt_i32_i32
      module procedure gt_i64_i64
      module procedure gt_i32_i64
   end interface assertGreaterThan

   interface assertGreaterThanOrEqual
      module procedure ge_i32_r64
      module procedure ge_i32_r64_tol32
      module procedure ge_i32_r64_tol64
      module procedure ge_r32_r64
      module procedure ge_r32_r64_tol32
      module procedure ge_r32_r64_tol64
      module procedure ge_r64_r64
      module procedure ge_r64_r64_tol32
      module procedure ge_r64_r64_tol64
      module procedure ge_i32_r32
      module procedure ge_i32_r32_tol32
      module procedure ge_r32_r32
      module procedure ge_r32_r32_tol32
      module procedure ge_i32_i32
      module procedure ge_i64_i64
      module procedure ge_i32_i64
   end interface assertGreaterThanOrEqual

   interface assertRelativelyEqual
      module procedure rel_i32_r64_tol32
      module procedure rel_i32_r64_tol64
      module procedure rel_r32_r64_tol32
      module procedure rel_r32_r64_tol64
      module procedure rel_r64_r64_tol32
      module procedure rel_r64_r64_tol64
      module procedure rel_i32_r32_tol32
      module procedure rel_r32_r32_tol32
   end interface assertRelativelyEqual

   interface assertTrue
      module procedure assert_true_0d
      module procedure assert_true_1d
   end interface assertTrue

   interface assertFalse
      module procedure assert_false_0d
      module procedure assert_false_1d
   end interface assertFalse

   interface assertIsFinite
      module procedure is_finite_r32
      module procedure is_finite_r64
   end interface assertIsFinite

   interface assertIsNaN
      module procedure is_nan_r32
      module procedure is_nan_r64
   end interface assertIsNaN

   interface to_r64
      module procedure r64_from_i32
      module procedure r64_from_r32
      module procedure r64_from_r64
   end interface to_r64

   interface to_i64
      module procedure i64_from_i32
      module procedure i64_from_i64
   end interface to_i64

   interface to_lgc
      module procedure lgc_from_lgc
   end interface to_lgc

contains

   ! ---------------------------------------------------------------------------------------
   ! Failure log and runner
   ! ---------------------------------------------------------------------------------------

   !> True once any assertion of the current test has failed (the directives return then).
   logical function anyExceptions()
      anyExceptions = n_recorded > 0
   end function anyExceptions

   !> Number of failures recorded since the last funit_clear_failures.
   integer function funit_num_failures()
      funit_num_failures = n_recorded
   end function funit_num_failures

   !> All failure reports recorded since the last funit_clear_failures, one per paragraph.
   function funit_failures() result(text)
      character(len=:), allocatable :: text
      if (allocated(failure_log)) then
         text = failure_log
      else
         text = ''
      end if
   end function funit_failures

   subroutine funit_clear_failures()
      n_recorded = 0
      failure_log = ''
   end subroutine funit_clear_failures

   !> Run one test: `before`, the test, `after`, then report it as OK or FAIL. The test is
   !> skipped when `before` fails; `after` runs whenever `before` succeeded.
   subroutine funit_run_test(name, test, before, after)
      character(len=*), intent(in) :: name
      procedure(funit_test_proc) :: test
      procedure(funit_test_proc), optional :: before
      procedure(funit_test_proc), optional :: after

      call funit_clear_failures()
      write (output_unit, '(a)') '[ RUN  ] '//name
      flush (output_unit)
      if (present(before)) call before()
      if (.not. anyExceptions()) then
         call test()
         if (present(after)) call after()
      end if
      if (anyExceptions()) then
         write (output_unit, '(a)') failure_log
         write (output_unit, '(a)') '[ FAIL ] '//name
         n_failed = n_failed + 1
      else
         write (output_unit, '(a)') '[  OK  ] '//name
         n_passed = n_passed + 1
      end if
      flush (output_unit)
      call funit_clear_failures()
   end subroutine funit_run_test

   !> Count a test marked @disable without running it.
   subroutine funit_skip_test(name)
      character(len=*), intent(in) :: name
      write (output_unit, '(a)') '[ SKIP ] '//name//' (disabled)'
      n_skipped = n_skipped + 1
   end subroutine funit_skip_test

   !> Print the closing line `N passed, N failed, N skipped`; true when nothing failed.
   logical function funit_finish()
      write (output_unit, '(i0,a,i0,a,i0,a)') n_passed, ' passed, ', n_failed, ' failed, ', &
         n_skipped, ' skipped'
      flush (output_unit)
      funit_finish = n_failed == 0
   end function funit_finish

   !> Append one failure report: `file:line: message` then the indented detail lines.
   subroutine record_failure(detail, message, location)
      character(len=*), intent(in) :: detail
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      character(len=:), allocatable :: entry

      entry = '  '
      if (present(location)) then
         entry = entry//trim(location%fileName)//':'//int_str(int(location%lineNumber, int64))
      else
         entry = entry//'<unknown location>'
      end if
      entry = entry//':'
      if (present(message)) then
         if (len_trim(message) > 0) entry = entry//' '//trim(message)
      end if
      entry = entry//detail
      if (.not. allocated(failure_log)) failure_log = ''
      if (n_recorded > 0) failure_log = failure_log//new_line('a')
      failure_log = failure_log//entry
      n_recorded = n_recorded + 1
   end subroutine record_failure

   !> A detail line for record_failure.
   function line(text) result(s)
      character(len=*), intent(in) :: text
      character(len=:), allocatable :: s
      s = new_line('a')//INDENT//text
   end function line

   ! ---------------------------------------------------------------------------------------
   ! Formatting
   ! ---------------------------------------------------------------------------------------

   function int_str(i) result(s)
      integer(int64), intent(in) :: i
      character(len=:), allocatable :: s
      character(len=24) :: buf
      write (buf, '(i0)') i
      s = trim(buf)
   end function int_str

   !> es24.16 for real64 values (es25.16e3 beyond 1e+-99), es16.8 for real32 ones: enough digits
   !> to tell neighbouring values apart.
   function real_str(x, single) result(s)
      real(real64), intent(in) :: x
      logical, intent(in) :: single
      character(len=:), allocatable :: s
      character(len=32) :: buf
      logical :: wide_exponent

      wide_exponent = .false.
      if (ieee_is_finite(x)) then
         if (abs(x) > 0.0_real64) wide_exponent = abs(x) >= 1.0e100_real64 &
            .or. abs(x) < 1.0e-99_real64
      end if
      if (single) then
         write (buf, '(es16.8e2)') x
      else if (wide_exponent) then
         write (buf, '(es25.16e3)') x
      else
         write (buf, '(es24.16e2)') x
      end if
      s = '<'//trim(adjustl(buf))//'>'
   end function real_str

   function logical_str(l) result(s)
      logical, intent(in) :: l
      character(len=:), allocatable :: s
      if (l) then
         s = '<.true.>'
      else
         s = '<.false.>'
      end if
   end function logical_str

   function shape_str(shp) result(s)
      integer, intent(in) :: shp(:)
      character(len=:), allocatable :: s
      integer :: k
      s = '['
      do k = 1, size(shp)
         if (k > 1) s = s//', '
         s = s//int_str(int(shp(k), int64))
      end do
      s = s//']'
   end function shape_str

   !> Detail line naming the first failing element (column-major flat index i in shape shp);
   !> empty for scalars.
   function index_line(i, shp) result(s)
      integer, intent(in) :: i
      integer, intent(in) :: shp(:)
      character(len=:), allocatable :: s
      integer :: idx(size(shp)), k, r
      if (size(shp) == 0) then
         s = ''
         return
      end if
      r = i - 1
      do k = 1, size(shp)
         idx(k) = mod(r, shp(k)) + 1
         r = r/shp(k)
      end do
      s = line('first difference at index: '//shape_str(idx))
   end function index_line

   ! ---------------------------------------------------------------------------------------
   ! Shape check shared by the array assertions
   ! ---------------------------------------------------------------------------------------

   !> A scalar `expected` conforms with any `actual`; otherwise the shapes must match.
   logical function conforms(e_shape, a_shape, message, location)
      integer, intent(in) :: e_shape(:), a_shape(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location

      conforms = .false.
      if (size(e_shape) > MAX_RANK .or. size(a_shape) > MAX_RANK) then
         call record_failure(line('pfunit_lite supports arrays up to rank 7'), message, location)
         return
      end if
      if (size(e_shape) /= 0) then
         if (size(e_shape) /= size(a_shape)) then
            conforms = .false.
         else
            conforms = all(e_shape == a_shape)
         end if
         if (.not. conforms) then
            call record_failure(line('nonconforming arrays - expected shape: ' &
               //shape_str(e_shape)//' but found shape: '//shape_str(a_shape)), &
               message, location)
            if (size(a_shape) == 0) failure_log = failure_log//line('(as in pFUnit, only ' &
               //'the first argument may be a scalar against an array)')
            return
         end if
      end if
      conforms = .true.
   end function conforms

   ! ---------------------------------------------------------------------------------------
   ! Real comparisons (every real kind is compared in real64)
   ! ---------------------------------------------------------------------------------------

   !> Equal within tolerance; exact equality first so that equal infinities pass. NaN never
   !> equals anything. Written without `==` on reals to stay clean under -Wcompare-reals.
   logical function reals_close(e, a, tol)
      real(real64), intent(in) :: e, a, tol
      reals_close = .false.
      if (ieee_is_nan(e) .or. ieee_is_nan(a)) return
      if (.not. (a < e .or. a > e)) then
         reals_close = .true.
      else if (ieee_is_finite(e) .and. ieee_is_finite(a)) then
         reals_close = abs(a - e) <= tol
      end if
   end function reals_close

   !> Whether `op` holds for expected/lhs `e` and actual/rhs `a` (pFUnit's definitions).
   logical function real_holds(op, e, a, tol)
      integer, intent(in) :: op
      real(real64), intent(in) :: e, a, tol
      real_holds = .false.
      if (ieee_is_nan(e) .or. ieee_is_nan(a)) then
         real_holds = op == OP_NE
         return
      end if
      select case (op)
      case (OP_EQ)
         real_holds = reals_close(e, a, tol)
      case (OP_NE)
         real_holds = .not. reals_close(e, a, tol)
      case (OP_LT)
         real_holds = e < a + tol
      case (OP_LE)
         real_holds = e <= a + tol
      case (OP_GT)
         real_holds = e > a - tol
      case (OP_GE)
         real_holds = e >= a - tol
      case (OP_REL)
         real_holds = reals_close(e, a, tol*abs(e))
      end select
   end function real_holds

   subroutine check_reals(op, e, e_shape, a, a_shape, tol, single, message, location)
      integer, intent(in) :: op
      real(real64), intent(in) :: e(:), a(:)
      integer, intent(in) :: e_shape(:), a_shape(:)
      real(real64), intent(in) :: tol
      logical, intent(in) :: single
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      integer :: i
      real(real64) :: ei

      if (.not. conforms(e_shape, a_shape, message, location)) return
      if (op == OP_REL) then
         do i = 1, size(e)
            if (is_zero(e(i))) then
               call record_failure(line('assertRelativelyEqual: expected value '// &
                  real_str(e(i), single)//' is zero, so no relative difference exists'), &
                  message, location)
               return
            end if
         end do
      end if
      do i = 1, size(a)
         if (size(e_shape) == 0) then
            ei = e(1)
         else
            ei = e(i)
         end if
         if (.not. real_holds(op, ei, a(i), tol)) then
            call record_failure(real_detail(op, ei, a(i), tol, single)//index_line(i, a_shape), &
               message, location)
            return
         end if
      end do
   end subroutine check_reals

   logical function is_zero(x)
      real(real64), intent(in) :: x
      is_zero = .false.
      if (ieee_is_nan(x)) return
      is_zero = .not. (abs(x) > 0.0_real64)
   end function is_zero

   function real_detail(op, e, a, tol, single) result(s)
      integer, intent(in) :: op
      real(real64), intent(in) :: e, a, tol
      logical, intent(in) :: single
      character(len=:), allocatable :: s
      character(len=:), allocatable :: es, as, ts, tol_clause
      logical :: finite

      es = real_str(e, single)
      as = real_str(a, single)
      ts = real_str(tol, single)
      finite = ieee_is_finite(e) .and. ieee_is_finite(a)
      tol_clause = ''
      if (tol > 0.0_real64) tol_clause = ' (tolerance '//ts//')'
      select case (op)
      case (OP_EQ)
         s = line('expected: '//es//' but found: '//as)
         if (finite) s = s//line('difference: '//real_str(a - e, single)// &
            ' (greater than tolerance of '//ts//')')
      case (OP_NE)
         s = line('expected a value different from: '//es//' but found: '//as)
         if (finite) s = s//line('difference: '//real_str(a - e, single)// &
            ' (not greater than tolerance of '//ts//')')
      case (OP_LT)
         s = line('expected: '//es//' to be less than: '//as//tol_clause)
      case (OP_LE)
         s = line('expected: '//es//' to be less than or equal to: '//as//tol_clause)
      case (OP_GT)
         s = line('expected: '//es//' to be greater than: '//as//tol_clause)
      case (OP_GE)
         s = line('expected: '//es//' to be greater than or equal to: '//as//tol_clause)
      case (OP_REL)
         s = line('expected: '//es//' but found: '//as)
         if (finite) s = s//line('difference: '//real_str(a - e, single)// &
            ', relative difference: '//real_str(abs(a - e)/abs(e), single)// &
            ' (greater than relative tolerance of '//ts//')')
      case default
         s = line('unknown comparison')
      end select
   end function real_detail

   ! ---------------------------------------------------------------------------------------
   ! Integer comparisons (in int64)
   ! ---------------------------------------------------------------------------------------

   subroutine check_ints(op, e, e_shape, a, a_shape, message, location)
      integer, intent(in) :: op
      integer(int64), intent(in) :: e(:), a(:)
      integer, intent(in) :: e_shape(:), a_shape(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      integer :: i
      integer(int64) :: ei
      logical :: holds

      if (.not. conforms(e_shape, a_shape, message, location)) return
      do i = 1, size(a)
         if (size(e_shape) == 0) then
            ei = e(1)
         else
            ei = e(i)
         end if
         select case (op)
         case (OP_EQ)
            holds = ei == a(i)
         case (OP_NE)
            holds = ei /= a(i)
         case (OP_LT)
            holds = ei < a(i)
         case (OP_LE)
            holds = ei <= a(i)
         case (OP_GT)
            holds = ei > a(i)
         case (OP_GE)
            holds = ei >= a(i)
         case default
            holds = .false.
         end select
         if (.not. holds) then
            call record_failure(int_detail(op, ei, a(i))//index_line(i, a_shape), &
               message, location)
            return
         end if
      end do
   end subroutine check_ints

   function int_detail(op, e, a) result(s)
      integer, intent(in) :: op
      integer(int64), intent(in) :: e, a
      character(len=:), allocatable :: s
      character(len=:), allocatable :: es, as

      es = '<'//int_str(e)//'>'
      as = '<'//int_str(a)//'>'
      select case (op)
      case (OP_EQ)
         s = line('expected: '//es//' but found: '//as)//line('difference: <' &
            //int_str(a - e)//'>')
      case (OP_NE)
         s = line('expected a value different from: '//es//' but found: '//as)
      case (OP_LT)
         s = line('expected: '//es//' to be less than: '//as)
      case (OP_LE)
         s = line('expected: '//es//' to be less than or equal to: '//as)
      case (OP_GT)
         s = line('expected: '//es//' to be greater than: '//as)
      case (OP_GE)
         s = line('expected: '//es//' to be greater than or equal to: '//as)
      case default
         s = line('unknown comparison')
      end select
   end function int_detail

   ! ---------------------------------------------------------------------------------------
   ! Logical and character comparisons
   ! ---------------------------------------------------------------------------------------

   subroutine check_logicals(op, e, e_shape, a, a_shape, message, location)
      integer, intent(in) :: op
      logical, intent(in) :: e(:), a(:)
      integer, intent(in) :: e_shape(:), a_shape(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      integer :: i
      logical :: ei, holds

      if (.not. conforms(e_shape, a_shape, message, location)) return
      do i = 1, size(a)
         if (size(e_shape) == 0) then
            ei = e(1)
         else
            ei = e(i)
         end if
         if (op == OP_EQ) then
            holds = ei .eqv. a(i)
         else
            holds = ei .neqv. a(i)
         end if
         if (.not. holds) then
            if (op == OP_EQ) then
               call record_failure(line('expected: '//logical_str(ei)//' but found: ' &
                  //logical_str(a(i)))//index_line(i, a_shape), message, location)
            else
               call record_failure(line('expected a value different from: ' &
                  //logical_str(ei)//' but found: '//logical_str(a(i))) &
                  //index_line(i, a_shape), message, location)
            end if
            return
         end if
      end do
   end subroutine check_logicals

   !> Strings compare equal after dropping leading and trailing blanks (pFUnit's default).
   subroutine eq_str_str(expected, found, message, location)
      character(len=*), intent(in) :: expected
      character(len=*), intent(in) :: found
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      character(len=:), allocatable :: e, a
      integer :: k

      e = trim(adjustl(expected))
      a = trim(adjustl(found))
      if (e == a .and. len(e) == len(a)) return
      k = 1
      do while (k <= min(len(e), len(a)))
         if (e(k:k) /= a(k:k)) exit
         k = k + 1
      end do
      call record_failure(line('expected: <"'//e//'"> but found: <"'//a//'">') &
         //line('first difference at character '//int_str(int(k, int64))), message, location)
   end subroutine eq_str_str

   ! ---------------------------------------------------------------------------------------
   ! Logical conditions
   ! ---------------------------------------------------------------------------------------

   subroutine assert_true_0d(condition, message, location)
      logical, intent(in) :: condition
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (.not. condition) call record_failure(line('expected: <.true.> but found: <.false.>'), &
         message, location)
   end subroutine assert_true_0d

   subroutine assert_true_1d(condition, message, location)
      logical, intent(in) :: condition(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call first_mismatch(condition, .true., 'expected all elements .true.', message, location)
   end subroutine assert_true_1d

   subroutine assert_false_0d(condition, message, location)
      logical, intent(in) :: condition
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (condition) call record_failure(line('expected: <.false.> but found: <.true.>'), &
         message, location)
   end subroutine assert_false_0d

   subroutine assert_false_1d(condition, message, location)
      logical, intent(in) :: condition(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call first_mismatch(condition, .false., 'expected all elements .false.', message, &
         location)
   end subroutine assert_false_1d

   subroutine assertAll(conditions, message, location)
      logical, intent(in) :: conditions(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call first_mismatch(conditions, .true., 'assertAll: expected all elements .true.', &
         message, location)
   end subroutine assertAll

   subroutine assertNone(conditions, message, location)
      logical, intent(in) :: conditions(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call first_mismatch(conditions, .false., 'assertNone: expected no element .true.', &
         message, location)
   end subroutine assertNone

   subroutine assertAny(conditions, message, location)
      logical, intent(in) :: conditions(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (.not. any(conditions)) call record_failure(line('assertAny: expected at least one ' &
         //'element .true., but all '//int_str(size(conditions, kind=int64))// &
         ' are .false.'), message, location)
   end subroutine assertAny

   subroutine assertNotAll(conditions, message, location)
      logical, intent(in) :: conditions(:)
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (all(conditions)) call record_failure(line('assertNotAll: expected at least one ' &
         //'element .false., but all '//int_str(size(conditions, kind=int64))// &
         ' are .true.'), message, location)
   end subroutine assertNotAll

   !> Record a failure at the first element of `conditions` that differs from `want`.
   subroutine first_mismatch(conditions, want, what, message, location)
      logical, intent(in) :: conditions(:)
      logical, intent(in) :: want
      character(len=*), intent(in) :: what
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      integer :: i
      do i = 1, size(conditions)
         if (conditions(i) .neqv. want) then
            call record_failure(line(what//'; element ['//int_str(int(i, int64))//'] is ' &
               //logical_str(conditions(i))), message, location)
            return
         end if
      end do
   end subroutine first_mismatch

   ! ---------------------------------------------------------------------------------------
   ! IEEE classes and unconditional failure
   ! ---------------------------------------------------------------------------------------

   subroutine is_finite_r64(x, message, location)
      real(real64), intent(in) :: x
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (.not. ieee_is_finite(x)) call record_failure(line('expected a finite value but ' &
         //'found: '//real_str(x, .false.)), message, location)
   end subroutine is_finite_r64

   subroutine is_finite_r32(x, message, location)
      real(real32), intent(in) :: x
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (.not. ieee_is_finite(x)) call record_failure(line('expected a finite value but ' &
         //'found: '//real_str(real(x, real64), .true.)), message, location)
   end subroutine is_finite_r32

   subroutine is_nan_r64(x, message, location)
      real(real64), intent(in) :: x
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (.not. ieee_is_nan(x)) call record_failure(line('expected: <NaN> but found: ' &
         //real_str(x, .false.)), message, location)
   end subroutine is_nan_r64

   subroutine is_nan_r32(x, message, location)
      real(real32), intent(in) :: x
      character(len=*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (.not. ieee_is_nan(x)) call record_failure(line('expected: <NaN> but found: ' &
         //real_str(real(x, real64), .true.)), message, location)
   end subroutine is_nan_r32

   !> Fail unconditionally with `message`.
   subroutine assertFail(message, location)
      character(len=*), intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call record_failure(line('assertFail'), message, location)
   end subroutine assertFail

   ! ---------------------------------------------------------------------------------------
   ! Specific procedures of the comparison generics: convert both operands to flat int64,
   ! real64 or logical arrays and hand them with their shapes to check_ints, check_reals or
   ! check_logicals. Names are <op>_<expected kind>_<actual kind>[_tol<tolerance kind>].
   ! Combinations follow pFUnit's: `expected` may be default integer, or a real kind not
   ! above that of `actual`; `tolerance` may be real32 or the kind of `actual`.
   ! ---------------------------------------------------------------------------------------

   subroutine eq_i32_r64(expected, actual, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .false., message, location)
   end subroutine eq_i32_r64

   subroutine eq_i32_r64_tol32(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine eq_i32_r64_tol32

   subroutine eq_i32_r64_tol64(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine eq_i32_r64_tol64

   subroutine eq_r32_r64(expected, actual, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .false., message, location)
   end subroutine eq_r32_r64

   subroutine eq_r32_r64_tol32(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine eq_r32_r64_tol32

   subroutine eq_r32_r64_tol64(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine eq_r32_r64_tol64

   subroutine eq_r64_r64(expected, actual, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .false., message, location)
   end subroutine eq_r64_r64

   subroutine eq_r64_r64_tol32(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine eq_r64_r64_tol32

   subroutine eq_r64_r64_tol64(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine eq_r64_r64_tol64

   subroutine eq_i32_r32(expected, actual, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .true., message, location)
   end subroutine eq_i32_r32

   subroutine eq_i32_r32_tol32(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .true., message, location)
   end subroutine eq_i32_r32_tol32

   subroutine eq_r32_r32(expected, actual, message, location)
      real(real32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .true., message, location)
   end subroutine eq_r32_r32

   subroutine eq_r32_r32_tol32(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_EQ, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .true., message, location)
   end subroutine eq_r32_r32_tol32

   subroutine eq_i32_i32(expected, actual, message, location)
      integer(int32), intent(in) :: expected(..)
      integer(int32), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_ints(OP_EQ, to_i64(expected), shape(expected), &
         to_i64(actual), shape(actual), message, location)
   end subroutine eq_i32_i32

   subroutine eq_i64_i64(expected, actual, message, location)
      integer(int64), intent(in) :: expected(..)
      integer(int64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_ints(OP_EQ, to_i64(expected), shape(expected), &
         to_i64(actual), shape(actual), message, location)
   end subroutine eq_i64_i64

   subroutine eq_i32_i64(expected, actual, message, location)
      integer(int32), intent(in) :: expected(..)
      integer(int64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_ints(OP_EQ, to_i64(expected), shape(expected), &
         to_i64(actual), shape(actual), message, location)
   end subroutine eq_i32_i64

   subroutine eq_lgc_lgc(expected, actual, unused, message, location)
      logical, intent(in) :: expected(..)
      logical, intent(in) :: actual(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_logicals(OP_EQ, to_lgc(expected), shape(expected), &
         to_lgc(actual), shape(actual), message, location)
   end subroutine eq_lgc_lgc

   subroutine ne_i32_r64(expected, actual, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .false., message, location)
   end subroutine ne_i32_r64

   subroutine ne_i32_r64_tol32(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine ne_i32_r64_tol32

   subroutine ne_i32_r64_tol64(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine ne_i32_r64_tol64

   subroutine ne_r32_r64(expected, actual, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .false., message, location)
   end subroutine ne_r32_r64

   subroutine ne_r32_r64_tol32(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine ne_r32_r64_tol32

   subroutine ne_r32_r64_tol64(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine ne_r32_r64_tol64

   subroutine ne_r64_r64(expected, actual, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .false., message, location)
   end subroutine ne_r64_r64

   subroutine ne_r64_r64_tol32(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine ne_r64_r64_tol32

   subroutine ne_r64_r64_tol64(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine ne_r64_r64_tol64

   subroutine ne_i32_r32(expected, actual, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .true., message, location)
   end subroutine ne_i32_r32

   subroutine ne_i32_r32_tol32(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .true., message, location)
   end subroutine ne_i32_r32_tol32

   subroutine ne_r32_r32(expected, actual, message, location)
      real(real32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), 0.0_real64, .true., message, location)
   end subroutine ne_r32_r32

   subroutine ne_r32_r32_tol32(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_NE, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .true., message, location)
   end subroutine ne_r32_r32_tol32

   subroutine ne_i32_i32(expected, actual, unused, message, location)
      integer(int32), intent(in) :: expected(..)
      integer(int32), intent(in) :: actual(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_NE, to_i64(expected), shape(expected), &
         to_i64(actual), shape(actual), message, location)
   end subroutine ne_i32_i32

   subroutine ne_i64_i64(expected, actual, unused, message, location)
      integer(int64), intent(in) :: expected(..)
      integer(int64), intent(in) :: actual(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_NE, to_i64(expected), shape(expected), &
         to_i64(actual), shape(actual), message, location)
   end subroutine ne_i64_i64

   subroutine ne_i32_i64(expected, actual, unused, message, location)
      integer(int32), intent(in) :: expected(..)
      integer(int64), intent(in) :: actual(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_NE, to_i64(expected), shape(expected), &
         to_i64(actual), shape(actual), message, location)
   end subroutine ne_i32_i64

   subroutine ne_lgc_lgc(expected, actual, unused, message, location)
      logical, intent(in) :: expected(..)
      logical, intent(in) :: actual(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_logicals(OP_NE, to_lgc(expected), shape(expected), &
         to_lgc(actual), shape(actual), message, location)
   end subroutine ne_lgc_lgc

   subroutine lt_i32_r64(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine lt_i32_r64

   subroutine lt_i32_r64_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine lt_i32_r64_tol32

   subroutine lt_i32_r64_tol64(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine lt_i32_r64_tol64

   subroutine lt_r32_r64(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine lt_r32_r64

   subroutine lt_r32_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine lt_r32_r64_tol32

   subroutine lt_r32_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine lt_r32_r64_tol64

   subroutine lt_r64_r64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine lt_r64_r64

   subroutine lt_r64_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine lt_r64_r64_tol32

   subroutine lt_r64_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine lt_r64_r64_tol64

   subroutine lt_i32_r32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine lt_i32_r32

   subroutine lt_i32_r32_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine lt_i32_r32_tol32

   subroutine lt_r32_r32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine lt_r32_r32

   subroutine lt_r32_r32_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine lt_r32_r32_tol32

   subroutine lt_i32_i32(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int32), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_LT, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine lt_i32_i32

   subroutine lt_i64_i64(lhs, rhs, unused, message, location)
      integer(int64), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_LT, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine lt_i64_i64

   subroutine lt_i32_i64(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_LT, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine lt_i32_i64

   subroutine le_i32_r64(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine le_i32_r64

   subroutine le_i32_r64_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine le_i32_r64_tol32

   subroutine le_i32_r64_tol64(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine le_i32_r64_tol64

   subroutine le_r32_r64(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine le_r32_r64

   subroutine le_r32_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine le_r32_r64_tol32

   subroutine le_r32_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine le_r32_r64_tol64

   subroutine le_r64_r64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine le_r64_r64

   subroutine le_r64_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine le_r64_r64_tol32

   subroutine le_r64_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine le_r64_r64_tol64

   subroutine le_i32_r32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine le_i32_r32

   subroutine le_i32_r32_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine le_i32_r32_tol32

   subroutine le_r32_r32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine le_r32_r32

   subroutine le_r32_r32_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_LE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine le_r32_r32_tol32

   subroutine le_i32_i32(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int32), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_LE, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine le_i32_i32

   subroutine le_i64_i64(lhs, rhs, unused, message, location)
      integer(int64), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_LE, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine le_i64_i64

   subroutine le_i32_i64(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_LE, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine le_i32_i64

   subroutine gt_i32_r64(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine gt_i32_r64

   subroutine gt_i32_r64_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine gt_i32_r64_tol32

   subroutine gt_i32_r64_tol64(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine gt_i32_r64_tol64

   subroutine gt_r32_r64(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine gt_r32_r64

   subroutine gt_r32_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine gt_r32_r64_tol32

   subroutine gt_r32_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine gt_r32_r64_tol64

   subroutine gt_r64_r64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine gt_r64_r64

   subroutine gt_r64_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine gt_r64_r64_tol32

   subroutine gt_r64_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine gt_r64_r64_tol64

   subroutine gt_i32_r32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine gt_i32_r32

   subroutine gt_i32_r32_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine gt_i32_r32_tol32

   subroutine gt_r32_r32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine gt_r32_r32

   subroutine gt_r32_r32_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GT, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine gt_r32_r32_tol32

   subroutine gt_i32_i32(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int32), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_GT, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine gt_i32_i32

   subroutine gt_i64_i64(lhs, rhs, unused, message, location)
      integer(int64), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_GT, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine gt_i64_i64

   subroutine gt_i32_i64(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_GT, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine gt_i32_i64

   subroutine ge_i32_r64(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine ge_i32_r64

   subroutine ge_i32_r64_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine ge_i32_r64_tol32

   subroutine ge_i32_r64_tol64(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine ge_i32_r64_tol64

   subroutine ge_r32_r64(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine ge_r32_r64

   subroutine ge_r32_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine ge_r32_r64_tol32

   subroutine ge_r32_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine ge_r32_r64_tol64

   subroutine ge_r64_r64(lhs, rhs, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .false., message, location)
   end subroutine ge_r64_r64

   subroutine ge_r64_r64_tol32(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine ge_r64_r64_tol32

   subroutine ge_r64_r64_tol64(lhs, rhs, tolerance, message, location)
      real(real64), intent(in) :: lhs(..)
      real(real64), intent(in) :: rhs(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .false., message, location)
   end subroutine ge_r64_r64_tol64

   subroutine ge_i32_r32(lhs, rhs, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine ge_i32_r32

   subroutine ge_i32_r32_tol32(lhs, rhs, tolerance, message, location)
      integer(int32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine ge_i32_r32_tol32

   subroutine ge_r32_r32(lhs, rhs, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), 0.0_real64, .true., message, location)
   end subroutine ge_r32_r32

   subroutine ge_r32_r32_tol32(lhs, rhs, tolerance, message, location)
      real(real32), intent(in) :: lhs(..)
      real(real32), intent(in) :: rhs(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_GE, to_r64(lhs), shape(lhs), &
         to_r64(rhs), shape(rhs), real(tolerance, real64), .true., message, location)
   end subroutine ge_r32_r32_tol32

   subroutine ge_i32_i32(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int32), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_GE, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine ge_i32_i32

   subroutine ge_i64_i64(lhs, rhs, unused, message, location)
      integer(int64), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_GE, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine ge_i64_i64

   subroutine ge_i32_i64(lhs, rhs, unused, message, location)
      integer(int32), intent(in) :: lhs(..)
      integer(int64), intent(in) :: rhs(..)
      type(keyword_enforcer), optional, intent(in) :: unused
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      if (present(unused)) return  ! never: the type is private
      call check_ints(OP_GE, to_i64(lhs), shape(lhs), &
         to_i64(rhs), shape(rhs), message, location)
   end subroutine ge_i32_i64

   subroutine rel_i32_r64_tol32(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine rel_i32_r64_tol32

   subroutine rel_i32_r64_tol64(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine rel_i32_r64_tol64

   subroutine rel_r32_r64_tol32(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine rel_r32_r64_tol32

   subroutine rel_r32_r64_tol64(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine rel_r32_r64_tol64

   subroutine rel_r64_r64_tol32(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine rel_r64_r64_tol32

   subroutine rel_r64_r64_tol64(expected, actual, tolerance, message, location)
      real(real64), intent(in) :: expected(..)
      real(real64), intent(in) :: actual(..)
      real(real64), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .false., message, location)
   end subroutine rel_r64_r64_tol64

   subroutine rel_i32_r32_tol32(expected, actual, tolerance, message, location)
      integer(int32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .true., message, location)
   end subroutine rel_i32_r32_tol32

   subroutine rel_r32_r32_tol32(expected, actual, tolerance, message, location)
      real(real32), intent(in) :: expected(..)
      real(real32), intent(in) :: actual(..)
      real(real32), intent(in) :: tolerance
      character(*), optional, intent(in) :: message
      type(SourceLocation), optional, intent(in) :: location
      call check_reals(OP_REL, to_r64(expected), shape(expected), &
         to_r64(actual), shape(actual), real(tolerance, real64), .true., message, location)
   end subroutine rel_r32_r32_tol32

   ! ---------------------------------------------------------------------------------------
   ! Flatten an assumed-rank argument (rank 0 to 7) to a rank-1 array in array element order
   ! ---------------------------------------------------------------------------------------

   pure function r64_from_i32(x) result(f)
      integer(int32), intent(in) :: x(..)
      real(real64), allocatable :: f(:)
      select rank (x)
      rank (0); f = real([x], real64)
      rank (1); f = real([x], real64)
      rank (2); f = real([x], real64)
      rank (3); f = real([x], real64)
      rank (4); f = real([x], real64)
      rank (5); f = real([x], real64)
      rank (6); f = real([x], real64)
      rank (7); f = real([x], real64)
      rank default; allocate (f(0))
      end select
   end function r64_from_i32

   pure function r64_from_r32(x) result(f)
      real(real32), intent(in) :: x(..)
      real(real64), allocatable :: f(:)
      select rank (x)
      rank (0); f = real([x], real64)
      rank (1); f = real([x], real64)
      rank (2); f = real([x], real64)
      rank (3); f = real([x], real64)
      rank (4); f = real([x], real64)
      rank (5); f = real([x], real64)
      rank (6); f = real([x], real64)
      rank (7); f = real([x], real64)
      rank default; allocate (f(0))
      end select
   end function r64_from_r32

   pure function r64_from_r64(x) result(f)
      real(real64), intent(in) :: x(..)
      real(real64), allocatable :: f(:)
      select rank (x)
      rank (0); f = real([x], real64)
      rank (1); f = real([x], real64)
      rank (2); f = real([x], real64)
      rank (3); f = real([x], real64)
      rank (4); f = real([x], real64)
      rank (5); f = real([x], real64)
      rank (6); f = real([x], real64)
      rank (7); f = real([x], real64)
      rank default; allocate (f(0))
      end select
   end function r64_from_r64

   pure function i64_from_i32(x) result(f)
      integer(int32), intent(in) :: x(..)
      integer(int64), allocatable :: f(:)
      select rank (x)
      rank (0); f = int([x], int64)
      rank (1); f = int([x], int64)
      rank (2); f = int([x], int64)
      rank (3); f = int([x], int64)
      rank (4); f = int([x], int64)
      rank (5); f = int([x], int64)
      rank (6); f = int([x], int64)
      rank (7); f = int([x], int64)
      rank default; allocate (f(0))
      end select
   end function i64_from_i32

   pure function i64_from_i64(x) result(f)
      integer(int64), intent(in) :: x(..)
      integer(int64), allocatable :: f(:)
      select rank (x)
      rank (0); f = int([x], int64)
      rank (1); f = int([x], int64)
      rank (2); f = int([x], int64)
      rank (3); f = int([x], int64)
      rank (4); f = int([x], int64)
      rank (5); f = int([x], int64)
      rank (6); f = int([x], int64)
      rank (7); f = int([x], int64)
      rank default; allocate (f(0))
      end select
   end function i64_from_i64

   pure function lgc_from_lgc(x) result(f)
      logical, intent(in) :: x(..)
      logical, allocatable :: f(:)
      select rank (x)
      rank (0); f = [x]
      rank (1); f = [x]
      rank (2); f = [x]
      rank (3); f = [x]
      rank (4); f = [x]
      rank (5); f = [x]
      rank (6); f = [x]
      rank (7); f = [x]
      rank default; allocate (f(0))
      end select
   end function lgc_from_lgc
end module funit
