!> Window (kernel) functions of RKPM, eq. (8) of Li, Qian, Liu, Belytschko (2001).
!!
!! Convention (doc/design.md, Decisions: the text and footnote 1 hold against eq. (2)): the
!! 1D window w(s) has support |s| < 2 and unit integral; the dilation parameter rho is the
!! support *radius*, so in each direction
!! phi_rho(x) = prod_i (2/rho_i) w(2 x_i/rho_i), support |x_i| < rho_i, integral 1.
!! The radial window uses r = |2 x/rho| (elliptic when rho differs per direction) and a
!! constant c_n so that it also integrates to 1 in n dimensions.
module kernels_m
  use dims_m, only: max_dim
  use kinds_m, only: wp, pi
  implicit none
  private
  public :: kernel_cubic, kernel_quartic, kernel_names, kernel_id
  public :: window_tensor, window_radial, window_shape_names, window_shape_id
  public :: window_1d, window_1d_d, radial_norm, window_eval

  integer, parameter :: kernel_cubic = 1    !< cubic B-spline, eq. (8)
  integer, parameter :: kernel_quartic = 2  !< quartic spline 1 - 6q^2 + 8q^3 - 3q^4, q = |s|/2
  character(len=*), parameter :: kernel_names(2) = [character(len=12) :: &
    'cubic_spline', 'quartic']

  integer, parameter :: window_tensor = 1   !< tensor-product box (Example 2.2, the default)
  integer, parameter :: window_radial = 2   !< circular / spherical support
  character(len=*), parameter :: window_shape_names(2) = [character(len=6) :: &
    'tensor', 'radial']

  !> 1D normalisation of the quartic: integral of f(|s|/2) over (-2,2) is 1.6.
  real(wp), parameter :: quartic_1d = 1.6_wp

contains

  !> Kernel id from its deck name, 0 if unknown.
  pure integer function kernel_id(name)
    character(len=*), intent(in) :: name
    integer :: k
    kernel_id = 0
    do k = 1, size(kernel_names)
      if (trim(adjustl(name)) == trim(kernel_names(k))) kernel_id = k
    end do
  end function kernel_id

  !> Window shape id from its deck name, 0 if unknown.
  pure integer function window_shape_id(name)
    character(len=*), intent(in) :: name
    integer :: k
    window_shape_id = 0
    do k = 1, size(window_shape_names)
      if (trim(adjustl(name)) == trim(window_shape_names(k))) window_shape_id = k
    end do
  end function window_shape_id

  !> 1D window w(s), support |s| < 2, unit integral.
  elemental real(wp) function window_1d(kid, s) result(w)
    integer, intent(in) :: kid
    real(wp), intent(in) :: s
    real(wp) :: a, q
    a = abs(s)
    w = 0.0_wp
    if (a >= 2.0_wp) return
    select case (kid)
    case (kernel_cubic)
      if (a < 1.0_wp) then
        w = 2.0_wp/3.0_wp - a*a*(1.0_wp - 0.5_wp*a)
      else
        w = (2.0_wp - a)**3/6.0_wp
      end if
    case (kernel_quartic)
      q = 0.5_wp*a
      w = (1.0_wp + q*q*(-6.0_wp + q*(8.0_wp - 3.0_wp*q)))/quartic_1d
    end select
  end function window_1d

  !> 1D window and its derivative dw/ds.
  elemental subroutine window_1d_d(kid, s, w, dw)
    integer, intent(in) :: kid
    real(wp), intent(in) :: s
    real(wp), intent(out) :: w, dw
    real(wp) :: a, q, sg
    a = abs(s)
    w = 0.0_wp
    dw = 0.0_wp
    if (a >= 2.0_wp) return
    sg = sign(1.0_wp, s)
    select case (kid)
    case (kernel_cubic)
      if (a < 1.0_wp) then
        w = 2.0_wp/3.0_wp - a*a*(1.0_wp - 0.5_wp*a)
        dw = sg*a*(1.5_wp*a - 2.0_wp)
      else
        w = (2.0_wp - a)**3/6.0_wp
        dw = -sg*0.5_wp*(2.0_wp - a)**2
      end if
    case (kernel_quartic)
      q = 0.5_wp*a
      w = (1.0_wp + q*q*(-6.0_wp + q*(8.0_wp - 3.0_wp*q)))/quartic_1d
      dw = sg*0.5_wp*q*(-12.0_wp + q*(24.0_wp - 12.0_wp*q))/quartic_1d
    end select
  end subroutine window_1d_d

  !> Constant c_n making the radial window c_n w(|s|) integrate to 1 over R^n (s scaled).
  !! Cubic: int w(|s|) = 1, 7 pi/15, 2 pi/3 in 1, 2, 3D; quartic: 1, pi/2, 16 pi/21.
  pure real(wp) function radial_norm(kid, ndim) result(c)
    integer, intent(in) :: kid, ndim
    c = 1.0_wp
    select case (kid)
    case (kernel_cubic)
      select case (ndim)
      case (2)
        c = 15.0_wp/(7.0_wp*pi)
      case (3)
        c = 3.0_wp/(2.0_wp*pi)
      end select
    case (kernel_quartic)
      select case (ndim)
      case (2)
        c = 2.0_wp/pi
      case (3)
        c = 21.0_wp/(16.0_wp*pi)
      end select
    end select
  end function radial_norm

  !> phi_rho(d) and optionally its gradient with respect to d, for d = x_l - x.
  !! rhoinv(ndim): 1/rho per direction; cn: radial_norm(kid, ndim) for radial windows.
  pure subroutine window_eval(kid, wshape, ndim, d, rhoinv, cn, phi, dphi)
    integer, intent(in) :: kid, wshape, ndim
    real(wp), intent(in) :: d(ndim), rhoinv(ndim), cn
    real(wp), intent(out) :: phi
    real(wp), intent(out), optional :: dphi(ndim)
    ! fixed-size work arrays, of which the first ndim are used: arrays of size ndim were
    ! heap allocations at every call (three per neighbour of every det(M) evaluation)
    real(wp) :: s(max_dim), w(max_dim), dw(max_dim), r, wr, dwr, scale
    integer :: i, j
    s(:ndim) = 2.0_wp*d*rhoinv
    scale = product(2.0_wp*rhoinv)
    if (wshape == window_tensor) then
      if (present(dphi)) then
        call window_1d_d(kid, s(:ndim), w(:ndim), dw(:ndim))
        phi = scale*product(w(:ndim))
        do i = 1, ndim
          dphi(i) = scale*2.0_wp*rhoinv(i)*dw(i)
          do j = 1, ndim
            if (j /= i) dphi(i) = dphi(i)*w(j)
          end do
        end do
      else
        w(:ndim) = window_1d(kid, s(:ndim))
        phi = scale*product(w(:ndim))
      end if
    else
      r = sqrt(sum(s(:ndim)*s(:ndim)))
      if (present(dphi)) then
        call window_1d_d(kid, r, wr, dwr)
        phi = cn*scale*wr
        if (r > 0.0_wp) then
          dphi = cn*scale*dwr*s(:ndim)*2.0_wp*rhoinv/r
        else
          dphi = 0.0_wp
        end if
      else
        phi = cn*scale*window_1d(kid, r)
      end if
    end if
  end subroutine window_eval
end module kernels_m
