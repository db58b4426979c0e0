!> Small dense linear algebra of the moment matrix, eqs. (5)-(6): rank-one accumulation,
!! a hand-coded Cholesky factorization for m <= mmax, det(M) = prod L_ii^2 and solves.
!! A non-positive pivot means det(M) <= 0 (outside or degenerate, Theorem 3.1): the
!! factorization reports failure and det is taken as 0. LAPACK (dpotrf) is the reference in
!! the tests; for m <= 8 this hand-coded form is faster than a library call per point.
module moment_matrix_m
  use kinds_m, only: wp
  implicit none
  private
  public :: moment_add, chol_small, chol_det, chol_solve, moment_symmetrize, singular_pivot

  !> Relative pivot below which M is treated as singular (det(M) = 0). A rank-deficient
  !! Gram matrix assembled in floating point keeps pivots of a few eps x M_jj (~1e-15);
  !! genuine pivots in the buffer zone stay above 1e-12 until det(M) is ~1e-40, far below
  !! any detection threshold.
  real(wp), parameter :: singular_pivot = 1.0e-12_wp

contains

  !> Upper triangle of mm(1:m,1:m) += w p p^T.
  pure subroutine moment_add(m, p, w, mm)
    integer, intent(in) :: m
    real(wp), intent(in) :: p(:), w
    real(wp), intent(inout) :: mm(:, :)
    integer :: i, j
    real(wp) :: wp_i
    do j = 1, m
      wp_i = w*p(j)
      do i = 1, j
        mm(i, j) = mm(i, j) + wp_i*p(i)
      end do
    end do
  end subroutine moment_add

  !> Copy the upper triangle into the lower one.
  pure subroutine moment_symmetrize(m, mm)
    integer, intent(in) :: m
    real(wp), intent(inout) :: mm(:, :)
    integer :: i, j
    do j = 1, m
      do i = j + 1, m
        mm(i, j) = mm(j, i)
      end do
    end do
  end subroutine moment_symmetrize

  !> In-place Cholesky of the upper triangle of a(1:m,1:m): on exit the lower triangle
  !! holds L (a = L L^T), diagonal included. ok is false at the first pivot <= tol * a_ii
  !! (tol = 0 by default: only a non-positive pivot fails).
  pure subroutine chol_small(m, a, ok, tol)
    integer, intent(in) :: m
    real(wp), intent(inout) :: a(:, :)
    logical, intent(out) :: ok
    real(wp), intent(in), optional :: tol
    integer :: i, j, k
    real(wp) :: s, rtol
    rtol = 0.0_wp
    if (present(tol)) rtol = tol
    ok = .false.
    do j = 1, m
      s = a(j, j)
      do k = 1, j - 1
        s = s - a(j, k)*a(j, k)
      end do
      if (s <= rtol*abs(a(j, j)) .or. s /= s) return
      a(j, j) = sqrt(s)
      do i = j + 1, m
        s = a(j, i)
        do k = 1, j - 1
          s = s - a(i, k)*a(j, k)
        end do
        a(i, j) = s/a(j, j)
      end do
    end do
    ok = .true.
  end subroutine chol_small

  !> det(M) = prod L_ii^2 from a factor computed by chol_small.
  pure real(wp) function chol_det(m, a) result(det)
    integer, intent(in) :: m
    real(wp), intent(in) :: a(:, :)
    integer :: i
    det = 1.0_wp
    do i = 1, m
      det = det*a(i, i)*a(i, i)
    end do
  end function chol_det

  !> Solve L L^T y = b in place (b overwritten by y).
  pure subroutine chol_solve(m, a, b)
    integer, intent(in) :: m
    real(wp), intent(in) :: a(:, :)
    real(wp), intent(inout) :: b(:)
    integer :: i, k
    real(wp) :: s
    do i = 1, m
      s = b(i)
      do k = 1, i - 1
        s = s - a(i, k)*b(k)
      end do
      b(i) = s/a(i, i)
    end do
    do i = m, 1, -1
      s = b(i)
      do k = i + 1, m
        s = s - a(k, i)*b(k)
      end do
      b(i) = s/a(i, i)
    end do
  end subroutine chol_solve
end module moment_matrix_m
