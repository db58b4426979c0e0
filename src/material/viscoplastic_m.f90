!> The paper's J2 overstress viscoplastic model, eqs. (73)-(81), advanced by the rate tangent
!! method of Peirce, Shih and Needleman, eqs. (82)-(88).
!!
!! Model (Kirchhoff stress tau, Jaumann rate, eqs. 58-59):
!!   s = dev(tau) (74),  s' = s - alpha (75),  sbar^2 = 3/2 s':s' (76),  P = 3/2 s'/sbar (78),
!!   D^p = epsdot P (73),  epsdot = epsdot0 (sbar/g(epsbar))^(1/m) (79),
!!   g = sigma0 (1 + epsbar/eps0)^N / (1 + (epsbar/eps1)^2) (80),  alpha_jaumann = b D^p (81),
!!   tau_jaumann = C : (D - D^p) (58).
!! Rate tangent step (doc/materials.md), everything at t_n after the Hughes-Winget rotation:
!!   H0  = 3G + b P:P + sbar g'/g     (84; P:P = 3/2, and -(d epsdot/d epsbar)/(d epsdot/d sbar)
!!                                     = sbar g'/g for the power law)
!!   xi  = theta dt (epsdot_n/(m sbar)) H0                                   (86)
!!   epsdot_theta = epsdot_n/(1 + xi) + xi/((1 + xi) H0) (2G P):D            (83)
!!   tau_jaumann  = C:D - epsdot_theta 2G P     (87-88: C_tan:D - epsdot_n/(1+xi) 2G P)
!!   alpha_jaumann = b epsdot_theta P,  epsbar_{n+1} = epsbar_n + dt epsdot_theta,
!! with epsdot_n from eq. (79) at the state of step n, and epsdot_theta stored as the rate.
!!
!! Numerical guards (all documented in doc/materials.md):
!! - sbar = 0, or x = log(sbar/g)/m < -230 (epsdot_n < 1e-100 epsdot0; sbar < 0.1 g at
!!   m = 0.01): no flow, the step is elastic, and no denormal numbers arise.
!! - (sbar/g)^(1/m) has exponent 100 for m = 0.01: it is evaluated as exp(x),
!!   x = log(sbar/g)/m, with x capped at 300 (sbar/g = exp(300 m), i.e. 20 at m = 0.01) so it
!!   never overflows. Harmless: where the cap acts, xi >> 1 and epsdot_theta tends to
!!   P:D 2G/H0 + m sbar/(theta dt H0), independent of epsdot_n.
!! - epsdot_theta < 0 (strong unloading with xi >> 1) is set to 0: elastic unloading.
!! - H0 is kept >= G (reached only for a softening slope sbar g'/g < -2G, far outside metals).
!!
!! Bounded step (sub-stepping): epsdot_n is taken at the start of the step, so the step that
!! crosses the yield knee is integrated as an elastic one and overshoots by up to 3G times
!! its equivalent deviatoric strain increment deq = dt sqrt(2/3 D':D'); past deq ~ 5e-4
!! for the steel the peak stress overshoots (up to 56% at deq = 2.5e-3, 15x at 2.5e-2).
!! Each point is therefore advanced in nsub = ceiling(deq/deps_max) equal sub-steps of the
!! rate tangent step at the step's D, deps_max = substep_fraction sigma0/(3G). The bound is
!! on the total, not the plastic, deviatoric increment: it is known before the step from D
!! alone, and the knee-crossing step that needs bounding is the one whose plastic increment
!! is still ~0. The Hughes-Winget rotation stays once per step, over dt, before the
!! sub-steps; dwp sums the sub-steps' plastic work; epsdot is the step's mean rate. Below
!! the bound nsub = 1 and the update is the plain step, bit for bit.
module viscoplastic_m
  use kinds_m, only: wp
  use material_m, only: material_t, material_params_t, material_state_t, ncomp, &
    jaumann_rotate, elastic_rate, ncomp3d, jaumann_rotate_3d, elastic_rate_3d
  implicit none
  private
  public :: viscoplastic_t

  real(wp), parameter :: x_cap = 300.0_wp    !< cap on log(sbar/g)/m (see the module notes)
  real(wp), parameter :: x_floor = -230.0_wp !< below it epsdot_n < 1e-100 epsdot0: no flow
  !> Sub-steps keep the elastic trial change of sbar, 3G deq, at or below this fraction of
  !! sigma0 (deps_max = 9.45e-5 for the steel). Measured (doc/materials.md, single points at
  !! 1e5/s, every phase of the yield crossing): with steps up to 3G deq = 0.05 sigma0 the
  !! plain step's stress stays within 0.8% of a fine run over the whole history, knee
  !! included; at 0.13 sigma0 (deq = 2.5e-4) the knee is 4% off, and beyond 0.25 sigma0
  !! (deq ~ 5e-4) the peak overshoots. In units of sigma0/(3G) because both the knee width,
  !! m g/(3G), and the overshoot, 3G deq, scale with it, so the bound carries over to other
  !! metals.
  real(wp), parameter :: substep_fraction = 0.05_wp
  !> At most this many sub-steps (a step of deq = 1000 deps_max ~ 0.1 for the steel); it only
  !! bounds the cost of a point whose D is garbage (an inverted particle the run-health check
  !! is about to report), and the bound is not kept beyond it.
  integer, parameter :: max_substeps = 1000

  !> Overstress power-law viscoplasticity with isotropic (g) and kinematic (b) hardening.
  type, extends(material_t) :: viscoplastic_t
    real(wp) :: sigma0 = 0.0_wp   !< sigma_0 of eq. (80) (Pa)
    real(wp) :: n = 0.0_wp        !< hardening exponent N of eq. (80)
    real(wp) :: m = 1.0_wp        !< rate sensitivity m of eq. (79)
    real(wp) :: eps0 = 1.0_wp     !< epsilon_0 of eq. (80)
    real(wp) :: eps1 = 1.0_wp     !< epsilon_1 of eq. (80)
    real(wp) :: epsdot0 = 0.0_wp  !< reference rate of eq. (79) (1/s)
    real(wp) :: b = 0.0_wp        !< back-stress modulus of eq. (81) (Pa)
    real(wp) :: theta = 0.5_wp    !< time-integration parameter of eq. (86)
    !> Bound on the equivalent deviatoric strain increment of one sub-step (-), set by init
    !! to substep_fraction sigma0/(3G); huge(1.0_wp) switches sub-stepping off.
    real(wp) :: deps_max = huge(1.0_wp)
  contains
    procedure :: init => vp_init
    procedure :: update => vp_update
    procedure :: update3d => vp_update3d
    procedure, nopass :: model_name => vp_name
    procedure :: flow_stress => vp_flow_stress
  end type viscoplastic_t

contains

  !> Elastic constants, the parameters of eqs. (79)-(81), (86) from params, and the
  !! sub-step bound deps_max.
  subroutine vp_init(this, params)
    class(viscoplastic_t), intent(inout) :: this
    type(material_params_t), intent(in) :: params
    call this%set_elastic_constants(params%density, params%youngs_modulus, &
      params%poisson_ratio)
    this%sigma0 = params%sigma0
    this%n = params%hardening_n
    this%m = params%rate_m
    this%eps0 = params%eps0
    this%eps1 = params%eps1
    this%epsdot0 = params%epsdot0
    this%b = params%back_stress_b
    this%theta = params%theta
    this%deps_max = substep_fraction*this%sigma0/(3.0_wp*this%g)
  end subroutine vp_init

  !> Flow stress g(epsbar) of eq. (80) (Pa).
  pure real(wp) function vp_flow_stress(this, epsbar) result(gv)
    class(viscoplastic_t), intent(in) :: this
    real(wp), intent(in) :: epsbar
    gv = this%sigma0*(1.0_wp + epsbar/this%eps0)**this%n/(1.0_wp + (epsbar/this%eps1)**2)
  end function vp_flow_stress

  !> Advance points i0..i1 over one step dt (arguments: see update_i). Per point: the
  !! Hughes-Winget rotation of tau and alpha over the whole step, then nsub rate-tangent
  !! sub-steps of dt/nsub at the step's D, nsub the smallest count that keeps the equivalent
  !! deviatoric strain increment of each sub-step at or below deps_max (nsub = 1, the plain
  !! step, whenever the whole step already is). epsdot is stored as the step's mean rate,
  !! dwp as the sum of the sub-steps' plastic work.
  subroutine vp_update(this, dt, d, w12, st, i0, i1, dwp)
    class(viscoplastic_t), intent(in) :: this
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :)
    real(wp), intent(in), contiguous :: w12(:)
    type(material_state_t), intent(inout) :: st
    integer, intent(in) :: i0, i1
    real(wp), intent(inout), contiguous :: dwp(:)
    real(wp) :: t(ncomp), a(ncomp), ce(ncomp)
    real(wp) :: eb, edot, dw, wsum, esum, h, deq2, trd, rm, dmax2
    integer :: i, k, nsub
    rm = 1.0_wp/this%m
    dmax2 = min(this%deps_max, sqrt(huge(1.0_wp)))**2  ! no overflow when switched off
    do i = i0, i1
      t = st%tau(:, i)
      a = st%alpha(:, i)
      call jaumann_rotate(dt, w12(i), t)
      call jaumann_rotate(dt, w12(i), a)
      call elastic_rate(this%lambda, this%g, d(:, i), ce)
      eb = st%epsbar(i)
      ! squared equivalent deviatoric strain increment, dt^2 2/3 D':D' (NaN: nsub = 1)
      trd = (d(1, i) + d(2, i) + d(3, i))/3.0_wp
      deq2 = dt*dt*(2.0_wp/3.0_wp)*((d(1, i) - trd)**2 + (d(2, i) - trd)**2 &
        + (d(3, i) - trd)**2 + 2.0_wp*d(4, i)**2)
      if (deq2 > dmax2) then
        nsub = ceiling(min(sqrt(deq2/dmax2), real(max_substeps, wp)))
        h = dt/nsub
        wsum = 0.0_wp
        esum = 0.0_wp
        do k = 1, nsub
          call rate_tangent_step(this, rm, h, d(:, i), ce, t, a, eb, edot, dw)
          wsum = wsum + dw
          esum = esum + edot
        end do
        dwp(i) = wsum
        st%epsdot(i) = esum/nsub
      else
        call rate_tangent_step(this, rm, dt, d(:, i), ce, t, a, eb, edot, dw)
        dwp(i) = dw
        st%epsdot(i) = edot
      end if
      st%tau(:, i) = t
      st%alpha(:, i) = a
      st%epsbar(i) = eb
    end do
  end subroutine vp_update

  !> One rate-tangent step of length h (s), eqs. (82)-(88), at the step's D = d (1/s) with
  !! ce = C:D (Pa/s) and rm = 1/m, from the (already rotated) state t = tau, a = alpha (Pa),
  !! eb = epsbar, all updated in place; edot the rate epsdot_theta of the step (1/s), dw its
  !! plastic work h epsdot_theta P:(tau_start + tau_end)/2 (J/m^3, midpoint stress).
  pure subroutine rate_tangent_step(this, rm, h, d, ce, t, a, eb, edot, dw)
    type(viscoplastic_t), intent(in) :: this
    real(wp), intent(in) :: rm, h, d(ncomp), ce(ncomp)
    real(wp), intent(inout) :: t(ncomp), a(ncomp), eb
    real(wp), intent(out) :: edot, dw
    real(wp) :: r(ncomp), s(ncomp), pdir(ncomp), tn(ncomp)
    real(wp) :: p, sbar, gv, dlng, x, edn, h0, xi, pd, g2
    g2 = 2.0_wp*this%g
    r = ce
    edot = 0.0_wp
    pdir = 0.0_wp
    ! s' = dev(tau) - alpha and sbar, eqs. (74)-(76)
    p = (t(1) + t(2) + t(3))/3.0_wp
    s(1:3) = t(1:3) - p - a(1:3)
    s(4) = t(4) - a(4)
    sbar = sqrt(1.5_wp*(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp*s(4)**2))
    if (sbar > 0.0_wp) then
      gv = this%sigma0*(1.0_wp + eb/this%eps0)**this%n/(1.0_wp + (eb/this%eps1)**2)
      x = log(sbar/gv)*rm
      if (x > x_floor) then
        edn = this%epsdot0*exp(min(x, x_cap))                          ! eq. (79)
        dlng = this%n/(this%eps0 + eb) - 2.0_wp*eb/(this%eps1**2 + eb**2)  ! g'/g
        pdir = (1.5_wp/sbar)*s                                          ! eq. (78)
        ! eq. (84) with b P:P = 3/2 b; kept >= G (module notes)
        h0 = max(3.0_wp*this%g + 1.5_wp*this%b + sbar*dlng, this%g)
        xi = this%theta*h*edn*rm/sbar*h0                                ! eq. (86)
        pd = g2*(pdir(1)*d(1) + pdir(2)*d(2) + pdir(3)*d(3) + 2.0_wp*pdir(4)*d(4))  ! (C:P):D
        edot = max(0.0_wp, (edn + xi*pd/h0)/(1.0_wp + xi))              ! eq. (83)
        r = r - (edot*g2)*pdir                                          ! eqs. (87)-(88)
      end if
    end if
    tn = t + h*r
    if (edot > 0.0_wp) then
      a = a + (h*this%b*edot)*pdir                                      ! eq. (81)
      eb = eb + h*edot
      dw = h*edot*0.5_wp*(pdir(1)*(t(1) + tn(1)) + pdir(2)*(t(2) + tn(2)) &
        + pdir(3)*(t(3) + tn(3)) + 2.0_wp*pdir(4)*(t(4) + tn(4)))
    else
      dw = 0.0_wp
    end if
    t = tn
  end subroutine rate_tangent_step

  !> vp_update in 3D (arguments: see update3d_i): the same rotation, sub-step count and
  !! rate-tangent steps on six components (the shear ones weighted twice in the inner
  !! products: D':D' and P:D).
  subroutine vp_update3d(this, dt, d, w, st, i0, i1, dwp)
    class(viscoplastic_t), intent(in) :: this
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :), w(:, :)
    type(material_state_t), intent(inout) :: st
    integer, intent(in) :: i0, i1
    real(wp), intent(inout), contiguous :: dwp(:)
    real(wp) :: t(ncomp3d), a(ncomp3d), ce(ncomp3d)
    real(wp) :: eb, edot, dw, wsum, esum, h, deq2, trd, rm, dmax2
    integer :: i, k, nsub
    rm = 1.0_wp/this%m
    dmax2 = min(this%deps_max, sqrt(huge(1.0_wp)))**2
    do i = i0, i1
      t = st%tau(:, i)
      a = st%alpha(:, i)
      call jaumann_rotate_3d(dt, w(:, i), t)
      call jaumann_rotate_3d(dt, w(:, i), a)
      call elastic_rate_3d(this%lambda, this%g, d(:, i), ce)
      eb = st%epsbar(i)
      trd = (d(1, i) + d(2, i) + d(3, i))/3.0_wp
      deq2 = dt*dt*(2.0_wp/3.0_wp)*((d(1, i) - trd)**2 + (d(2, i) - trd)**2 &
        + (d(3, i) - trd)**2 + 2.0_wp*(d(4, i)**2 + d(5, i)**2 + d(6, i)**2))
      nsub = 1
      if (deq2 > dmax2) nsub = ceiling(min(sqrt(deq2/dmax2), real(max_substeps, wp)))
      h = dt/nsub
      wsum = 0.0_wp
      esum = 0.0_wp
      do k = 1, nsub
        call rate_tangent_step_3d(this, rm, h, d(:, i), ce, t, a, eb, edot, dw)
        wsum = wsum + dw
        esum = esum + edot
      end do
      dwp(i) = wsum
      st%epsdot(i) = esum/nsub
      st%tau(:, i) = t
      st%alpha(:, i) = a
      st%epsbar(i) = eb
    end do
  end subroutine vp_update3d

  !> rate_tangent_step on six components (eqs. 82-88 in 3D).
  pure subroutine rate_tangent_step_3d(this, rm, h, d, ce, t, a, eb, edot, dw)
    type(viscoplastic_t), intent(in) :: this
    real(wp), intent(in) :: rm, h, d(ncomp3d), ce(ncomp3d)
    real(wp), intent(inout) :: t(ncomp3d), a(ncomp3d), eb
    real(wp), intent(out) :: edot, dw
    real(wp) :: r(ncomp3d), s(ncomp3d), pdir(ncomp3d), tn(ncomp3d), wgt(ncomp3d)
    real(wp) :: p, sbar, gv, dlng, x, edn, h0, xi, pd, g2
    ! the weights of a symmetric tensor's inner product in this layout
    wgt = [1.0_wp, 1.0_wp, 1.0_wp, 2.0_wp, 2.0_wp, 2.0_wp]
    g2 = 2.0_wp*this%g
    r = ce
    edot = 0.0_wp
    pdir = 0.0_wp
    p = (t(1) + t(2) + t(3))/3.0_wp
    s(1:3) = t(1:3) - p - a(1:3)
    s(4:6) = t(4:6) - a(4:6)
    sbar = sqrt(1.5_wp*sum(wgt*s*s))
    if (sbar > 0.0_wp) then
      gv = this%sigma0*(1.0_wp + eb/this%eps0)**this%n/(1.0_wp + (eb/this%eps1)**2)
      x = log(sbar/gv)*rm
      if (x > x_floor) then
        edn = this%epsdot0*exp(min(x, x_cap))                          ! eq. (79)
        dlng = this%n/(this%eps0 + eb) - 2.0_wp*eb/(this%eps1**2 + eb**2)
        pdir = (1.5_wp/sbar)*s                                          ! eq. (78)
        h0 = max(3.0_wp*this%g + 1.5_wp*this%b + sbar*dlng, this%g)
        xi = this%theta*h*edn*rm/sbar*h0                                ! eq. (86)
        pd = g2*sum(wgt*pdir*d)                                         ! (C:P):D
        edot = max(0.0_wp, (edn + xi*pd/h0)/(1.0_wp + xi))              ! eq. (83)
        r = r - (edot*g2)*pdir                                          ! eqs. (87)-(88)
      end if
    end if
    tn = t + h*r
    if (edot > 0.0_wp) then
      a = a + (h*this%b*edot)*pdir                                      ! eq. (81)
      eb = eb + h*edot
      dw = h*edot*0.5_wp*sum(wgt*pdir*(t + tn))
    else
      dw = 0.0_wp
    end if
    t = tn
  end subroutine rate_tangent_step_3d

  !> 'viscoplastic'.
  pure function vp_name() result(name)
    character(len=:), allocatable :: name
    name = 'viscoplastic'
  end function vp_name

end module viscoplastic_m
