!> Linear isotropic hypoelastic material in Jaumann rate form (verification model).
!!
!! Eq. (58) with D^p = 0: tau_jaumann = C : D = lambda tr(D) 1 + 2 G D, tau the Kirchhoff
!! stress; the spin terms of eq. (59) by the Hughes-Winget rotation (material_m).
!! Under uniaxial strain at constant rate without spin this is exact in the logarithmic strain
!! (tau11 = (lambda + 2G) eps, tau22 = tau33 = lambda eps); under simple shear it gives the
!! Jaumann oscillation tau12 = G sin(gamma), tau11 = -tau22 = G (1 - cos(gamma)).
module elastic_m
  use kinds_m, only: wp
  use material_m, only: material_t, material_params_t, material_state_t, ncomp, &
    jaumann_rotate, elastic_rate, ncomp3d, jaumann_rotate_3d, elastic_rate_3d
  implicit none
  private
  public :: elastic_t

  !> Hypoelastic material: only the elastic constants of material_t.
  type, extends(material_t) :: elastic_t
  contains
    procedure :: init => elastic_init
    procedure :: update => elastic_update
    procedure :: update3d => elastic_update3d
    procedure, nopass :: model_name => elastic_name
  end type elastic_t

contains

  !> Elastic constants from params (density, youngs_modulus, poisson_ratio).
  subroutine elastic_init(this, params)
    class(elastic_t), intent(inout) :: this
    type(material_params_t), intent(in) :: params
    call this%set_elastic_constants(params%density, params%youngs_modulus, &
      params%poisson_ratio)
  end subroutine elastic_init

  !> tau_{n+1} = Q tau_n Q^T + dt C:D for points i0..i1; no plastic work (see update_i).
  subroutine elastic_update(this, dt, d, w12, st, i0, i1, dwp)
    class(elastic_t), intent(in) :: this
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :)
    real(wp), intent(in), contiguous :: w12(:)
    type(material_state_t), intent(inout) :: st
    integer, intent(in) :: i0, i1
    real(wp), intent(inout), contiguous :: dwp(:)
    real(wp) :: t(ncomp), r(ncomp)
    integer :: i
    do i = i0, i1
      t = st%tau(:, i)
      call jaumann_rotate(dt, w12(i), t)
      call elastic_rate(this%lambda, this%g, d(:, i), r)
      st%tau(:, i) = t + dt*r
      dwp(i) = 0.0_wp
    end do
  end subroutine elastic_update

  !> elastic_update in 3D (arguments: see update3d_i).
  subroutine elastic_update3d(this, dt, d, w, st, i0, i1, dwp)
    class(elastic_t), intent(in) :: this
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :), w(:, :)
    type(material_state_t), intent(inout) :: st
    integer, intent(in) :: i0, i1
    real(wp), intent(inout), contiguous :: dwp(:)
    real(wp) :: t(ncomp3d), r(ncomp3d)
    integer :: i
    do i = i0, i1
      t = st%tau(:, i)
      call jaumann_rotate_3d(dt, w(:, i), t)
      call elastic_rate_3d(this%lambda, this%g, d(:, i), r)
      st%tau(:, i) = t + dt*r
      dwp(i) = 0.0_wp
    end do
  end subroutine elastic_update3d

  !> 'elastic'.
  pure function elastic_name() result(name)
    character(len=:), allocatable :: name
    name = 'elastic'
  end function elastic_name

end module elastic_m
