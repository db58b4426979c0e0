!> Rate-independent J2 plasticity with linear isotropic hardening (radial return).
!!
!! Not in the paper: for comparing with the Taylor-impact benchmarks of the literature
!! (doc/materials.md). Kirchhoff stress, Jaumann rate (eqs. 58-59): the elastic predictor is
!! tau_tr = Q tau_n Q^T + dt C:D (Hughes-Winget rotation, material_m); with s = dev(tau_tr),
!! sbar = sqrt(3/2 s:s) and the yield stress sigma_y(epsbar) = yield_stress + H epsbar, a
!! trial stress outside the yield surface is returned radially (backward Euler, exact for
!! linear hardening):
!!   dgamma = (sbar_tr - sigma_y(epsbar_n)) / (3G + H),
!!   s_{n+1} = (1 - 3G dgamma/sbar_tr) s_tr,   epsbar_{n+1} = epsbar_n + dgamma,
!! so that sbar_{n+1} = sigma_y(epsbar_{n+1}) to round-off. The plastic work of the step is
!! tau_{n+1}:D^p dt = sigma_y(epsbar_{n+1}) dgamma, and epsdot = dgamma/dt. The back stress
!! alpha is not used (isotropic hardening only).
module j2_plastic_m
  use kinds_m, only: wp
  use material_m, only: material_t, material_params_t, material_state_t, ncomp, &
    jaumann_rotate, elastic_rate, ncomp3d, jaumann_rotate_3d, elastic_rate_3d
  implicit none
  private
  public :: j2_plastic_t

  !> J2 plasticity: initial yield stress and linear hardening modulus.
  type, extends(material_t) :: j2_plastic_t
    real(wp) :: yield_stress = 0.0_wp  !< initial yield stress (Pa)
    real(wp) :: hardening = 0.0_wp     !< H = d sigma_y / d epsbar (Pa)
  contains
    procedure :: init => j2_init
    procedure :: update => j2_update
    procedure :: update3d => j2_update3d
    procedure, nopass :: model_name => j2_name
  end type j2_plastic_t

contains

  !> Elastic constants, yield_stress and hardening_modulus from params.
  subroutine j2_init(this, params)
    class(j2_plastic_t), intent(inout) :: this
    type(material_params_t), intent(in) :: params
    call this%set_elastic_constants(params%density, params%youngs_modulus, &
      params%poisson_ratio)
    this%yield_stress = params%yield_stress
    this%hardening = params%hardening_modulus
  end subroutine j2_init

  !> Elastic predictor and radial return for points i0..i1 (arguments: see update_i).
  subroutine j2_update(this, dt, d, w12, st, i0, i1, dwp)
    class(j2_plastic_t), intent(in) :: this
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :)
    real(wp), intent(in), contiguous :: w12(:)
    type(material_state_t), intent(inout) :: st
    integer, intent(in) :: i0, i1
    real(wp), intent(inout), contiguous :: dwp(:)
    real(wp) :: t(ncomp), r(ncomp), p, s(ncomp), sbar, sy, dgam, fac, g3, rdt
    integer :: i
    g3 = 3.0_wp*this%g
    rdt = 0.0_wp
    if (dt > 0.0_wp) rdt = 1.0_wp/dt
    do i = i0, i1
      t = st%tau(:, i)
      call jaumann_rotate(dt, w12(i), t)
      call elastic_rate(this%lambda, this%g, d(:, i), r)
      t = t + dt*r
      p = (t(1) + t(2) + t(3))/3.0_wp
      s(1:3) = t(1:3) - p
      s(4) = t(4)
      sbar = sqrt(1.5_wp*(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp*s(4)**2))
      sy = this%yield_stress + this%hardening*st%epsbar(i)
      if (sbar > sy) then
        dgam = (sbar - sy)/(g3 + this%hardening)
        fac = 1.0_wp - g3*dgam/sbar
        t(1:3) = fac*s(1:3) + p
        t(4) = fac*s(4)
        st%epsbar(i) = st%epsbar(i) + dgam
        st%epsdot(i) = dgam*rdt
        dwp(i) = (sy + this%hardening*dgam)*dgam
      else
        st%epsdot(i) = 0.0_wp
        dwp(i) = 0.0_wp
      end if
      st%tau(:, i) = t
    end do
  end subroutine j2_update

  !> j2_update in 3D (arguments: see update3d_i): the same predictor and radial return on
  !! six components, sbar = sqrt(3/2 (s11^2 + s22^2 + s33^2 + 2 (s23^2 + s13^2 + s12^2))).
  subroutine j2_update3d(this, dt, d, w, st, i0, i1, dwp)
    class(j2_plastic_t), intent(in) :: this
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :), w(:, :)
    type(material_state_t), intent(inout) :: st
    integer, intent(in) :: i0, i1
    real(wp), intent(inout), contiguous :: dwp(:)
    real(wp) :: t(ncomp3d), r(ncomp3d), p, s(ncomp3d), sbar, sy, dgam, fac, g3, rdt
    integer :: i
    g3 = 3.0_wp*this%g
    rdt = 0.0_wp
    if (dt > 0.0_wp) rdt = 1.0_wp/dt
    do i = i0, i1
      t = st%tau(:, i)
      call jaumann_rotate_3d(dt, w(:, i), t)
      call elastic_rate_3d(this%lambda, this%g, d(:, i), r)
      t = t + dt*r
      p = (t(1) + t(2) + t(3))/3.0_wp
      s(1:3) = t(1:3) - p
      s(4:6) = t(4:6)
      sbar = sqrt(1.5_wp*(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp*(s(4)**2 + s(5)**2 + &
        s(6)**2)))
      sy = this%yield_stress + this%hardening*st%epsbar(i)
      if (sbar > sy) then
        dgam = (sbar - sy)/(g3 + this%hardening)
        fac = 1.0_wp - g3*dgam/sbar
        t(1:3) = fac*s(1:3) + p
        t(4:6) = fac*s(4:6)
        st%epsbar(i) = st%epsbar(i) + dgam
        st%epsdot(i) = dgam*rdt
        dwp(i) = (sy + this%hardening*dgam)*dgam
      else
        st%epsdot(i) = 0.0_wp
        dwp(i) = 0.0_wp
      end if
      st%tau(:, i) = t
    end do
  end subroutine j2_update3d

  !> 'j2_plastic'.
  pure function j2_name() result(name)
    character(len=:), allocatable :: name
    name = 'j2_plastic'
  end function j2_name

end module j2_plastic_m
