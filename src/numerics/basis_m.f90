!> Monomial bases P(z) of the moment matrix, eq. (3), in scaled coordinates z = (x_l - x)/h.
!! Deck names are read together with the dimension: 'linear' is (1,z) in 1D, (1,x,y) in 2D,
!! (1,x,y,z) in 3D. 'counterexample_1xy' is the paper's P = (1, xy) of Theorem 3.1 (2D).
module basis_m
  use kinds_m, only: wp
  implicit none
  private
  public :: mmax, basis_linear_1d, basis_quadratic_1d, basis_linear_2d, basis_bilinear
  public :: basis_quadratic_2d, basis_linear_3d, basis_trilinear, basis_1xy
  public :: basis_size, basis_id, basis_names, basis_eval, basis_eval_grad, basis_order

  integer, parameter :: mmax = 8  !< largest basis size (trilinear)

  integer, parameter :: basis_linear_1d = 1     !< (1, z)
  integer, parameter :: basis_quadratic_1d = 2  !< (1, z, z^2)
  integer, parameter :: basis_linear_2d = 3     !< (1, x, y)
  integer, parameter :: basis_bilinear = 4      !< (1, x, y, xy), the paper's default
  integer, parameter :: basis_quadratic_2d = 5  !< (1, x, y, x^2, xy, y^2)
  integer, parameter :: basis_linear_3d = 6     !< (1, x, y, z)
  integer, parameter :: basis_trilinear = 7     !< (1, x, y, z, xy, yz, zx, xyz)
  integer, parameter :: basis_1xy = 8           !< (1, xy): Theorem 3.1's counterexample

  character(len=*), parameter :: basis_names(5) = [character(len=18) :: &
    'linear', 'quadratic', 'bilinear', 'trilinear', 'counterexample_1xy']

contains

  !> Basis id from deck name and dimension; 0 when the name is unknown or not defined in ndim.
  pure integer function basis_id(name, ndim) result(bid)
    character(len=*), intent(in) :: name
    integer, intent(in) :: ndim
    bid = 0
    select case (trim(adjustl(name)))
    case ('linear')
      if (ndim == 1) bid = basis_linear_1d
      if (ndim == 2) bid = basis_linear_2d
      if (ndim == 3) bid = basis_linear_3d
    case ('quadratic')
      if (ndim == 1) bid = basis_quadratic_1d
      if (ndim == 2) bid = basis_quadratic_2d
    case ('bilinear')
      if (ndim == 2) bid = basis_bilinear
    case ('trilinear')
      if (ndim == 3) bid = basis_trilinear
    case ('counterexample_1xy')
      if (ndim == 2) bid = basis_1xy
    end select
  end function basis_id

  !> Number of monomials m.
  pure integer function basis_size(bid) result(m)
    integer, intent(in) :: bid
    select case (bid)
    case (basis_linear_1d, basis_1xy)
      m = 2
    case (basis_quadratic_1d, basis_linear_2d)
      m = 3
    case (basis_bilinear, basis_linear_3d)
      m = 4
    case (basis_quadratic_2d)
      m = 6
    case (basis_trilinear)
      m = 8
    case default
      m = 0
    end select
  end function basis_size

  !> Highest polynomial degree per coordinate direction (1 for linear and multilinear).
  pure integer function basis_order(bid) result(p)
    integer, intent(in) :: bid
    select case (bid)
    case (basis_quadratic_1d, basis_quadratic_2d)
      p = 2
    case default
      p = 1
    end select
  end function basis_order

  !> P(z) for one point.
  pure subroutine basis_eval(bid, z, p)
    integer, intent(in) :: bid
    real(wp), intent(in) :: z(:)
    real(wp), intent(out) :: p(:)
    p(1) = 1.0_wp
    select case (bid)
    case (basis_linear_1d)
      p(2) = z(1)
    case (basis_quadratic_1d)
      p(2) = z(1)
      p(3) = z(1)*z(1)
    case (basis_linear_2d)
      p(2:3) = z(1:2)
    case (basis_bilinear)
      p(2:3) = z(1:2)
      p(4) = z(1)*z(2)
    case (basis_quadratic_2d)
      p(2:3) = z(1:2)
      p(4) = z(1)*z(1)
      p(5) = z(1)*z(2)
      p(6) = z(2)*z(2)
    case (basis_linear_3d)
      p(2:4) = z(1:3)
    case (basis_trilinear)
      p(2:4) = z(1:3)
      p(5) = z(1)*z(2)
      p(6) = z(2)*z(3)
      p(7) = z(3)*z(1)
      p(8) = z(1)*z(2)*z(3)
    case (basis_1xy)
      p(2) = z(1)*z(2)
    end select
  end subroutine basis_eval

  !> P(z) and dP/dz (dp(k, i) = d P_k / d z_i).
  pure subroutine basis_eval_grad(bid, z, p, dp)
    integer, intent(in) :: bid
    real(wp), intent(in) :: z(:)
    real(wp), intent(out) :: p(:), dp(:, :)
    call basis_eval(bid, z, p)
    dp = 0.0_wp
    select case (bid)
    case (basis_linear_1d)
      dp(2, 1) = 1.0_wp
    case (basis_quadratic_1d)
      dp(2, 1) = 1.0_wp
      dp(3, 1) = 2.0_wp*z(1)
    case (basis_linear_2d)
      dp(2, 1) = 1.0_wp
      dp(3, 2) = 1.0_wp
    case (basis_bilinear)
      dp(2, 1) = 1.0_wp
      dp(3, 2) = 1.0_wp
      dp(4, 1) = z(2)
      dp(4, 2) = z(1)
    case (basis_quadratic_2d)
      dp(2, 1) = 1.0_wp
      dp(3, 2) = 1.0_wp
      dp(4, 1) = 2.0_wp*z(1)
      dp(5, 1) = z(2)
      dp(5, 2) = z(1)
      dp(6, 2) = 2.0_wp*z(2)
    case (basis_linear_3d)
      dp(2, 1) = 1.0_wp
      dp(3, 2) = 1.0_wp
      dp(4, 3) = 1.0_wp
    case (basis_trilinear)
      dp(2, 1) = 1.0_wp
      dp(3, 2) = 1.0_wp
      dp(4, 3) = 1.0_wp
      dp(5, 1) = z(2)
      dp(5, 2) = z(1)
      dp(6, 2) = z(3)
      dp(6, 3) = z(2)
      dp(7, 3) = z(1)
      dp(7, 1) = z(3)
      dp(8, 1) = z(2)*z(3)
      dp(8, 2) = z(1)*z(3)
      dp(8, 3) = z(1)*z(2)
    case (basis_1xy)
      dp(2, 1) = z(2)
      dp(2, 2) = z(1)
    end select
  end subroutine basis_eval_grad
end module basis_m
