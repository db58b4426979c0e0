!> Constitutive models: the abstract material, its parameters and state, the factory.
!!
!! Section 4 of Li, Qian, Liu, Belytschko (2001). The stress is the Kirchhoff stress
!! tau = J sigma, advanced with its Jaumann rate (eq. 59),
!!   tau_dot = tau_jaumann + W.tau - tau.W,   tau_jaumann = C : (D - D^p)   (eq. 58),
!! C isotropic (lambda, G). Models (doc/materials.md): 'elastic' (D^p = 0), 'j2_plastic'
!! (rate-independent J2, linear isotropic hardening, radial return) and 'viscoplastic' (the
!! paper's overstress power law, eqs. (73)-(81), by the rate tangent method, eqs. (82)-(88)).
!!
!! Conventions (2D: plane strain and axisymmetric carry 3D tensors):
!! - components ordered (11, 22, 33, 12): 1-2 the plane (x,y or r,z), 3 out of plane (zz in
!!   plane strain, the hoop theta-theta in axisymmetry); 13 = 23 = 0;
!! - tau(4,n) and alpha(4,n) in Pa; d(4,n) holds D11, D22, D33, D12 (tensor components, 1/s);
!!   w12(n) = W12 = -W21 (1/s), the only non-zero spin component;
!! - a double contraction a:b = a11 b11 + a22 b22 + a33 b33 + 2 a12 b12.
!! Rotation: the Hughes-Winget rotation Q = (I - dt W/2)^-1 (I + dt W/2) applied as
!! tau* = Q tau_n Q^T (and likewise alpha), then tau_{n+1} = tau* + dt tau_jaumann.
!!
!! All models are chosen once by make_material; the time loop calls mat%update on blocks of
!! points (i0..i1), never per point through a select case.
module material_m
  use dims_m, only: dims_plane
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use strings_m, only: rtoa, join_names, lower
  implicit none
  private
  public :: ncomp, material_names
  public :: material_params_t, material_state_t, material_t
  public :: make_material, check_material_params, jaumann_rotate, elastic_rate
  public :: ncomp3d, jaumann_rotate_3d, elastic_rate_3d
  public :: material_constant_names, material_constant_units, material_constant_meaning, &
    model_uses, model_default, &
    material_constant, set_material_constant, material_presets

  !> stored tensor components (11, 22, 33, 12): the updates are the plane kernels
  integer, parameter :: ncomp = dims_plane%ncomp
  !> the components of a symmetric tensor in 3D (dims_3d: 11, 22, 33, 23, 13, 12)
  integer, parameter :: ncomp3d = 6

  !> Valid values of material_params_t%model.
  character(len=*), parameter :: material_names(3) = [character(len=12) :: &
    'elastic', 'j2_plastic', 'viscoplastic']

  !> Material parameters as read from the deck, SI units. Defaults: the paper's steel
  !! (Table 1 with E = 211 GPa, doc/materials.md: the printed 2110 MPa contradicts
  !! eps0 = sigma0/E = 460 MPa / 2.18e-3).
  !> The constants of a material, in this order everywhere (deck, log, output); a model
  !! uses some of them (model_uses).
  character(len=*), parameter :: material_constant_names(13) = [character(len=17) :: &
    'density', 'youngs_modulus', 'poisson_ratio', 'sigma0', 'hardening_n', 'rate_m', &
    'eps0', 'eps1', 'epsdot0', 'back_stress_b', 'theta', 'yield_stress', &
    'hardening_modulus']
  character(len=*), parameter :: material_constant_units(13) = [character(len=6) :: &
    'kg/m^3', 'Pa', '-', 'Pa', '-', '-', '-', '-', '1/s', 'Pa', '-', 'Pa', 'Pa']
  !> What each constant is, for the messages that ask for one.
  character(len=*), parameter :: material_constant_meaning(13) = [character(len=128) :: &
    'the reference density', 'Young''s modulus (Pa, not MPa or GPa)', &
    'Poisson''s ratio', 'sigma_0 of the flow stress g, eq. (80)', &
    'N, the hardening exponent of eq. (80)', 'm, the rate sensitivity of eq. (79)', &
    'eps0 of eq. (80), often sigma0/E', &
    'eps1, the softening strain of eq. (80): g falls as 1/(1 + (epsbar/eps1)^2); '// &
    'a large value turns softening off', &
    'the reference strain rate of eq. (79)', 'b, the back-stress modulus of eq. (81)', &
    'theta of the rate tangent, eq. (86)', 'the initial yield stress', &
    'H, the linear hardening modulus (0: perfectly plastic)']

  !> Named sets of constants a deck may ask for (&material preset): 'paper_steel' is the
  !! paper's steel (Table 1 and Section 6), material_params_t's initial values.
  character(len=*), parameter :: material_presets(1) = [character(len=11) :: 'paper_steel']

  type :: material_params_t
    character(len=32) :: model = 'viscoplastic'  !< one of material_names
    real(wp) :: density = 7800.0_wp         !< rho0 (kg/m^3)
    real(wp) :: youngs_modulus = 211.0e9_wp !< E (Pa)
    real(wp) :: poisson_ratio = 0.3_wp      !< nu (-)
    ! viscoplastic, eqs. (79)-(81) and (86)
    real(wp) :: sigma0 = 460.0e6_wp         !< sigma_0 of g, eq. (80) (Pa)
    real(wp) :: hardening_n = 0.1_wp        !< N of eq. (80) (-)
    real(wp) :: rate_m = 0.01_wp            !< m of eq. (79) (-)
    real(wp) :: eps0 = 2.18e-3_wp           !< epsilon_0 of eq. (80) (-)
    real(wp) :: eps1 = 0.218_wp             !< epsilon_1 of eq. (80), 100 eps0 (-)
    real(wp) :: epsdot0 = 0.0021_wp         !< reference rate of eq. (79) (1/s)
    real(wp) :: back_stress_b = 0.0_wp      !< b of eq. (81) (Pa); not in Table 1
    real(wp) :: theta = 0.5_wp              !< theta of eq. (86), 0 explicit .. 1 (-)
    ! j2_plastic
    real(wp) :: yield_stress = 460.0e6_wp   !< initial yield stress (Pa)
    real(wp) :: hardening_modulus = 0.0_wp  !< H, in yield = yield_stress + H epsbar (Pa)
  end type material_params_t

  !> Per-point state in structure-of-arrays form.
  type :: material_state_t
    real(wp), allocatable :: tau(:, :)    !< Kirchhoff stress (4, n) (Pa)
    real(wp), allocatable :: alpha(:, :)  !< back stress (4, n) (Pa)
    real(wp), allocatable :: epsbar(:)    !< effective plastic strain (n) (-)
    real(wp), allocatable :: epsdot(:)    !< effective plastic strain rate of the last step (1/s)
  contains
    procedure :: init => state_init
    procedure :: init3d => state_init3d
  end type material_state_t

  !> A constitutive model: elastic constants plus what an extension adds.
  type, abstract :: material_t
    real(wp) :: rho0 = 0.0_wp    !< reference density (kg/m^3)
    real(wp) :: e = 0.0_wp       !< Young's modulus (Pa)
    real(wp) :: nu = 0.0_wp      !< Poisson's ratio (-)
    real(wp) :: g = 0.0_wp       !< shear modulus E/(2(1+nu)) (Pa)
    real(wp) :: k = 0.0_wp       !< bulk modulus E/(3(1-2nu)) (Pa)
    real(wp) :: lambda = 0.0_wp  !< Lame's first parameter (Pa)
  contains
    procedure(init_i), deferred :: init
    procedure(update_i), deferred :: update
    procedure(update3d_i), deferred :: update3d
    procedure(model_name_i), deferred, nopass :: model_name
    procedure :: set_elastic_constants
    procedure :: dilatational_speed
  end type material_t

  abstract interface
    !> Take the model's parameters (assumed checked by check_material_params).
    subroutine init_i(this, params)
      import :: material_t, material_params_t
      class(material_t), intent(inout) :: this
      type(material_params_t), intent(in) :: params
    end subroutine init_i

    !> Advance points i0..i1 over one step dt (s): d(:,i) rate of deformation (1/s),
    !! w12(i) spin (1/s), st the state (tau, alpha, epsbar, epsdot of point i updated);
    !! dwp(i) the plastic work of the step per unit reference volume, tau:D^p dt (J/m^3).
    !! d, w12, dwp are indexed like st (point i is column i everywhere); only entries i0..i1
    !! are read or written, so blocks may run concurrently on disjoint ranges.
    subroutine update_i(this, dt, d, w12, st, i0, i1, dwp)
      import :: material_t, material_state_t, wp
      class(material_t), intent(in) :: this
      real(wp), intent(in) :: dt
      real(wp), intent(in), contiguous :: d(:, :)
      real(wp), intent(in), contiguous :: w12(:)
      type(material_state_t), intent(inout) :: st
      integer, intent(in) :: i0, i1
      real(wp), intent(inout), contiguous :: dwp(:)
    end subroutine update_i

    !> update_i in three dimensions (dims_3d): d(6, :) the rate of deformation in the
    !! order 11, 22, 33, 23, 13, 12 (1/s), w(3, :) the spin W23, W13, W12 (1/s); the state's
    !! tau and alpha (6, n) in the same order (material_state_t%init3d).
    subroutine update3d_i(this, dt, d, w, st, i0, i1, dwp)
      import :: material_t, material_state_t, wp
      class(material_t), intent(in) :: this
      real(wp), intent(in) :: dt
      real(wp), intent(in), contiguous :: d(:, :), w(:, :)
      type(material_state_t), intent(inout) :: st
      integer, intent(in) :: i0, i1
      real(wp), intent(inout), contiguous :: dwp(:)
    end subroutine update3d_i

    !> The model's deck name (one of material_names).
    pure function model_name_i() result(name)
      character(len=:), allocatable :: name
    end function model_name_i
  end interface

  interface
    !> The model named by params%model (material_names), initialised from params after
    !! check_material_params. Implemented in material_factory_sm (it needs the extensions,
    !! which themselves use this module).
    module subroutine make_material(params, mat, err)
      type(material_params_t), intent(in) :: params
      class(material_t), allocatable, intent(out) :: mat
      type(error_t), allocatable, intent(inout) :: err
    end subroutine make_material
  end interface

contains

  !> Allocate n points, all zero (unstressed, no plastic strain).
  subroutine state_init(this, n)
    class(material_state_t), intent(inout) :: this
    integer, intent(in) :: n
    call state_alloc(this, n, ncomp)
  end subroutine state_init

  !> Allocate n points in 3D (six components a tensor), all zero.
  subroutine state_init3d(this, n)
    class(material_state_t), intent(inout) :: this
    integer, intent(in) :: n
    call state_alloc(this, n, ncomp3d)
  end subroutine state_init3d

  !> n points of nc tensor components each, all zero.
  subroutine state_alloc(this, n, nc)
    class(material_state_t), intent(inout) :: this
    integer, intent(in) :: n, nc
    if (allocated(this%tau)) deallocate(this%tau)
    if (allocated(this%alpha)) deallocate(this%alpha)
    if (allocated(this%epsbar)) deallocate(this%epsbar)
    if (allocated(this%epsdot)) deallocate(this%epsdot)
    allocate(this%tau(nc, n), this%alpha(nc, n), this%epsbar(n), this%epsdot(n))
    this%tau = 0.0_wp
    this%alpha = 0.0_wp
    this%epsbar = 0.0_wp
    this%epsdot = 0.0_wp
  end subroutine state_alloc

  !> Store rho0 (kg/m^3), E (Pa), nu and the derived G, K, lambda (Pa).
  subroutine set_elastic_constants(this, rho0, e, nu)
    class(material_t), intent(inout) :: this
    real(wp), intent(in) :: rho0, e, nu
    this%rho0 = rho0
    this%e = e
    this%nu = nu
    this%g = e/(2.0_wp*(1.0_wp + nu))
    this%k = e/(3.0_wp*(1.0_wp - 2.0_wp*nu))
    this%lambda = e*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
  end subroutine set_elastic_constants

  !> Dilatational (P) wave speed sqrt((lambda + 2G)/rho0) (m/s), for the critical time step.
  pure real(wp) function dilatational_speed(this)
    class(material_t), intent(in) :: this
    dilatational_speed = sqrt((this%lambda + 2.0_wp*this%g)/this%rho0)
  end function dilatational_speed

  !> Hughes-Winget rotation of one tensor t (11, 22, 33, 12) over a step dt (s) with spin
  !! W12 = w12 (1/s): t <- Q t Q^T, Q = (I - dt W/2)^-1 (I + dt W/2). For this W,
  !! with a = dt w12/2, Q = [c s; -s c], c = (1-a^2)/(1+a^2), s = 2a/(1+a^2): an exact
  !! rotation (by 2 atan(a)), so the invariants of t are kept to round-off; to first order
  !! it adds dt (W t - t W), the spin terms of eq. (59). t33 is unchanged.
  pure subroutine jaumann_rotate(dt, w12, t)
    real(wp), intent(in) :: dt, w12
    real(wp), intent(inout) :: t(ncomp)
    real(wp) :: a, r, c, s, cc, ss, cs, t11, t22, t12
    a = 0.5_wp*dt*w12
    r = 1.0_wp/(1.0_wp + a*a)
    c = (1.0_wp - a*a)*r
    s = 2.0_wp*a*r
    cc = c*c
    ss = s*s
    cs = c*s
    t11 = t(1)
    t22 = t(2)
    t12 = t(4)
    t(1) = cc*t11 + 2.0_wp*cs*t12 + ss*t22
    t(2) = ss*t11 - 2.0_wp*cs*t12 + cc*t22
    t(4) = cs*(t22 - t11) + (cc - ss)*t12
  end subroutine jaumann_rotate

  !> The Hughes-Winget rotation in 3D: t <- Q t Q^T with Q = (I - A)^-1 (I + A), A = dt W/2,
  !! W = [0 W12 W13; -W12 0 W23; -W13 -W23 0] from w = (W23, W13, W12) (1/s), t symmetric
  !! in the order 11, 22, 33, 23, 13, 12. Q is orthogonal (a Cayley transform), so the
  !! invariants of t are kept to round-off; with only W12 it is jaumann_rotate.
  pure subroutine jaumann_rotate_3d(dt, w, t)
    real(wp), intent(in) :: dt, w(3)
    real(wp), intent(inout) :: t(ncomp3d)
    real(wp) :: a(3, 3), m(3, 3), mi(3, 3), q(3, 3), tm(3, 3), det
    a = 0.5_wp*dt*reshape([0.0_wp, -w(3), -w(2), w(3), 0.0_wp, -w(1), w(2), w(1), &
      0.0_wp], [3, 3])
    m = -a
    m(1, 1) = m(1, 1) + 1.0_wp
    m(2, 2) = m(2, 2) + 1.0_wp
    m(3, 3) = m(3, 3) + 1.0_wp
    ! (I - A)^-1 by cofactors
    mi(1, 1) = m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)
    mi(1, 2) = m(1, 3)*m(3, 2) - m(1, 2)*m(3, 3)
    mi(1, 3) = m(1, 2)*m(2, 3) - m(1, 3)*m(2, 2)
    mi(2, 1) = m(2, 3)*m(3, 1) - m(2, 1)*m(3, 3)
    mi(2, 2) = m(1, 1)*m(3, 3) - m(1, 3)*m(3, 1)
    mi(2, 3) = m(1, 3)*m(2, 1) - m(1, 1)*m(2, 3)
    mi(3, 1) = m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1)
    mi(3, 2) = m(1, 2)*m(3, 1) - m(1, 1)*m(3, 2)
    mi(3, 3) = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
    det = m(1, 1)*mi(1, 1) + m(1, 2)*mi(2, 1) + m(1, 3)*mi(3, 1)
    m = a
    m(1, 1) = m(1, 1) + 1.0_wp
    m(2, 2) = m(2, 2) + 1.0_wp
    m(3, 3) = m(3, 3) + 1.0_wp
    q = matmul(mi, m)/det
    tm = reshape([t(1), t(6), t(5), t(6), t(2), t(4), t(5), t(4), t(3)], [3, 3])
    tm = matmul(q, matmul(tm, transpose(q)))
    t = [tm(1, 1), tm(2, 2), tm(3, 3), 0.5_wp*(tm(2, 3) + tm(3, 2)), &
      0.5_wp*(tm(1, 3) + tm(3, 1)), 0.5_wp*(tm(1, 2) + tm(2, 1))]
  end subroutine jaumann_rotate_3d

  !> elastic_rate in 3D: r = lambda tr(d) 1 + 2 G d, six components (11, 22, 33, 23, 13,
  !! 12; tensor shear components).
  pure subroutine elastic_rate_3d(lambda, g, d, r)
    real(wp), intent(in) :: lambda, g, d(ncomp3d)
    real(wp), intent(out) :: r(ncomp3d)
    real(wp) :: ltr
    ltr = lambda*(d(1) + d(2) + d(3))
    r(1:3) = ltr + 2.0_wp*g*d(1:3)
    r(4:6) = 2.0_wp*g*d(4:6)
  end subroutine elastic_rate_3d

  !> Isotropic elastic rate r = C : d = lambda tr(d) 1 + 2 G d (Pa/s for d in 1/s).
  pure subroutine elastic_rate(lambda, g, d, r)
    real(wp), intent(in) :: lambda, g, d(ncomp)
    real(wp), intent(out) :: r(ncomp)
    real(wp) :: ltr
    ltr = lambda*(d(1) + d(2) + d(3))
    r(1) = ltr + 2.0_wp*g*d(1)
    r(2) = ltr + 2.0_wp*g*d(2)
    r(3) = ltr + 2.0_wp*g*d(3)
    r(4) = 2.0_wp*g*d(4)
  end subroutine elastic_rate

  !> Range checks of the parameters params%model uses; err names the variable, its value
  !! and the fix. Messages start with 'material' so a caller can prefix the deck path.
  subroutine check_material_params(params, err)
    type(material_params_t), intent(in) :: params
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: model
    model = trim(adjustl(lower(params%model)))
    if (.not. any(material_names == model)) then
      call set_error(err, "material: variable model = '"//trim(params%model)// &
        "' is not a material model; use one of: "//join_names(material_names))
      return
    end if
    if (.not. (params%density > 0.0_wp)) then
      call bad('density', params%density, 'must be > 0 (kg/m^3; steel: 7800)')
    else if (.not. (params%youngs_modulus > 0.0_wp)) then
      call bad('youngs_modulus', params%youngs_modulus, &
        'must be > 0 (Pa, not MPa; the paper''s steel: 211e9)')
    else if (.not. (params%poisson_ratio > -1.0_wp .and. params%poisson_ratio < 0.5_wp)) then
      call bad('poisson_ratio', params%poisson_ratio, &
        'must satisfy -1 < nu < 0.5 (0.5 is incompressible, which an explicit code cannot '// &
        'carry); steel: 0.3')
    end if
    if (allocated(err)) return
    select case (model)
    case ('j2_plastic')
      if (.not. (params%yield_stress > 0.0_wp)) then
        call bad('yield_stress', params%yield_stress, 'must be > 0 (Pa; steel: 460e6)')
      else if (.not. (params%hardening_modulus >= 0.0_wp)) then
        call bad('hardening_modulus', params%hardening_modulus, &
          'must be >= 0 (Pa; 0 is perfect plasticity)')
      end if
    case ('viscoplastic')
      if (.not. (params%sigma0 > 0.0_wp)) then
        call bad('sigma0', params%sigma0, 'must be > 0 (Pa, eq. (80); steel: 460e6)')
      else if (.not. (params%hardening_n >= 0.0_wp)) then
        call bad('hardening_n', params%hardening_n, 'must be >= 0 (eq. (80); steel: 0.1)')
      else if (.not. (params%rate_m > 0.0_wp)) then
        call bad('rate_m', params%rate_m, &
          'must be > 0 (rate sensitivity of eq. (79); steel: 0.01)')
      else if (.not. (params%eps0 > 0.0_wp)) then
        call bad('eps0', params%eps0, 'must be > 0 (eq. (80); steel: sigma0/E = 2.18e-3)')
      else if (.not. (params%eps1 > 0.0_wp)) then
        call bad('eps1', params%eps1, 'must be > 0 (eq. (80); steel: 100 eps0 = 0.218)')
      else if (.not. (params%epsdot0 > 0.0_wp)) then
        call bad('epsdot0', params%epsdot0, 'must be > 0 (1/s, eq. (79); steel: 0.0021)')
      else if (.not. (params%back_stress_b >= 0.0_wp)) then
        call bad('back_stress_b', params%back_stress_b, &
          'must be >= 0 (Pa, eq. (81); 0 for no kinematic hardening)')
      else if (.not. (params%theta >= 0.0_wp .and. params%theta <= 1.0_wp)) then
        call bad('theta', params%theta, &
          'must be in [0, 1] (eq. (86); 0.5 is the default, 1 the most stable)')
      end if
    end select

  contains

    subroutine bad(name, value, fix)
      character(len=*), intent(in) :: name, fix
      real(wp), intent(in) :: value
      call set_error(err, 'material ('//model//'): variable '//name//' = '//rtoa(value)// &
        ' '//fix)
    end subroutine bad
  end subroutine check_material_params

  !> Does model use constant k of material_constant_names? elastic: rho, E, nu;
  !! j2_plastic: those and yield_stress, hardening_modulus; viscoplastic: those of eqs.
  !! (79)-(81) and (86) (rho, E, nu, sigma0, N, m, eps0, eps1, epsdot0, b, theta).
  pure logical function model_uses(model, k)
    character(len=*), intent(in) :: model
    integer, intent(in) :: k
    select case (trim(model))
    case ('elastic')
      model_uses = k <= 3
    case ('j2_plastic')
      model_uses = k <= 3 .or. k >= 12
    case ('viscoplastic')
      model_uses = k <= 11
    case default
      model_uses = .false.
    end select
  end function model_uses

  !> May constant k take material_params_t's value when a deck leaves it out? Only the
  !! back stress modulus b (0: no kinematic hardening, Table 1 gives none) and theta (the
  !! integration parameter of eq. 86, 0.5: the paper's). Every physical constant of the
  !! model is given, or comes from a preset the deck names.
  pure logical function model_default(k)
    integer, intent(in) :: k
    model_default = k == 10 .or. k == 11
  end function model_default

  !> Constant k (material_constant_names) of p.
  pure real(wp) function material_constant(p, k) result(v)
    type(material_params_t), intent(in) :: p
    integer, intent(in) :: k
    select case (k)
    case (1)
      v = p%density
    case (2)
      v = p%youngs_modulus
    case (3)
      v = p%poisson_ratio
    case (4)
      v = p%sigma0
    case (5)
      v = p%hardening_n
    case (6)
      v = p%rate_m
    case (7)
      v = p%eps0
    case (8)
      v = p%eps1
    case (9)
      v = p%epsdot0
    case (10)
      v = p%back_stress_b
    case (11)
      v = p%theta
    case (12)
      v = p%yield_stress
    case default
      v = p%hardening_modulus
    end select
  end function material_constant

  !> Set constant k (material_constant_names) of p to v.
  pure subroutine set_material_constant(p, k, v)
    type(material_params_t), intent(inout) :: p
    integer, intent(in) :: k
    real(wp), intent(in) :: v
    select case (k)
    case (1)
      p%density = v
    case (2)
      p%youngs_modulus = v
    case (3)
      p%poisson_ratio = v
    case (4)
      p%sigma0 = v
    case (5)
      p%hardening_n = v
    case (6)
      p%rate_m = v
    case (7)
      p%eps0 = v
    case (8)
      p%eps1 = v
    case (9)
      p%epsdot0 = v
    case (10)
      p%back_stress_b = v
    case (11)
      p%theta = v
    case (12)
      p%yield_stress = v
    case default
      p%hardening_modulus = v
    end select
  end subroutine set_material_constant

end module material_m
