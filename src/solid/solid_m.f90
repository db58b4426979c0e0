!> A deformable solid in the explicit total-Lagrangian scheme, whatever its discretization:
!! the state and the central-difference steps of eqs. (62)-(64), with the row-sum lumped
!! mass (70),
!!   u_{n+1} = u_n + dt v_n + dt^2/2 a_n                      (64)  solid_predict
!!   a_{n+1} = M^-1 (f_ext - f_int(u_{n+1}))                  (62)  solid_internal_force
!!   v_{n+1} = v_n + dt/2 (a_n + a_{n+1})                     (63)  solid_update
!! and the hooks contact uses between (64) and (62): the nodes' physical points at the start
!! of the step and at the prediction, the spreading of point forces onto the nodal
!! coefficients (eq. 98 for RK particles, the identity of eq. 99 for element nodes), and the
!! corrected a_n and prediction.
!!
!! The solid sees its discretization only through solid_tables_t: RKPM (rkpm_tl_m) and CST4
!! elements (cst4_m) fill the same tables (point-to-node gradients, hoop terms, weights,
!! lumped masses, position table), so one code path serves both; what differs between
!! them is data (the position table is the identity for elements), not behaviour. Linear
!! tetrahedra (tet4_m) add one step, flagged in their tables: the averaged nodal pressure
!! (anp_average).
!! Kinematic conditions arrive as masks (pres) and values (vpres) per node component.
module solid_m
  use omp_lib, only: omp_get_wtime
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use material_m, only: material_t, material_state_t, material_params_t, make_material
  use dims_m, only: dims_plane, dims_3d, max_dim
  use exact_sum_m, only: exact_sum_t, exact_add
  use sorting_m, only: sorted_place
  use solid_tables_m, only: solid_tables_t, tables_move
  use tl_kinematics_m, only: f_identity, deformation_gradient, rate_of_deformation, piola_stress, &
    internal_force, physical_positions, jacobian, deformation_gradient_list, &
    rate_of_deformation_list, piola_stress_list, internal_force_list
  use tl_kinematics3d_m, only: f_identity_3d, stretch2_min_3d
  implicit none
  private
  public :: solid_t, solid_sub_t, solid_part_t, solid_state_t, solid_options_t, &
    solid_accounts_t, solid_init, solid_start, solid_predict, solid_internal_force, solid_update
  public :: solid_kinetic_energy, solid_positions, solid_point_position, solid_body_sums, &
    solid_account_sums, solid_sums_size
  public :: solid_set_gravity, solid_add_spin, solid_bc_reactions
  public :: solid_clear_contact, solid_add_point_forces, solid_correct, solid_quiet_init, &
    solid_quiet_blocks
  public :: at_step_start, at_prediction, solid_step_estimate, solid_worst_node, &
    solid_node_number, solid_point_number, solid_np_whole, solid_nq_whole, solid_node_place
  public :: health_ok, health_j, health_stress, health_epsbar, health_deps, health_names
  public :: solid_set_owned, solid_points_force, solid_nodes_force, part_halo_t, &
    solid_share_corrections
  public :: state_field_t, state_fields, solid_field_rows, solid_get_field, &
    solid_put_field, solid_state_derived, solid_energies, solid_set_energies
  public :: solid_sub_levels, solid_sub_select, solid_sub_begin, &
    solid_rate_predict, solid_rates_force, solid_rates_update, solid_sub_end

  !> point_health codes: what is wrong at an integration point
  integer, parameter :: health_ok = 0, health_j = 1, health_stress = 2, health_epsbar = 3, &
    health_deps = 4
  character(len=*), parameter :: health_names(4) = [character(len=40) :: &
    'J outside its bounds', 'non-finite stress', 'effective plastic strain above its limit', &
    'plastic strain increment above its limit']

  integer, parameter :: at_step_start = 1   !< solid_positions gives x at the start of the step
  !> solid_positions gives x at the (corrected) prediction
  integer, parameter :: at_prediction = 2


  !> Material points are updated in blocks of this many (dynamic scheduling over blocks).
  integer, parameter :: material_block = 256

  !> Averaged nodal pressure: the share of a tetrahedron's own volume change in the volume
  !! its material sees, J_mix = J_bar^(1 - anp_own) J^anp_own (anp_average). With none, a
  !! tetrahedron's volume may leave its nodes' mean at no volumetric cost (the nodal means,
  !! one per node, leave about five of the six volumes per node free), resisted only by the
  !! deviatoric stiffness of its isochoric part, which plastic flow at the saturated flow
  !! stress takes away: in the Taylor bar's foot single tetrahedra then fall to J = 0.08
  !! with their nodes' J near 1 and the critical step with them. The share puts a bulk
  !! modulus anp_own K (0.9 GPa for steel, twice its initial yield stress) on the difference
  !! ln J - ln J_bar: weak against the plastic flow (the thick cylinder's limit pressure
  !! moves by +0.1%), but no free mode.
  real(wp), parameter, public :: anp_own = 0.005_wp

  !> A field of a solid's step state: what the reference configuration does not fix and a
  !! step changes. state_fields is the one list of them, through which checkpoints
  !! (run_checkpoint_m), the parts of a run restarted on ranks and the gathers to rank 0
  !! (mpi_domain_m) go, so none of them lists the fields again. name: the checkpoint's
  !! dataset; nodal: on nodes (else integration points); snapshot: gathered for snapshots
  !! and measures too (else for checkpoints only); what: the checkpoint's description.
  type :: state_field_t
    character(len=16) :: name
    character(len=8) :: unit
    logical :: nodal
    logical :: snapshot
    character(len=128) :: what
  end type state_field_t

  type(state_field_t), parameter :: state_fields(14) = [ &
    state_field_t('d', 'm', .true., .true., 'nodal coefficients of the displacement'), &
    state_field_t('v', 'm/s', .true., .true., 'nodal coefficients of the velocity'), &
    state_field_t('a', 'm/s^2', .true., .false., 'nodal coefficients of the acceleration'), &
    state_field_t('freac', 'N', .true., .false., 'reactions of the kinematic conditions'), &
    state_field_t('contact_impulse', 'N s', .true., .true., 'contact impulse on the '// &
      'physical points since the last snapshot'), &
    state_field_t('F', '1', .false., .true., 'deformation gradient (plane: 11, 12, 21, '// &
      '22, 33; 3D: 11, 12, 13, 21, .., 33)'), &
    state_field_t('P', 'Pa', .false., .false., 'first Piola-Kirchhoff stress (as F)'), &
    state_field_t('tau', 'Pa', .false., .true., 'Kirchhoff stress (plane: 11, 22, 33, 12; '// &
      '3D: 11, 22, 33, 23, 13, 12)'), &
    state_field_t('alpha', 'Pa', .false., .false., 'back stress (as tau)'), &
    state_field_t('epsbar', '1', .false., .true., 'effective plastic strain'), &
    state_field_t('epsdot', '1/s', .false., .false., 'effective plastic strain rate of '// &
      'the last step'), &
    state_field_t('work_points', 'J', .false., .false., 'internal and plastic work at each '// &
      'point since t = 0 (J/m in plane strain)'), &
    state_field_t('work_nodes', 'J', .true., .false., 'work of the kinematic conditions, '// &
      'of contact and of the body force at each node since t = 0, and its kinetic energy '// &
      'at t = 0'), &
    state_field_t('estab', 'J', .false., .false., 'stabilization energy at each point, '// &
      'of the last force evaluation (J/m in plane strain)')]

  !> A rank's part of a solid and its neighbour ranks (distributed memory, doc/parallel.md):
  !! the ghost entries of local arrays from their owners. The MPI build implements it
  !! (mpi_domain_m); a serial solid has none.
  type, abstract :: part_halo_t
  contains
    !> x(:, local nodes): the ghost nodes' columns from their owners.
    procedure(halo_array_i), deferred :: nodes
    !> x and y (2, local nodes): the ghost nodes' columns from their owners, one exchange.
    procedure(halo_pair_i), deferred :: nodes2
    !> x(:, local points): the ghost points' columns from their owners.
    procedure(halo_array_i), deferred :: points
  end type part_halo_t

  abstract interface
    subroutine halo_array_i(h, x)
      import :: part_halo_t, wp
      class(part_halo_t), intent(inout) :: h
      real(wp), intent(inout) :: x(:, :)
    end subroutine halo_array_i
    subroutine halo_pair_i(h, x, y)
      import :: part_halo_t, wp
      class(part_halo_t), intent(inout) :: h
      real(wp), intent(inout) :: x(:, :), y(:, :)
    end subroutine halo_pair_i
  end interface

  !> Subcycling (&solver subcycle; the step and its rules in subcycle_m): a step dt of
  !! levels L takes each node over 2^r sub-steps dt/2^r, its rate r (0..L), and evaluates
  !! each point at the rate of its fastest node.
  type :: solid_sub_t
    logical :: on = .false.                      !< this solid may subcycle (element meshes)
    integer :: levels = 0                        !< L of this step (0: a plain step)
    integer :: rate = -1                         !< the rate whose nodes move now (-1: all)
    real(wp) :: dt = 0.0_wp                      !< the step dt (s)
    integer, allocatable :: node_rate(:), point_rate(:)   !< (np), (nq)
    !> nodes and points by rate (CSR over rates 0..L), and for each point rate p the nodes
    !! of lower rate its points touch (iface), which it needs between their steps' ends
    integer, allocatable :: nptr(:), nlist(:), qptr(:), qlist(:), iptr(:), ilist(:)
    integer, allocatable :: lev_node(:), lev_point(:), mark(:)   !< work space
    real(wp), allocatable :: d_end(:, :)         !< d at the end of each node's current step
  end type solid_sub_t

  !> Distributed memory (decomposition_m, halo_m, doc/parallel.md): the solid is a rank's
  !! part on its local tables. It evaluates its own points and updates its own nodes (and
  !! sums their energies); the ghosts' values come from their owners by halo exchange
  !! between solid_points_force and solid_nodes_force (P of the ghost points) and after
  !! solid_update (d, v, a of the ghost nodes). Predictions run on every local node: a
  !! ghost node's, from its owner's v and a, is its owner's to the bit.
  type :: solid_part_t
    logical :: on = .false.                      !< a rank's part (else the whole solid)
    !> the set-up's shell of a rank's region of the solid (mfcd_mpi, before the split):
    !! its nodes and points are the whole solid's nglob and qglob (ascending), np_whole
    !! and nq_whole the whole counts; no array over the whole solid (doc/parallel.md)
    logical :: region = .false.
    integer, allocatable :: own_q(:), own_n(:)   !< owned points, owned nodes (local numbers)
    integer, allocatable :: nglob(:)             !< the local nodes' numbers in the whole solid
    integer, allocatable :: qglob(:)             !< the local points' numbers in the whole solid
    integer :: np_whole = 0, nq_whole = 0        !< the whole solid's nodes and points
    !> the part's exchanges with the neighbour ranks (none for a serial solid)
    class(part_halo_t), pointer :: halo => null()
  end type solid_part_t

  !> What a step changes: the nodal coefficients of eqs. (65)-(67), the reactions of the
  !! kinematic conditions, the contact impulse since the last snapshot, F and P (eq. 62) and
  !! the material's state. The fields a restart needs are state_fields (solid_get_field,
  !! solid_put_field); the rest follows from them (solid_state_derived).
  type :: solid_state_t
    real(wp), allocatable :: d(:, :), v(:, :), a(:, :)   !< (ndim, np) (m, m/s, m/s^2)
    real(wp), allocatable :: d_old(:, :)         !< d at the start of the step
    real(wp), allocatable :: a_old(:, :)         !< a_n during the step
    real(wp), allocatable :: freac(:, :), freac_old(:, :)  !< reactions (ndim, np) (N)
    !> the contact forces' impulse on the physical points since the last snapshot (N s),
    !! 1/2 dt fpoint per step as the history's f_contact (eq. 63), and the time it covers
    !! (s): /snapshots f_contact = impulse / time
    real(wp), allocatable :: ipoint(:, :)
    real(wp) :: ipoint_time = 0.0_wp
    real(wp), allocatable :: f(:, :), f_old(:, :)        !< F (nf, nq)
    real(wp), allocatable :: p(:, :), p_old(:, :)        !< first Piola-Kirchhoff (nf, nq) (Pa)
    type(material_state_t) :: st                 !< stresses, back stress, epsbar, its rate
    !> the energy accounts entry by entry (J, J/m in plane strain): at each point its
    !! internal and plastic work since t = 0 (2, nq); at each node the work of the
    !! kinematic conditions, of the contact forces and of the body force since t = 0 and its
    !! kinetic energy at t = 0 (4, np). The run's accounts are their exact sums
    !! (solid_account_sums): the same bits whatever the split among ranks or threads.
    real(wp), allocatable :: work_q(:, :), work_n(:, :)
  end type solid_state_t

  !> Options of a solid, set once by the run's set-up: the SCNI stabilization and the local
  !! health limits (run_health_m).
  type :: solid_options_t
    real(wp) :: stab_normal = 0.0_wp, stab_shear = 0.0_wp  !< alpha (lambda + 2 mu), alpha mu
    real(wp) :: v_limit = huge(1.0_wp)           !< node speed limit (m/s)
    real(wp) :: epsbar_limit = huge(1.0_wp)      !< effective plastic strain limit (-)
    real(wp) :: deps_limit = huge(1.0_wp)        !< its increment in one step (-)
    real(wp) :: j_bounds(2) = [0.0_wp, huge(1.0_wp)]   !< J must stay inside (-)
    real(wp) :: gravity(max_dim) = 0.0_wp        !< body force per unit mass (m/s^2)
  end type solid_options_t

  !> What a solid has received and spent since t = 0: the energy accounts (J, or J/m in
  !! plane strain; solid_energies packs them for checkpoints), and the work done.
  type :: solid_accounts_t
    real(wp) :: ke0 = 0.0_wp, ke = 0.0_wp, w_int = 0.0_wp, w_plastic = 0.0_wp, w_bc = 0.0_wp
    real(wp) :: w_ext = 0.0_wp, w_contact = 0.0_wp
    real(wp) :: e_stab = 0.0_wp                  !< stabilization energy
    real(wp) :: wall(3) = 0.0_wp                 !< seconds in kinematics, material, forces
    integer(i64) :: quiet_skipped = 0            !< quiet point-steps skipped
  end type solid_accounts_t

  type :: solid_t
    character(len=64) :: name = ''
    real(wp) :: spacing = 0.0_wp                 !< nominal node spacing (m), for measures
    integer :: np = 0                            !< nodes (RK particles or element nodes)
    integer :: nq = 0                            !< integration points
    type(solid_tables_t) :: t
    class(material_t), allocatable :: mat
    !> the parameters the material was made from (a rank's part of the solid makes its own)
    type(material_params_t) :: mat_params
    real(wp), allocatable :: x0(:, :)            !< reference positions (ndim, np) (m)
    type(solid_state_t) :: state                 !< what a step changes
    type(solid_options_t) :: opt                 !< set once by the run's set-up
    type(solid_accounts_t) :: acc                !< energies and work since t = 0
    logical, allocatable :: pres(:, :)           !< prescribed velocity component (ndim, np)
    real(wp), allocatable :: vpres(:, :)         !< its value (m/s)
    ! work space of a step, recomputed from the state
    real(wp), allocatable :: fint(:, :), fext(:, :)      !< (ndim, np) (N)
    !> the deck's &bc group that prescribes each component (ndim, np), 0 for none (or the
    !! symmetry axis): whose reaction force it is (solid_bc_reactions)
    integer, allocatable :: bc_of(:, :)
    real(wp), allocatable :: fcon(:, :)          !< contact forces on the coefficients (N)
    !> contact forces at the nodes' physical points this step, before eq. (98) spreads them
    !! (action and reaction of every pass; N)
    real(wp), allocatable :: fpoint(:, :)
    real(wp), allocatable :: x(:, :)             !< physical positions (ndim, np) (m)
    !> D (ncomp, nq), the spin (W12 (1, nq) in the plane, W23, W13, W12 (3, nq) in 3D), the
    !! plastic work of the step (nq)
    real(wp), allocatable :: dr(:, :), spin(:, :), dwp(:)
    real(wp), allocatable :: stab(:, :)          !< stabilization stresses (nstab, nq)
    real(wp), allocatable :: estab(:)            !< their energy at each point (nq) (J, J/m)
    !> averaged nodal pressure (tables flagged anp: linear tetrahedra, anp_average): J and
    !! J_bar of each point (2, nq), each node's volume-weighted J (1, np), the material's
    !! F_bar (nf, nq) now and at the point's last evaluation, and the Kirchhoff stress
    !! whose pressure is carried by the point's own volume (ncomp, nq), which P takes
    real(wp), allocatable :: jq(:, :), jn(:, :), fbar(:, :), fbar_old(:, :), taup(:, :)
    ! the critical-step estimate that follows the deformation (solid_step_estimate)
    real(wp), allocatable :: kap0(:)             !< kappa0_L of each point (1/m^2), step_metric
    real(wp) :: kappa0 = 0.0_wp                  !< largest kappa in the reference state (1/m^2)
    real(wp) :: kappa = 0.0_wp                   !< largest kappa at the current state (1/m^2)
    integer :: kappa_q = 0                       !< the point where it is
    !> its number in the whole solid, and on ranks the run's (the largest over the ranks,
    !! the lowest number among equals: the serial point; explicit_driver_m kappa_max)
    integer :: kappa_g = 0
    real(wp) :: dt_cal = 0.0_wp                  !< 2/omega_max(0) sqrt(kappa0) (s/m)
    integer :: bad_code = 0                      !< point_health code of the failed point
    ! quiet points (&solver skip_quiet): a point all of whose nodes still move in the
    ! body's initial uniform translation has F = I and no stress; it skips F, the material
    ! update and its share of the internal force until a disturbance (a kinematic
    ! condition, a contact force, an active neighbour's force) reaches one of its nodes
    logical :: quiet_on = .false.                !< skipping (all_awake turns it off)
    logical :: all_awake = .true.                !< every point is active: no mask
    logical, allocatable :: awake(:)             !< node disturbed (np)
    logical, allocatable :: qact(:)              !< point active (nq)
    logical, allocatable :: bact(:)              !< material block with an active point
    !> subcycling (&solver subcycle): solid_sub_t
    type(solid_sub_t) :: sub
    !> distributed memory: solid_part_t
    type(solid_part_t) :: part
  end type solid_t

contains

  !> A solid on the tables t (moved in: t is deallocated on return) with the material of
  !! params, the SCNI stabilization coefficient alpha (0: none; meaningful for RKPM tables
  !! only), the initial velocity v0 (ndim) (m/s) and the kinematic conditions pres/vpres
  !! (ndim, np). Components on the symmetry axis (t%fix1) are held at zero in addition.
  !! The shapes of the state are those of the tables' geometry (t%dims).
  !! shell: the whole solid of a decomposed set-up, which only the split reads (mpi_domain_m
  !! make_part: reference positions, kinematic conditions, velocities, tables, material,
  !! options): no state beyond the velocities, no work arrays, no stiffness measures, so
  !! that no rank holds the whole body's state (it makes its part's at the split).
  subroutine solid_init(s, name, t, x0, params, alpha, v0, pres, vpres, err, shell)
    type(solid_t), intent(out) :: s
    character(len=*), intent(in) :: name
    type(solid_tables_t), intent(inout) :: t
    real(wp), intent(in) :: x0(:, :)
    type(material_params_t), intent(in) :: params
    real(wp), intent(in) :: alpha, v0(:)
    logical, intent(in) :: pres(:, :)
    real(wp), intent(in) :: vpres(:, :)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: shell
    integer :: i, np, nq, nd, nf, nc
    logical :: plane, space, whole
    whole = .true.
    if (present(shell)) whole = .not. shell
    plane = t%dims%ndim == dims_plane%ndim .and. t%dims%nf == dims_plane%nf .and. &
      t%dims%ncomp == dims_plane%ncomp
    space = t%dims%ndim == dims_3d%ndim .and. t%dims%nf == dims_3d%nf .and. &
      t%dims%ncomp == dims_3d%ncomp
    if (.not. (plane .or. space)) then
      call set_error(err, "solid '"//trim(name)//"': no kernels for tables of dimension "// &
        itoa(t%dims%ndim)//' (this build has the plane kernels, plane strain and '// &
        'axisymmetry, and the 3D kernels)')
      return
    end if
    call make_material(params, s%mat, err)
    if (allocated(err)) return
    s%mat_params = params
    s%name = name
    call tables_move(t, s%t)
    np = s%t%np
    nq = s%t%nq
    nd = s%t%dims%ndim
    nf = s%t%dims%nf
    nc = s%t%dims%ncomp
    s%np = np
    s%nq = nq
    s%opt%stab_normal = alpha*(s%mat%lambda + 2.0_wp*s%mat%g)
    s%opt%stab_shear = alpha*s%mat%g
    if (.not. whole) then
      s%x0 = x0
      allocate(s%state%v(nd, np))
      do i = 1, np
        s%state%v(:, i) = v0
      end do
      call solid_conditions(s, pres, vpres)
      s%acc%ke0 = solid_kinetic_energy(s)
      s%acc%ke = s%acc%ke0
      return
    end if
    allocate(s%stab(s%t%dims%nstab, nq), s%estab(nq), s%state%work_q(2, nq), &
      s%state%work_n(4, np))
    s%stab = 0.0_wp
    s%estab = 0.0_wp
    s%state%work_q = 0.0_wp
    s%state%work_n = 0.0_wp
    if (space) then
      call s%state%st%init3d(nq)
    else
      call s%state%st%init(nq)
    end if
    s%x0 = x0
    s%x = x0
    allocate(s%state%d(nd, np), s%state%v(nd, np), s%state%a(nd, np), &
      s%state%d_old(nd, np), s%state%a_old(nd, np), s%state%freac(nd, np), &
      s%state%freac_old(nd, np), s%state%ipoint(nd, np), s%fint(nd, np), s%fext(nd, np), &
      s%fcon(nd, np), s%fpoint(nd, np))
    s%state%d = 0.0_wp
    s%state%d_old = 0.0_wp
    s%state%a = 0.0_wp
    s%state%a_old = 0.0_wp
    s%fint = 0.0_wp
    s%fext = 0.0_wp
    s%fcon = 0.0_wp
    s%fpoint = 0.0_wp
    s%state%ipoint = 0.0_wp
    s%state%freac = 0.0_wp
    s%state%freac_old = 0.0_wp
    do i = 1, np
      s%state%v(:, i) = v0
    end do
    call solid_conditions(s, pres, vpres)
    allocate(s%state%f(nf, nq), s%state%f_old(nf, nq), s%state%p(nf, nq), &
      s%state%p_old(nf, nq), s%dr(nc, nq), s%spin(merge(3, 1, space), nq), s%dwp(nq))
    do i = 1, nq
      if (space) then
        s%state%f(:, i) = f_identity_3d
      else
        s%state%f(:, i) = f_identity
      end if
    end do
    s%state%f_old = s%state%f
    s%state%p = 0.0_wp
    s%state%p_old = 0.0_wp
    if (s%t%anp) then
      allocate(s%jq(2, nq), s%jn(1, np), s%fbar(nf, nq), s%fbar_old(nf, nq), s%taup(nc, nq))
      s%jq = 1.0_wp
      s%jn = 1.0_wp
      s%fbar = s%state%f
      s%fbar_old = s%state%f
      s%taup = 0.0_wp
    end if
    s%dr = 0.0_wp
    s%spin = 0.0_wp
    s%dwp = 0.0_wp
    s%acc%ke0 = solid_kinetic_energy(s)
    s%acc%ke = s%acc%ke0
    call step_metric(s)
  end subroutine solid_init

  !> The kinematic conditions pres/vpres of solid s, with the components on the symmetry
  !! axis (t%fix1) held at zero, and its velocities where they are prescribed.
  subroutine solid_conditions(s, pres, vpres)
    type(solid_t), intent(inout) :: s
    logical, intent(in) :: pres(:, :)
    real(wp), intent(in) :: vpres(:, :)
    s%pres = pres
    s%vpres = vpres
    s%pres(1, :) = s%pres(1, :) .or. s%t%fix1
    where (s%t%fix1) s%vpres(1, :) = 0.0_wp
    where (s%pres) s%state%v = s%vpres
  end subroutine solid_conditions

  !> The reference stiffness measure of each integration point L for the time-step
  !! estimate: with the reference gradients g of the shape functions touching L (both
  !! components) and the hoop terms h,
  !!   kappa0_L = sum_I (|grad N^1_I|^2 + |grad N^2_I|^2 + h_I^2)   (1/m^2),
  !! the square of an inverse length of the point's cell or element. The current gradients
  !! are F^-T grad N and the current hoop terms h/F33, so at the deformation F of point L
  !!   kappa_L(F) = kappa0_L / s_min(F)^2 >= sum_I (|F^-T grad N_I|^2 + h_I^2/F33^2),
  !! s_min the smallest principal stretch (in-plane singular values of F, and F33): the
  !! critical step of the body scales like 1/sqrt(max_L kappa_L). The bound rather than the
  !! exact sum: measured against the power iteration on bodies built in the deformed shape
  !! (tests/unit/solid/test_stable_step.pf), the exact sum overestimates the step by 15-37% on
  !! anisotropic compressions (the highest mode follows the shortest direction, not the
  !! sum of the directions); the bound is 8-12% below it, never above (doc/solver.md).
  subroutine step_metric(s)
    type(solid_t), intent(inout) :: s
    integer :: q, e
    allocate(s%kap0(s%nq))
    s%kap0 = 0.0_wp
    do q = 1, s%nq
      do e = s%t%ptr(q), s%t%ptr(q + 1) - 1
        s%kap0(q) = s%kap0(q) + sum(s%t%g(:, e)**2)
        if (s%t%axisym) s%kap0(q) = s%kap0(q) + s%t%h(e)**2
      end do
    end do
    s%kappa0 = 0.0_wp
    s%kappa_q = 0
    if (s%nq > 0) then
      s%kappa_q = maxloc(s%kap0, 1)
      s%kappa0 = s%kap0(s%kappa_q)
    end if
    s%kappa_g = s%kappa_q
    s%kappa = s%kappa0
  end subroutine step_metric

  !> Start skipping quiet points (&solver skip_quiet): the nodes disturbed from the start
  !! are those whose prescribed velocity differs from the initial one v0; in axisymmetry a
  !! radial v0 is no rigid motion (it strains the hoop direction), so everything is active.
  subroutine solid_quiet_init(s, v0)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: v0(:)
    integer :: i
    allocate(s%awake(s%np), s%qact(s%nq), s%bact((s%nq + material_block - 1)/material_block))
    s%qact = .false.
    s%bact = .false.
    do i = 1, s%np
      s%awake(i) = any(s%pres(:, i) .and. s%vpres(:, i) /= v0)
    end do
    s%quiet_on = .not. (s%t%axisym .and. v0(1) /= 0.0_wp)
    s%all_awake = .not. s%quiet_on
    if (s%all_awake) s%awake = .true.
    if (s%all_awake) s%qact = .true.
  end subroutine solid_quiet_init

  !> Which points are active this step (quiet points skip): nodes with a contact force wake,
  !! a point with an awake node turns active (for good), and every node of an active point
  !! wakes, so that the force gather covers all nodes an active point touches. Once every
  !! point is active the masks are dropped (all_awake).
  !! Averaged nodal pressure (t%anp): a point's volume J_bar averages the J of every point
  !! that shares a node with it, so a point beside an active one has a pressure although its
  !! own F is still I. Its force must be gathered at all of its nodes (a force gathered at
  !! some of them only is not in equilibrium: the momentum drifted by 1.4e-4 of the Taylor
  !! bar's), so the activation and the waking are done twice: the second ring of points
  !! is active too, and the disturbance spreads by the two rings a step that the nodal
  !! average couples.
  subroutine quiet_update(s)
    type(solid_t), intent(inout) :: s
    integer :: q, e, nact, pass
    !$omp parallel do default(none) shared(s) schedule(static)
    do q = 1, s%np
      if (any(s%fcon(:, q) /= 0.0_wp)) s%awake(q) = .true.
    end do
    !$omp end parallel do
    do pass = 1, merge(2, 1, s%t%anp)
      nact = 0
      !$omp parallel do default(none) shared(s) private(e) reduction(+: nact) &
      !$omp schedule(static)
      do q = 1, s%nq
        if (.not. s%qact(q)) then
          do e = s%t%ptr(q), s%t%ptr(q + 1) - 1
            if (s%awake(s%t%nbr(e))) then
              s%qact(q) = .true.
              exit
            end if
          end do
        end if
        if (s%qact(q)) nact = nact + 1
      end do
      !$omp end parallel do
      ! wake the nodes of the active points (serial: a node is shared by several points)
      do q = 1, s%nq
        if (.not. s%qact(q)) cycle
        do e = s%t%ptr(q), s%t%ptr(q + 1) - 1
          s%awake(s%t%nbr(e)) = .true.
        end do
      end do
    end do
    call solid_quiet_blocks(s)
    s%acc%quiet_skipped = s%acc%quiet_skipped + (s%nq - nact)
    if (nact == s%nq) then
      s%all_awake = .true.
      s%awake = .true.
    end if
  end subroutine quiet_update

  !> The material blocks that hold an active point.
  subroutine solid_quiet_blocks(s)
    type(solid_t), intent(inout) :: s
    integer :: blk
    do blk = 1, size(s%bact)
      s%bact(blk) = any(s%qact((blk - 1)*material_block + 1:min(blk*material_block, s%nq)))
    end do
  end subroutine solid_quiet_blocks

  !> The square of the smallest principal stretch of f: in the plane layout (dims_plane) the
  !! smaller eigenvalue of the in-plane C = F^T F, or F33^2 if smaller; in 3D (f of 9)
  !! the smallest eigenvalue of C (stretch2_min_3d). Here and not with the plane kernels of
  !! tl_kinematics_m because points_account calls it at every point of every step and in
  !! this module it can be inlined.
  pure real(wp) function stretch2_min(f) result(s2)
    real(wp), intent(in) :: f(:)
    real(wp) :: c11, c12, c22, tr, det, lmax
    if (size(f) == size(f_identity_3d)) then
      s2 = stretch2_min_3d(f)
      return
    end if
    c11 = f(1)**2 + f(3)**2
    c22 = f(2)**2 + f(4)**2
    c12 = f(1)*f(2) + f(3)*f(4)
    tr = c11 + c22
    det = (f(1)*f(4) - f(2)*f(3))**2
    lmax = 0.5_wp*(tr + sqrt(max((c11 - c22)**2 + 4.0_wp*c12**2, 0.0_wp)))
    s2 = min(det/lmax, f(5)**2)
  end function stretch2_min

  !> The critical step of the solid at its current state (s): dt_cal/sqrt(max_L kappa_L),
  !! with dt_cal = (2/omega_max) sqrt(max_L kappa_L) in the reference state, omega_max from
  !! the power iteration (stable_step_m). Current after solid_internal_force.
  pure real(wp) function solid_step_estimate(s) result(dt)
    type(solid_t), intent(in) :: s
    if (s%kappa > 0.0_wp .and. s%dt_cal < huge(1.0_wp)) then
      dt = s%dt_cal/sqrt(s%kappa)
    else
      dt = huge(1.0_wp)   ! no integration point or no free component: nothing limits it
    end if
  end function solid_step_estimate

  !> The tables moved component by component (no copy of the large arrays).
  !> 1/2 sum m |v|^2 (J; J/m in plane strain).
  pure real(wp) function solid_kinetic_energy(s) result(ke)
    type(solid_t), intent(in) :: s
    ke = 0.5_wp*sum(s%t%mass*sum(s%state%v**2, dim=1))
  end function solid_kinetic_energy

  !> The state at t = 0: forces and accelerations at u = 0, prescribed components at rest.
  subroutine solid_start(s, dt, bad_q, bad_j)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(out) :: bad_q
    real(wp), intent(out) :: bad_j
    call solid_internal_force(s, dt, bad_q, bad_j)
    where (s%pres)
      s%state%v = s%vpres
      s%state%a = 0.0_wp
    end where
    if (associated(s%part%halo)) call s%part%halo%nodes2(s%state%v, s%state%a)
    s%state%work_n(4, :) = 0.5_wp*s%t%mass*sum(s%state%v**2, dim=1)
  end subroutine solid_start

  !> The prediction of eq. (64); contact may correct it (solid_correct) before the forces.
  subroutine solid_predict(s, dt)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer :: i
    real(wp) :: h
    !$omp parallel do default(none) shared(s, dt) private(h) schedule(static)
    do i = 1, s%np
      ! two where statements: a where construct of two assignments kept its mask in a heap
      ! temporary, one allocation per node and step
      where (s%pres(:, i)) s%state%v(:, i) = s%vpres(:, i)
      where (s%pres(:, i)) s%state%a(:, i) = 0.0_wp
      ! subcycling: the nodes of rate above 0 wait at d_n for their sub-steps
      h = dt
      if (s%sub%rate == 0) then
        if (s%sub%node_rate(i) > 0) h = 0.0_wp
      end if
      s%state%d_old(:, i) = s%state%d(:, i)
      s%state%d(:, i) = s%state%d(:, i) + h*s%state%v(:, i) + 0.5_wp*h*h*s%state%a(:, i)   ! (64)
      s%state%a_old(:, i) = s%state%a(:, i)
      s%fcon(:, i) = 0.0_wp
      s%fpoint(:, i) = 0.0_wp
    end do
    !$omp end parallel do
  end subroutine solid_predict

  !> At the new coefficients d: F, D and W from the old F, the material update, P, the
  !! internal force and a_{n+1} = (f_ext - f_int)/m (eq. 62), with the step's internal and
  !! plastic work. a_n (as corrected by contact) is kept in a_old for eq. (63). bad_q: the
  !! last integration point with J <= 0 or a non-finite stress (0 if none), bad_j its J.
  subroutine solid_internal_force(s, dt, bad_q, bad_j)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(out) :: bad_q
    real(wp), intent(out) :: bad_j
    integer :: q, nblocks, i0, i1, blk, kq
    real(wp) :: dw, dwp, t0, t1, t2, kmax
    if (s%sub%levels > 0) then
      ! the end of a subcycled step: every rate's points and nodes
      call solid_rates_force(s, 0, 2**s%sub%levels, bad_q, bad_j)
      return
    end if
    if (s%part%on) then
      ! a rank's part: its points, the ghost points' P and stabilization stresses from
      ! their owners, its nodes
      call solid_points_force(s, dt, bad_q, bad_j)
      if (associated(s%part%halo)) then
        call s%part%halo%points(s%state%p)
        if (s%opt%stab_normal > 0.0_wp) call s%part%halo%points(s%stab)
      end if
      call solid_nodes_force(s)
      return
    end if
    t0 = omp_get_wtime()
    if (.not. s%all_awake) call quiet_update(s)
    !$omp parallel do default(none) shared(s) schedule(static)
    do q = 1, s%nq
      s%state%f_old(:, q) = s%state%f(:, q)
      s%state%p_old(:, q) = s%state%p(:, q)
    end do
    !$omp end parallel do
    if (s%t%anp) then
      !$omp parallel do default(none) shared(s) schedule(static)
      do q = 1, s%nq
        s%fbar_old(:, q) = s%fbar(:, q)
      end do
      !$omp end parallel do
    end if
    if (s%all_awake) then
      if (s%opt%stab_normal > 0.0_wp) then
        call deformation_gradient(s%t, s%state%d, s%state%f, &
          [s%opt%stab_normal, s%opt%stab_shear], s%stab, s%acc%e_stab, energy_q=s%estab)
      else
        call deformation_gradient(s%t, s%state%d, s%state%f)
      end if
    else
      ! quiet points keep F = I and zero stabilization stresses (and add no energy)
      if (s%opt%stab_normal > 0.0_wp) then
        call deformation_gradient(s%t, s%state%d, s%state%f, &
          [s%opt%stab_normal, s%opt%stab_shear], s%stab, s%acc%e_stab, active=s%qact, &
          energy_q=s%estab)
      else
        call deformation_gradient(s%t, s%state%d, s%state%f, active=s%qact)
      end if
    end if
    if (s%t%anp) then
      ! the material sees F_bar: D and W between the last F_bar and this one
      call anp_average(s)
      call rate_of_deformation(s%nq, dt, s%fbar_old, s%fbar, s%dr, s%spin)
    else
      call rate_of_deformation(s%nq, dt, s%state%f_old, s%state%f, s%dr, s%spin)
    end if
    t1 = omp_get_wtime()
    nblocks = (s%nq + material_block - 1)/material_block
    !$omp parallel do default(none) shared(s, dt, nblocks) private(i0, i1) &
    !$omp schedule(dynamic, 4)
    do blk = 1, nblocks
      if (.not. s%all_awake) then
        if (.not. s%bact(blk)) cycle   ! only quiet points: D = 0, no stress
      end if
      i0 = (blk - 1)*material_block + 1
      i1 = min(blk*material_block, s%nq)
      call material_range(s, dt, i0, i1)
    end do
    !$omp end parallel do
    t2 = omp_get_wtime()
    if (s%t%anp) then
      call anp_stress(s)
      call piola_stress(s%nq, s%state%f, s%taup, s%state%p)
    else
      call piola_stress(s%nq, s%state%f, s%state%st%tau, s%state%p)
    end if
    if (s%all_awake) then
      if (s%opt%stab_normal > 0.0_wp) then
        call internal_force(s%t, s%state%p, s%fint, s%stab)
      else
        call internal_force(s%t, s%state%p, s%fint)
      end if
    else
      if (s%opt%stab_normal > 0.0_wp) then
        call internal_force(s%t, s%state%p, s%fint, s%stab, awake=s%awake)
      else
        call internal_force(s%t, s%state%p, s%fint, awake=s%awake)
      end if
    end if
    call points_account(s, dt, bad_q, dw, dwp, kmax, kq)
    if (kq > 0) then
      s%kappa = kmax
      s%kappa_q = kq
    end if
    bad_j = 1.0_wp
    s%bad_code = health_ok
    if (bad_q > 0) then
      bad_j = jacobian(s%state%f(:, bad_q))
      s%bad_code = point_health(s, bad_q, dt)
    end if
    s%acc%w_int = s%acc%w_int + dw
    s%acc%w_plastic = s%acc%w_plastic + dwp
    !$omp parallel do default(none) shared(s) schedule(static)
    do q = 1, s%np
      s%state%a_old(:, q) = s%state%a(:, q)
      s%state%a(:, q) = (s%fext(:, q) - s%fint(:, q))/s%t%mass(q)
    end do
    !$omp end parallel do
    s%acc%wall = s%acc%wall + [t1 - t0, t2 - t1, omp_get_wtime() - t2]
  end subroutine solid_internal_force

  !> The averaged nodal pressure (Bonet and Burton 1998): at the points list(1:n) (all when
  !! list is absent), after F is computed there, the material's deformation gradient
  !!   F_bar = (J_mix/J)^(1/3) F,   J_mix = J_bar^(1 - a) J^a  (a = anp_own),
  !!   J_bar = (1/4) sum_{a in e} J_a,
  !!   J_a = sum_{e' around a} V_e' J_e' / sum_{e' around a} V_e'
  !! (J = det F of the point, J_a the volume-weighted mean over the points around node a,
  !! gathered per node over the transpose: no races). F_bar has the point's isochoric part
  !! F/J^(1/3) and the volume change of its nodes (with the small share a of its own): the
  !! deviatoric rates dev D and the spin are the point's own, the volumetric rate follows
  !! the averaged volume. A linear tetrahedron has one volume constraint per element, about 6
  !! per node against 3 degrees of freedom, and locks in isochoric (plastic) flow; with
  !! J_bar the constraints are one per node, and the share a keeps each element's volume
  !! from drifting off its nodes' at no cost (anp_own). jq(2, q) holds J_bar. A point whose
  !! J or J_bar is not positive keeps F (its J is what the health check sees).
  !! Consistency: on a linear displacement field J is uniform, so J_a = J_bar = J and
  !! F_bar = F (the patch test is untouched). With P built from anp_stress's Kirchhoff stress
  !! tau_dev + ((1 - a) J/J_bar + a) p_K I (p_K the material's Kirchhoff pressure at J_mix)
  !! and the point's own F, the force of eq. (72) is Bonet and Burton's
  !!   f_b = sum_e v_e (J_e^-1 tau_dev + p_e I) grad_x N_b,   p_e = p_K/J_bar,
  !! with the share 1 - a of the pressure, plus the plain tetrahedron's (p_e = p_K/J_e) with
  !! the share a. For a pressure linear in J, p_e = mean_{a in e} p(J_a), the first is
  !! exactly the gradient of the nodal volumetric energy sum_a V_a U(J_a) (V_a = sum V_e/4,
  !! J_a = v_a/V_a; their eq. for the nodal force), the second that of sum_e V_e U(J_e):
  !! conservative, and the internal work P : dF over the points' own F (points_account) is
  !! the work of these forces to round-off. Distributed memory: the ghost points' J and the
  !! ghost nodes' J_a come from their owners (two exchanges).
  subroutine anp_average(s, list, n)
    type(solid_t), intent(inout) :: s
    integer, intent(in), optional :: list(:), n
    integer :: k, q, i, e, nk
    real(wp) :: sw, sj, jb
    logical :: listed
    listed = present(list)
    nk = s%nq
    if (listed) nk = n
    !$omp parallel do default(none) shared(s, list, listed, nk) private(q) schedule(static)
    do k = 1, nk
      q = k
      if (listed) q = list(k)
      s%jq(1, q) = jacobian(s%state%f(:, q))
    end do
    !$omp end parallel do
    if (associated(s%part%halo)) call s%part%halo%points(s%jq)
    ! (subcycling: the points not listed keep the J of their last evaluation)
    !$omp parallel do default(none) shared(s) private(k, q, sw, sj) schedule(static)
    do i = 1, s%np
      sw = 0.0_wp
      sj = 0.0_wp
      do k = s%t%tptr(i), s%t%tptr(i + 1) - 1
        q = s%t%tq(k)
        sw = sw + s%t%wgt(q)
        sj = sj + s%t%wgt(q)*s%jq(1, q)
      end do
      s%jn(1, i) = 1.0_wp
      if (sw > 0.0_wp) s%jn(1, i) = sj/sw
    end do
    !$omp end parallel do
    if (associated(s%part%halo)) call s%part%halo%nodes(s%jn)
    !$omp parallel do default(none) shared(s, list, listed, nk) private(q, e, jb) &
    !$omp schedule(static)
    do k = 1, nk
      q = k
      if (listed) q = list(k)
      jb = 0.0_wp
      do e = s%t%ptr(q), s%t%ptr(q + 1) - 1
        jb = jb + s%jn(1, s%t%nbr(e))
      end do
      jb = jb/real(max(1, s%t%ptr(q + 1) - s%t%ptr(q)), wp)
      if (s%jq(1, q) > 0.0_wp .and. jb > 0.0_wp) then
        s%jq(2, q) = jb
        s%fbar(:, q) = (jb/s%jq(1, q))**((1.0_wp - anp_own)/3.0_wp)*s%state%f(:, q)
      else
        s%jq(2, q) = s%jq(1, q)
        s%fbar(:, q) = s%state%f(:, q)
      end if
    end do
    !$omp end parallel do
  end subroutine anp_average

  !> The Kirchhoff stress P takes at the points list(1:n) (all when absent) under the
  !! averaged nodal pressure: the material's tau (at F_bar) with its pressure carried by the
  !! point's own volume, tau_dev + ((1 - a) J/J_bar + a) (tr tau/3) I (a = anp_own: the
  !! share of the plain tetrahedron's pressure), so that P = taup F^-T with the
  !! point's own F gives Bonet and Burton's nodal force (anp_average). The normal
  !! components come first in both layouts (11, 22, 33).
  subroutine anp_stress(s, list, n)
    type(solid_t), intent(inout) :: s
    integer, intent(in), optional :: list(:), n
    integer :: k, q, nk
    real(wp) :: m
    logical :: listed
    listed = present(list)
    nk = s%nq
    if (listed) nk = n
    !$omp parallel do default(none) shared(s, list, listed, nk) private(q, m) schedule(static)
    do k = 1, nk
      q = k
      if (listed) q = list(k)
      m = (s%state%st%tau(1, q) + s%state%st%tau(2, q) + s%state%st%tau(3, q))/3.0_wp* &
        (1.0_wp - anp_own)*(s%jq(1, q)/s%jq(2, q) - 1.0_wp)
      s%taup(:, q) = s%state%st%tau(:, q)
      s%taup(1:3, q) = s%taup(1:3, q) + m
    end do
    !$omp end parallel do
  end subroutine anp_stress

  !> The material update of a step dt at the points i0..i1 from D and the spin: the plane
  !! update (W12) or the 3D one (W23, W13, W12), by the shape of the solid's spin.
  subroutine material_range(s, dt, i0, i1)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(in) :: i0, i1
    if (size(s%spin, 1) == 3) then
      call s%mat%update3d(dt, s%dr, s%spin, s%state%st, i0, i1, s%dwp)
    else
      ! (the spin's one row as a contiguous vector: spin(1, :) passed to the contiguous
      ! dummy was an array temporary at every call)
      call plane_update(s%mat, dt, s%dr, s%spin, size(s%spin, 2), s%state%st, i0, i1, s%dwp)
    end if
  end subroutine material_range

  !> The plane material update with the spin W12 of w (1, n) seen as the vector w(1:n).
  subroutine plane_update(mat, dt, d, w, n, st, i0, i1, dwp)
    class(material_t), intent(in) :: mat
    real(wp), intent(in) :: dt
    real(wp), intent(in), contiguous :: d(:, :)
    integer, intent(in) :: n, i0, i1
    real(wp), intent(in) :: w(*)
    type(material_state_t), intent(inout) :: st
    real(wp), intent(inout), contiguous :: dwp(:)
    call mat%update(dt, d, w(1:n), st, i0, i1, dwp)
  end subroutine plane_update

  !> Distributed memory: this solid owns the points own_point and the nodes own_node of its
  !! local tables (decomposition_m's local_part_t); from now on it evaluates and updates only
  !! those (see solid_t).
  subroutine solid_set_owned(s, own_point, own_node)
    type(solid_t), intent(inout) :: s
    logical, intent(in) :: own_point(:), own_node(:)
    integer :: k
    s%part%on = .true.
    s%part%own_q = pack([(k, k = 1, s%nq)], own_point)
    s%part%own_n = pack([(k, k = 1, s%np)], own_node)
  end subroutine solid_set_owned

  !> Distributed memory, the first half of eq. (62): F, the material and P at the owned
  !! points over the step dt, with their work, health and kappa (the largest over the owned
  !! points: the caller takes the largest over the ranks). The ghost points' P come next.
  subroutine solid_points_force(s, dt, bad_q, bad_j)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(out) :: bad_q
    real(wp), intent(out) :: bad_j
    integer :: kq
    real(wp) :: kmax
    call update_points(s, dt, s%part%own_q, size(s%part%own_q), bad_q, kmax, kq)
    if (kq > 0) then
      s%kappa = kmax
      s%kappa_q = kq
    end if
    bad_j = 1.0_wp
    s%bad_code = health_ok
    if (bad_q > 0) then
      bad_j = jacobian(s%state%f(:, bad_q))
      s%bad_code = point_health(s, bad_q, dt)
    end if
  end subroutine solid_points_force

  !> Distributed memory, the second half of eq. (62), once the ghost points' P (and SCNI
  !! stabilization stresses) are in: the
  !! internal force and a_{n+1} at the owned nodes (gathered over the transpose, in global
  !! point order: the serial sums).
  subroutine solid_nodes_force(s)
    type(solid_t), intent(inout) :: s
    integer :: k, i
    real(wp) :: t0
    t0 = omp_get_wtime()
    if (s%opt%stab_normal > 0.0_wp) then
      call internal_force_list(s%t, s%state%p, s%fint, s%part%own_n, size(s%part%own_n), s%stab)
    else
      call internal_force_list(s%t, s%state%p, s%fint, s%part%own_n, size(s%part%own_n))
    end if
    !$omp parallel do default(none) shared(s) private(i) schedule(static)
    do k = 1, size(s%part%own_n)
      i = s%part%own_n(k)
      s%state%a_old(:, i) = s%state%a(:, i)
      s%state%a(:, i) = (s%fext(:, i) - s%fint(:, i))/s%t%mass(i)
    end do
    !$omp end parallel do
    s%acc%wall(3) = s%acc%wall(3) + (omp_get_wtime() - t0)
  end subroutine solid_nodes_force

  !> After the material update of a step dt at the points list(1:n) (all points when list
  !! is absent): their internal and plastic work over the step (dw, dwp), the last point
  !! with a health problem (bad_q, 0 if none), and the largest kappa_L of the healthy ones
  !! (kmax at point kq; 0 if none).
  subroutine points_account(s, dt, bad_q, dw, dwp, kmax, kq, list, n)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(out) :: bad_q, kq
    real(wp), intent(out) :: dw, dwp, kmax
    integer, intent(in), optional :: list(:), n
    integer :: k, q, nk, qloc
    real(wp) :: kp, kloc, w, wpl
    logical :: listed, glob
    listed = present(list)
    ! a rank's part: its points' numbers in the whole solid decide between equal kappas
    glob = s%part%on .and. allocated(s%part%qglob)
    nk = s%nq
    if (listed) nk = n
    bad_q = 0
    dw = 0.0_wp
    dwp = 0.0_wp
    kmax = 0.0_wp
    kq = 0
    !$omp parallel default(none) shared(s, kmax, kq, dt, list, listed, nk, glob) &
    !$omp private(kp, kloc, qloc, q, w, wpl) reduction(+: dw, dwp) reduction(max: bad_q)
    kloc = 0.0_wp
    qloc = 0
    !$omp do schedule(static)
    do k = 1, nk
      q = k
      if (listed) q = list(k)
      w = s%t%wgt(q)*0.5_wp*sum((s%state%p_old(:, q) + s%state%p(:, q)) &
        *(s%state%f(:, q) - s%state%f_old(:, q)))
      wpl = s%t%wgt(q)*s%dwp(q)
      dw = dw + w
      dwp = dwp + wpl
      s%state%work_q(:, q) = s%state%work_q(:, q) + [w, wpl]
      if (point_health(s, q, dt) /= health_ok) then
        bad_q = max(bad_q, q)
      else
        kp = s%kap0(q)/stretch2_min(s%state%f(:, q))
        if (kp > kloc) then
          kloc = kp
          qloc = q
        else if (kp == kloc .and. glob .and. qloc > 0) then
          ! (a part's points are not in the whole solid's order: the lower number there)
          if (s%part%qglob(q) < s%part%qglob(qloc)) qloc = q
        end if
      end if
    end do
    !$omp end do
    !$omp critical (solid_kappa)
    if (kloc > kmax .or. (kloc == kmax .and. before(qloc, kq))) then
      kmax = kloc
      kq = qloc
    end if
    !$omp end critical (solid_kappa)
    !$omp end parallel
    ! (a rank's part: the bad point with the highest number in the whole solid, the serial
    ! run's; a failing step only)
    if (bad_q > 0 .and. glob) then
      do k = 1, nk
        q = k
        if (listed) q = list(k)
        if (s%part%qglob(q) <= s%part%qglob(bad_q)) cycle
        if (point_health(s, q, dt) /= health_ok) bad_q = q
      end do
    end if
  contains
    !> Is point a before point b in the whole solid (b = 0: none yet)?
    logical function before(a, b)
      integer, intent(in) :: a, b
      if (b == 0 .or. a == 0) then
        before = b == 0 .and. a > 0
      else if (glob) then
        before = s%part%qglob(a) < s%part%qglob(b)
      else
        before = a < b
      end if
    end function before
  end subroutine points_account

  !> Kinematics and material update of a step dt at the points list(1:n) only, with their
  !! work added to the accounts: F from the current d, D and W from F at the points' last
  !! evaluation, the material, P (no stabilization: element meshes).
  subroutine update_points(s, dt, list, n, bad_q, kmax, kq)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(in) :: list(:), n
    integer, intent(out) :: bad_q, kq
    real(wp), intent(out) :: kmax
    integer :: k, q, c, k1, k2
    real(wp) :: dw, dwp, t0, t1, t2
    t0 = omp_get_wtime()
    !$omp parallel do default(none) shared(s, list, n) private(q) schedule(static)
    do k = 1, n
      q = list(k)
      s%state%f_old(:, q) = s%state%f(:, q)
      s%state%p_old(:, q) = s%state%p(:, q)
    end do
    !$omp end parallel do
    if (s%t%anp) then
      !$omp parallel do default(none) shared(s, list, n) private(q) schedule(static)
      do k = 1, n
        q = list(k)
        s%fbar_old(:, q) = s%fbar(:, q)
      end do
      !$omp end parallel do
    end if
    if (s%opt%stab_normal > 0.0_wp) then
      ! (a rank's part of a stabilized RKPM solid: its points' share of the energy)
      call deformation_gradient_list(s%t, s%state%d, s%state%f, list, n, &
        [s%opt%stab_normal, s%opt%stab_shear], s%stab, s%acc%e_stab, energy_q=s%estab)
    else
      call deformation_gradient_list(s%t, s%state%d, s%state%f, list, n)
    end if
    if (s%t%anp) then
      call anp_average(s, list, n)
      call rate_of_deformation_list(dt, s%fbar_old, s%fbar, s%dr, s%spin, list, n)
    else
      call rate_of_deformation_list(dt, s%state%f_old, s%state%f, s%dr, s%spin, list, n)
    end if
    t1 = omp_get_wtime()
    ! in chunks of the list, each run of consecutive points in one call (the slow points of
    ! a subcycled step are most of the body in a few long runs)
    !$omp parallel do default(none) shared(s, dt, list, n) private(k, k1, k2) &
    !$omp schedule(dynamic, 1)
    do c = 1, (n + material_block - 1)/material_block
      k = (c - 1)*material_block + 1
      k2 = min(c*material_block, n)
      do while (k <= k2)
        k1 = k
        do while (k1 < k2)
          if (list(k1 + 1) /= list(k1) + 1) exit
          k1 = k1 + 1
        end do
        call material_range(s, dt, list(k), list(k1))
        k = k1 + 1
      end do
    end do
    !$omp end parallel do
    t2 = omp_get_wtime()
    if (s%t%anp) then
      call anp_stress(s, list, n)
      call piola_stress_list(s%state%f, s%taup, s%state%p, list, n)
    else
      call piola_stress_list(s%state%f, s%state%st%tau, s%state%p, list, n)
    end if
    call points_account(s, dt, bad_q, dw, dwp, kmax, kq, list, n)
    s%acc%w_int = s%acc%w_int + dw
    s%acc%w_plastic = s%acc%w_plastic + dwp
    s%acc%wall = s%acc%wall + [t1 - t0, t2 - t1, omp_get_wtime() - t2]
  end subroutine update_points

  !> The subcycling levels for the reference step dref (s): a point whose critical-step
  !! estimate dt_L satisfies 2^l dref <= dt_L < 2^(l+1) dref has level l (at most lmax); a
  !! node takes the lowest level of its points (lev_node) and then a point the lowest of
  !! its nodes (lev_point). npt(l) and nnd(l) count the points and nodes at level l.
  subroutine solid_sub_levels(s, dref, lmax, npt, nnd)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dref
    integer, intent(in) :: lmax
    integer, intent(out) :: npt(0:lmax), nnd(0:lmax)
    integer :: q, i, k, l
    real(wp) :: r
    if (.not. allocated(s%sub%lev_node)) allocate(s%sub%lev_node(s%np), s%sub%lev_point(s%nq))
    ! each point's own level, from its current kappa_L = kappa0_L/s_min(F)^2
    !$omp parallel do default(none) shared(s, dref, lmax) private(r) schedule(static)
    do q = 1, s%nq
      r = s%dt_cal/(dref*sqrt(s%kap0(q)/stretch2_min(s%state%f(:, q))))
      s%sub%lev_point(q) = lmax
      if (r < 2.0_wp**lmax) s%sub%lev_point(q) = max(0, exponent(r) - 1)
      ! (a non-finite r, from a broken point, steps at the finest rate)
      if (.not. (r == r)) s%sub%lev_point(q) = 0
    end do
    !$omp end parallel do
    nnd = 0
    !$omp parallel do default(none) shared(s, lmax) private(k, l) reduction(+: nnd) &
    !$omp schedule(static)
    do i = 1, s%np
      l = lmax
      do k = s%t%tptr(i), s%t%tptr(i + 1) - 1
        l = min(l, s%sub%lev_point(s%t%tq(k)))
      end do
      s%sub%lev_node(i) = l
      nnd(l) = nnd(l) + 1
    end do
    !$omp end parallel do
    npt = 0
    !$omp parallel do default(none) shared(s, lmax) private(k, l) reduction(+: npt) &
    !$omp schedule(static)
    do q = 1, s%nq
      l = lmax
      do k = s%t%ptr(q), s%t%ptr(q + 1) - 1
        l = min(l, s%sub%lev_node(s%t%nbr(k)))
      end do
      s%sub%lev_point(q) = l
      npt(l) = npt(l) + 1
    end do
    !$omp end parallel do
  end subroutine solid_sub_levels

  !> The step ahead, dt, with levels L (after solid_sub_levels; 0 turns subcycling off for
  !! the step): node rates max(0, L - lev_node), point rates max(0, L - lev_point) (the
  !! rate of the point's fastest node), the lists by rate and the interface lists; the
  !! step's prediction then moves the nodes of rate 0 (sub_rate = 0).
  subroutine solid_sub_select(s, levels, dt)
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: levels
    real(wp), intent(in) :: dt
    integer :: i, q, k, e, r, n
    s%sub%levels = levels
    s%sub%dt = dt
    s%sub%rate = -1
    if (levels == 0) return
    if (.not. allocated(s%sub%node_rate)) then
      allocate(s%sub%node_rate(s%np), s%sub%point_rate(s%nq), s%sub%nlist(s%np), &
        s%sub%qlist(s%nq), s%sub%ilist(size(s%t%nbr)), s%sub%mark(s%np), &
        s%sub%d_end(s%t%dims%ndim, s%np), s%sub%nptr(0:32), s%sub%qptr(0:32), s%sub%iptr(0:32))
      s%sub%mark = -1
    end if
    s%sub%node_rate = max(0, levels - s%sub%lev_node)
    s%sub%point_rate = max(0, levels - s%sub%lev_point)
    call by_rate(s%sub%node_rate, levels, s%sub%nptr, s%sub%nlist)
    call by_rate(s%sub%point_rate, levels, s%sub%qptr, s%sub%qlist)
    ! interface nodes of each point rate r: the nodes of lower rate its points touch
    n = 0
    s%sub%iptr(0:1) = 1
    do r = 1, levels
      do k = s%sub%qptr(r), s%sub%qptr(r + 1) - 1
        q = s%sub%qlist(k)
        do e = s%t%ptr(q), s%t%ptr(q + 1) - 1
          i = s%t%nbr(e)
          if (s%sub%node_rate(i) >= r .or. s%sub%mark(i) == r) cycle
          s%sub%mark(i) = r
          n = n + 1
          s%sub%ilist(n) = i
        end do
      end do
      s%sub%iptr(r + 1) = n + 1
    end do
    do k = 1, n
      s%sub%mark(s%sub%ilist(k)) = -1
    end do
    s%sub%rate = 0
  contains
    !> rate(1:m) sorted by counting: ptr(r) .. ptr(r+1)-1 index list's entries of rate r.
    subroutine by_rate(rate, lv, ptr, list)
      integer, intent(in) :: rate(:), lv
      integer, intent(inout) :: ptr(0:), list(:)
      integer :: j, c, acc, cnt, cur(0:lv)
      ptr(0:lv + 1) = 0
      do j = 1, size(rate)
        ptr(rate(j)) = ptr(rate(j)) + 1
      end do
      acc = 1
      do c = 0, lv
        cnt = ptr(c)
        ptr(c) = acc
        acc = acc + cnt
      end do
      ptr(lv + 1) = acc
      cur = ptr(0:lv)
      do j = 1, size(rate)
        list(cur(rate(j))) = j
        cur(rate(j)) = cur(rate(j)) + 1
      end do
    end subroutine by_rate
  end subroutine solid_sub_select

  !> The nodes of rate r have just been predicted and corrected by contact for their step:
  !! keep where that step ends (their positions in between may be overwritten).
  subroutine solid_sub_begin(s, r)
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: r
    integer :: k
    do k = s%sub%nptr(r), s%sub%nptr(r + 1) - 1
      s%sub%d_end(:, s%sub%nlist(k)) = s%state%d(:, s%sub%nlist(k))
    end do
  end subroutine solid_sub_begin

  !> The start of a step of the nodes of rate r (1..L) over dt/2^r: their prediction (64);
  !! contact then corrects them (sub_rate = r).
  subroutine solid_rate_predict(s, r)
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: r
    integer :: k, i
    real(wp) :: h
    s%sub%rate = r
    h = s%sub%dt/2.0_wp**r
    !$omp parallel do default(none) shared(s, h, r) private(i) schedule(static)
    do k = s%sub%nptr(r), s%sub%nptr(r + 1) - 1
      i = s%sub%nlist(k)
      where (s%pres(:, i)) s%state%v(:, i) = s%vpres(:, i)   ! (not a construct: solid_predict)
      where (s%pres(:, i)) s%state%a(:, i) = 0.0_wp
      s%state%d_old(:, i) = s%state%d(:, i)
      s%state%d(:, i) = s%state%d(:, i) + h*s%state%v(:, i) + 0.5_wp*h*h*s%state%a(:, i)   ! (64)
      s%state%a_old(:, i) = s%state%a(:, i)
      s%fcon(:, i) = 0.0_wp
      s%fpoint(:, i) = 0.0_wp
    end do
    !$omp end parallel do
  end subroutine solid_rate_predict

  !> At time k dt/2^L of a subcycled step: the points of rates smin..L end a step there.
  !! The nodes they touch are put at that time (a node whose own step ends there at its
  !! end, any other on its step's trajectory d_n + tau v_n + tau^2/2 a_n, a_n as contact
  !! corrected it), the points are updated over their own steps, and the nodes of rates
  !! smin..L get their force and a (eq. 62). smin = 0 (k = 2^L) ends the step of everything;
  !! then kappa is current for the step estimate. bad_q, bad_j as solid_internal_force.
  subroutine solid_rates_force(s, smin, k, bad_q, bad_j)
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: smin, k
    integer, intent(out) :: bad_q
    real(wp), intent(out) :: bad_j
    integer :: lv, p, j, i, r, kk, bq, kq, kqa, n0, n
    real(wp) :: delta, tau, km, kma, t0, dtbad
    lv = s%sub%levels
    delta = s%sub%dt/2.0_wp**lv
    do p = max(smin, 1), lv
      !$omp parallel do default(none) shared(s, p, smin, lv, k, delta) &
      !$omp private(i, r, kk, tau) schedule(static)
      do j = s%sub%iptr(p), s%sub%iptr(p + 1) - 1
        i = s%sub%ilist(j)
        r = s%sub%node_rate(i)
        if (r >= smin) then
          s%state%d(:, i) = s%sub%d_end(:, i)
        else
          kk = mod(k, 2**(lv - r))
          tau = real(kk, wp)*delta
          s%state%d(:, i) = s%state%d_old(:, i) + tau*s%state%v(:, i) &
            + 0.5_wp*tau*tau*s%state%a(:, i)
        end if
      end do
      !$omp end parallel do
    end do
    bad_q = 0
    dtbad = s%sub%dt
    kma = 0.0_wp
    kqa = 0
    do p = smin, lv
      n = s%sub%qptr(p + 1) - s%sub%qptr(p)
      if (n == 0) cycle
      call update_points(s, s%sub%dt/2.0_wp**p, s%sub%qlist(s%sub%qptr(p):), n, bq, km, kq)
      if (bq > bad_q) then
        bad_q = bq
        dtbad = s%sub%dt/2.0_wp**p
      end if
      if (kq > 0 .and. (km > kma .or. (km == kma .and. kq < kqa))) then
        kma = km
        kqa = kq
      end if
    end do
    t0 = omp_get_wtime()
    n0 = s%sub%nptr(smin)
    n = s%sub%nptr(lv + 1) - n0
    if (smin == 0) then
      call internal_force(s%t, s%state%p, s%fint)
    else
      call internal_force_list(s%t, s%state%p, s%fint, s%sub%nlist(n0:), n)
    end if
    !$omp parallel do default(none) shared(s, n0, n) private(i) schedule(static)
    do j = n0, n0 + n - 1
      i = s%sub%nlist(j)
      s%state%a_old(:, i) = s%state%a(:, i)
      s%state%a(:, i) = (s%fext(:, i) - s%fint(:, i))/s%t%mass(i)
    end do
    !$omp end parallel do
    s%acc%wall(3) = s%acc%wall(3) + (omp_get_wtime() - t0)
    if (smin == 0 .and. kqa > 0) then
      s%kappa = kma
      s%kappa_q = kqa
    end if
    bad_j = 1.0_wp
    s%bad_code = health_ok
    if (bad_q > 0) then
      bad_j = jacobian(s%state%f(:, bad_q))
      s%bad_code = point_health(s, bad_q, dtbad)
    end if
  end subroutine solid_rates_force

  !> The velocities (63) of the nodes of rates smin..L, each over its own step, with their
  !! work (after solid_rates_force at the same time).
  subroutine solid_rates_update(s, smin)
    type(solid_t), intent(inout) :: s
    integer, intent(in) :: smin
    integer :: r
    real(wp) :: ke, ker
    ke = 0.0_wp
    do r = smin, s%sub%levels
      call advance_nodes(s, s%sub%dt/2.0_wp**r, s%sub%nptr(r + 1) - s%sub%nptr(r), ker, &
        s%sub%nlist(s%sub%nptr(r):))
      ke = ke + ker
    end do
    if (smin == 0) s%acc%ke = ke
  end subroutine solid_rates_update

  !> The step is over: back to plain steps until the next solid_sub_select.
  subroutine solid_sub_end(s)
    type(solid_t), intent(inout) :: s
    s%sub%levels = 0
    s%sub%rate = -1
  end subroutine solid_sub_end

  !> The velocity of eq. (63), with the work of the kinematic conditions and of the contact
  !! forces over the step (trapezoid 1/2 f . du, like the internal work; a contact force acts
  !! at n only) and the kinetic energy.
  subroutine solid_update(s, dt)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    real(wp) :: ke
    if (s%sub%levels > 0) then
      ! the end of a subcycled step: every node over its own step
      call solid_rates_update(s, 0)
    else
      if (s%part%on) then
        call advance_nodes(s, dt, size(s%part%own_n), ke, s%part%own_n)
      else
        call advance_nodes(s, dt, s%np, ke)
      end if
      s%acc%ke = ke
    end if
    s%state%ipoint_time = s%state%ipoint_time + dt
    ! a rank's part: the ghost nodes' v and a from their owners
    if (associated(s%part%halo)) call s%part%halo%nodes2(s%state%v, s%state%a)
  end subroutine solid_update

  !> State field k (state_fields) of solid s as a (rows, entries) array: the nodal vectors
  !! (ndim, np), F and P (nf, nq), the stresses (ncomp, nq), the scalars as one row. The
  !! one place that names the arrays behind state_fields.
  function state_field(s, k) result(p)
    type(solid_t), intent(in), target :: s
    integer, intent(in) :: k
    real(wp), pointer :: p(:, :)
    select case (k)
    case (1)
      p => s%state%d
    case (2)
      p => s%state%v
    case (3)
      p => s%state%a
    case (4)
      p => s%state%freac_old
    case (5)
      p => s%state%ipoint
    case (6)
      p => s%state%f
    case (7)
      p => s%state%p
    case (8)
      p => s%state%st%tau
    case (9)
      p => s%state%st%alpha
    case (10)
      p(1:1, 1:size(s%state%st%epsbar)) => s%state%st%epsbar
    case (11)
      p(1:1, 1:size(s%state%st%epsdot)) => s%state%st%epsdot
    case (12)
      p => s%state%work_q
    case (13)
      p => s%state%work_n
    case default
      ! (not s%state's: computed by every force evaluation, kept for a restart whose run
      ! ends before its next step, which the internal work takes it from)
      p(1:1, 1:size(s%estab)) => s%estab
    end select
  end function state_field

  !> The rows of state field k (state_fields) of solid s.
  integer function solid_field_rows(s, k) result(n)
    type(solid_t), intent(in), target :: s
    integer, intent(in) :: k
    n = size(state_field(s, k), 1)
  end function solid_field_rows

  !> buf(:, j) = state field k of solid s at entry idx(j) (of its nodes or points).
  subroutine solid_get_field(s, k, buf, idx)
    type(solid_t), intent(in), target :: s
    integer, intent(in) :: k
    real(wp), intent(out) :: buf(:, :)
    integer, intent(in) :: idx(:)
    real(wp), pointer :: p(:, :)
    p => state_field(s, k)
    buf = p(:, idx)
  end subroutine solid_get_field

  !> State field k of solid s at entry idx(j) = buf(:, j).
  subroutine solid_put_field(s, k, buf, idx)
    type(solid_t), intent(inout), target :: s
    integer, intent(in) :: k
    real(wp), intent(in) :: buf(:, :)
    integer, intent(in) :: idx(:)
    real(wp), pointer :: p(:, :)
    p => state_field(s, k)
    p(:, idx) = buf
  end subroutine solid_put_field

  !> What follows from the state fields once they are put back (a restart): the reactions
  !! of the step start, F and P of the last evaluation.
  subroutine solid_state_derived(s)
    type(solid_t), intent(inout) :: s
    s%state%freac = s%state%freac_old
    s%state%f_old = s%state%f
    s%state%p_old = s%state%p
    if (s%t%anp) then
      ! F_bar follows from the points' F (the last evaluation of each)
      call anp_average(s)
      s%fbar_old = s%fbar
    end if
  end subroutine solid_state_derived

  !> The energy accounts of solid s, in the order checkpoints hold them: ke0, ke, w_int,
  !! w_plastic, w_bc, w_ext, w_contact, e_stab (J/m in plane strain, J in axisymmetry).
  pure function solid_energies(s) result(e)
    type(solid_t), intent(in) :: s
    real(wp) :: e(8)
    e = [s%acc%ke0, s%acc%ke, s%acc%w_int, s%acc%w_plastic, s%acc%w_bc, s%acc%w_ext, &
      s%acc%w_contact, s%acc%e_stab]
  end function solid_energies

  !> The energy accounts of solid s from e (solid_energies' order).
  subroutine solid_set_energies(s, e)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: e(8)
    s%acc%ke0 = e(1)
    s%acc%ke = e(2)
    s%acc%w_int = e(3)
    s%acc%w_plastic = e(4)
    s%acc%w_bc = e(5)
    s%acc%w_ext = e(6)
    s%acc%w_contact = e(7)
    s%acc%e_stab = e(8)
  end subroutine solid_set_energies

  !> After contact corrected d and a at a part's own nodes: the ghost nodes' from their
  !! owners (a serial solid has none to get).
  subroutine solid_share_corrections(s)
    type(solid_t), intent(inout) :: s
    if (associated(s%part%halo)) call s%part%halo%nodes2(s%state%d, s%state%a)
  end subroutine solid_share_corrections

  !> solid_update for a step dt over the nodes list(1:n), or the nodes 1..n when list is
  !! absent; ke: their kinetic energy.
  subroutine advance_nodes(s, dt, n, ke, list)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer, intent(in) :: n
    real(wp), intent(out) :: ke
    integer, intent(in), optional :: list(:)
    integer :: i, k, nd
    ! a fixed-size private du: one of the solid's dimension was a heap array per thread and
    ! per call (1% of the FEM benchmark's time loop)
    real(wp) :: wbc, wc, wext, du(max_dim), wi(3)
    logical :: listed
    nd = size(s%state%d, 1)
    listed = present(list)
    wbc = 0.0_wp
    wc = 0.0_wp
    wext = 0.0_wp
    ke = 0.0_wp
    !$omp parallel do default(none) shared(s, dt, n, list, listed, nd) private(du, i, wi) &
    !$omp reduction(+: wbc, wc, wext, ke) schedule(static)
    do k = 1, n
      i = k
      if (listed) i = list(k)
      where (s%pres(:, i)) s%state%a(:, i) = 0.0_wp
      ! the contact correction's work in this integrator, exactly: the kinetic energy the
      ! impulse dt/2 f gives at v_n, dt/2 f.v_n + dt^2/8 |f|^2/m (doc/contact.md, "Contact
      ! work"; the trapezoid 1/2 f.(d_{n+1} - d_n) exceeds it by dt^2/4 a_n.f +
      ! dt^2/8 |f|^2/m, which grew without bound against a deformable master); on a
      ! prescribed component the force moves nothing: dt/2 f.v_n, returned in w_bc below
      wi(2) = 0.5_wp*dt*sum(s%fcon(:, i)*s%state%v(:, i)) + 0.125_wp*dt*dt* &
        sum(merge(0.0_wp, s%fcon(:, i)**2, s%pres(:, i)))/s%t%mass(i)
      s%state%v(:, i) = s%state%v(:, i) &
        + 0.5_wp*dt*(s%state%a_old(:, i) + s%state%a(:, i))   ! (63)
      where (s%pres(:, i)) s%state%v(:, i) = s%vpres(:, i)
      ! kinematic conditions: reactions R = f_int - f_ext times the motion
      s%state%freac(:, i) = merge(s%fint(:, i) - s%fext(:, i), 0.0_wp, s%pres(:, i))
      du(:nd) = s%state%d(:, i) - s%state%d_old(:, i)
      wi(1) = 0.5_wp*sum((s%state%freac_old(:, i) + s%state%freac(:, i))*du(:nd))
      ! a contact force on a prescribed component is held by the condition: its reaction
      ! does the opposite work (a driven plate pushing a body supplies what contact
      ! delivers to the body; w_contact counts both and nets to ~0)
      wi(1) = wi(1) - 0.5_wp*sum(merge(s%fcon(:, i), 0.0_wp, s%pres(:, i))*du(:nd))
      s%state%freac_old(:, i) = s%state%freac(:, i)
      ! the body force (gravity), constant: its work is f_ext . du exactly (on a prescribed
      ! component the reaction, which holds f_ext too, returns it in w_bc)
      wi(3) = sum(s%fext(:, i)*du(:nd))
      wbc = wbc + wi(1)
      wc = wc + wi(2)
      wext = wext + wi(3)
      s%state%work_n(1:3, i) = s%state%work_n(1:3, i) + wi
      s%state%ipoint(:, i) = s%state%ipoint(:, i) + 0.5_wp*dt*s%fpoint(:, i)
      ke = ke + 0.5_wp*s%t%mass(i)*sum(s%state%v(:, i)**2)
    end do
    !$omp end parallel do
    s%acc%w_bc = s%acc%w_bc + wbc
    s%acc%w_contact = s%acc%w_contact + wc
    s%acc%w_ext = s%acc%w_ext + wext
  end subroutine advance_nodes

  !> A uniform body force per unit mass g (gravity, m/s^2): f_ext = M_I g at every node
  !! with the lumped masses (eq. 70), the same force a consistent mass would give for a
  !! uniform field, since the lumped masses are its row sums. Kept in the options, so that
  !! a rank's part sets its own from the whole solid's.
  subroutine solid_set_gravity(s, g)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: g(:)
    integer :: i, nd
    real(wp) :: gv(max_dim)
    nd = s%t%dims%ndim
    ! (through a copy: a rank's part passes its own s%opt%gravity)
    gv = 0.0_wp
    gv(1:nd) = g(1:nd)
    s%opt%gravity = gv
    ! (a shell, solid_init's, has no forces: its part's are set at the split)
    if (.not. allocated(s%fext)) return
    do i = 1, s%np
      s%fext(:, i) = s%t%mass(i)*s%opt%gravity(1:nd)
    end do
  end subroutine solid_set_gravity

  !> An initial spin omega (rad/s, counter-clockwise, plane) about the centre of mass x_c
  !! = sum M X / M: v_I += omega e3 x (X_I - x_c) on the components not prescribed. RK
  !! shape functions reproduce linear fields, so the physical velocity is the rigid
  !! rotation exactly; the kinetic energy at t = 0 is taken again.
  subroutine solid_add_spin(s, omega)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: omega
    real(wp) :: xc(max_dim), r(max_dim), w(max_dim)
    integer :: i, nd
    nd = s%t%dims%ndim
    xc = 0.0_wp
    do i = 1, s%np
      xc(:nd) = xc(:nd) + s%t%mass(i)*s%x0(:, i)
    end do
    xc(:nd) = xc(:nd)/sum(s%t%mass)
    do i = 1, s%np
      r(:nd) = s%x0(:, i) - xc(:nd)
      w(:nd) = omega*[-r(2), r(1)]   ! e3 x r: the plane (the deck allows a spin there only)
      where (.not. s%pres(:, i)) s%state%v(:, i) = s%state%v(:, i) + w(:nd)
    end do
    s%acc%ke0 = solid_kinetic_energy(s)
    s%acc%ke = s%acc%ke0
  end subroutine solid_add_spin

  !> The reaction force of each &bc group on the solid (N, or N/m in plane strain), added
  !! exactly into v(k) for group k over the solid's nodes (a rank's part: its owned nodes): the
  !! force the condition exerts on the body to hold its components, R = f_int - f_ext at
  !! the end of the step (the contact forces of the step act at n only and are not in it).
  subroutine solid_bc_reactions(s, v)
    type(solid_t), intent(in) :: s
    type(exact_sum_t), intent(inout) :: v(:)
    integer :: k, i, n, c
    if (.not. allocated(s%bc_of)) return
    n = s%np
    if (s%part%on) n = size(s%part%own_n)
    do k = 1, n
      i = k
      if (s%part%on) i = s%part%own_n(k)
      do c = 1, size(s%bc_of, 1)
        if (s%bc_of(c, i) > 0) call exact_add(v(s%bc_of(c, i)), s%state%freac(c, i))
      end do
    end do
  end subroutine solid_bc_reactions

  !> Sums over the solid's nodes (a rank's part: its owned nodes) for the history, from
  !! the coefficients of eqs. (65)-(67) with the lumped masses: v(1) the kinetic energy,
  !! v(2) the mass, v(3:2+nd) the momentum sum M v, v(3+nd:2+2nd) sum M x with x = X + d,
  !! and then the angular momentum about the origin, sum M x (x) v: its one component out
  !! of the plane (x1 v2 - x2 v1), or its three in 3D. size(v) = solid_sums_size(ndim).
  !! Exact sums (exact_sum_m), so that the ranks' parts add up to the whole to the bit.
  subroutine solid_body_sums(s, v)
    type(solid_t), intent(in) :: s
    type(exact_sum_t), intent(inout) :: v(:)
    integer :: k, i, n, nd, o, c
    real(wp) :: m, x(max_dim), u(max_dim)
    nd = s%t%dims%ndim
    o = 2 + 2*nd
    n = s%np
    if (s%part%on) n = size(s%part%own_n)
    do k = 1, n
      i = k
      if (s%part%on) i = s%part%own_n(k)
      m = s%t%mass(i)
      x(:nd) = s%x0(:, i) + s%state%d(:, i)
      u(:nd) = s%state%v(:, i)
      call exact_add(v(1), 0.5_wp*m*sum(u(:nd)**2))
      call exact_add(v(2), m)
      do c = 1, nd
        call exact_add(v(2 + c), m*u(c))
        call exact_add(v(2 + nd + c), m*x(c))
      end do
      if (nd == dims_plane%ndim) then
        call exact_add(v(o + 1), m*(x(1)*u(2) - x(2)*u(1)))
      else
        call exact_add(v(o + 1), m*(x(2)*u(3) - x(3)*u(2)))
        call exact_add(v(o + 2), m*(x(3)*u(1) - x(1)*u(3)))
        call exact_add(v(o + 3), m*(x(1)*u(2) - x(2)*u(1)))
      end if
    end do
  end subroutine solid_body_sums

  !> The energy accounts of solid s added exactly into v(1:8), in solid_energies' order
  !! (ke0, ke, w_int, w_plastic, w_bc, w_ext, w_contact, e_stab), from its entries (a rank's
  !! part: its owned nodes and points): the kinetic energy now and at t = 0, the work at
  !! each point and node (solid_state_t's work_q, work_n) and the stabilization energy at
  !! each point. Exact sums (exact_sum_m): the totals are the same bits however the entries
  !! are split among ranks and threads, where the running sums of the step (s%acc, which
  !! the energy guard reads each step) are not.
  subroutine solid_account_sums(s, v)
    type(solid_t), intent(in) :: s
    type(exact_sum_t), intent(inout) :: v(:)
    integer :: k, i, n
    real(wp) :: e
    ! (most terms but the kinetic energy and the internal work are zeros, which add nothing:
    ! skipped before the call, a history row's cost is about halved)
    n = s%np
    if (s%part%on) n = size(s%part%own_n)
    do k = 1, n
      i = k
      if (s%part%on) i = s%part%own_n(k)
      if (s%state%work_n(4, i) /= 0.0_wp) call exact_add(v(1), s%state%work_n(4, i))
      e = 0.5_wp*s%t%mass(i)*sum(s%state%v(:, i)**2)
      if (e /= 0.0_wp) call exact_add(v(2), e)
      if (s%state%work_n(1, i) /= 0.0_wp) call exact_add(v(5), s%state%work_n(1, i))
      if (s%state%work_n(3, i) /= 0.0_wp) call exact_add(v(6), s%state%work_n(3, i))
      if (s%state%work_n(2, i) /= 0.0_wp) call exact_add(v(7), s%state%work_n(2, i))
    end do
    n = s%nq
    if (s%part%on) n = size(s%part%own_q)
    do k = 1, n
      i = k
      if (s%part%on) i = s%part%own_q(k)
      if (s%state%work_q(1, i) /= 0.0_wp) call exact_add(v(3), s%state%work_q(1, i))
      if (s%state%work_q(2, i) /= 0.0_wp) call exact_add(v(4), s%state%work_q(2, i))
      if (s%estab(i) /= 0.0_wp) call exact_add(v(8), s%estab(i))
    end do
  end subroutine solid_account_sums

  !> The size of solid_body_sums' v in ndim dimensions.
  pure integer function solid_sums_size(ndim) result(n)
    integer, intent(in) :: ndim
    n = 2 + 2*ndim + merge(3, 1, ndim == 3)
  end function solid_sums_size

  !> Physical positions of every node (ndim, np) at the start of the step or at the current
  !! (predicted, possibly corrected) coefficients (m).
  subroutine solid_positions(s, which, x)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: which
    real(wp), intent(out) :: x(:, :)
    if (which == at_step_start) then
      call physical_positions(s%t, s%x0, s%state%d_old, x)
    else
      call physical_positions(s%t, s%x0, s%state%d, x)
    end if
  end subroutine solid_positions

  !> Physical position x (ndim) of node j from the current coefficients, or with which =
  !! at_step_start from those at the start of the step (m). A subroutine: a function
  !! result of the solid's dimension would be a heap temporary at every call.
  pure subroutine solid_point_position(s, j, x, which)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: j
    real(wp), intent(out) :: x(:)
    integer, intent(in), optional :: which
    if (present(which)) then
      if (which == at_step_start) then
        call point_position(s, s%state%d_old, j, x)
        return
      end if
    end if
    call point_position(s, s%state%d, j, x)
  end subroutine solid_point_position

  pure subroutine point_position(s, d, j, x)
    type(solid_t), intent(in) :: s
    real(wp), intent(in) :: d(:, :)
    integer, intent(in) :: j
    real(wp), intent(out) :: x(:)
    integer :: e
    if (s%t%interpolating) then
      x = s%x0(:, j) + d(:, j)
      return
    end if
    ! summed in the order of physical_positions, so both give the same bits
    x = 0.0_wp
    if (s%t%dims%npos == 1) then
      ! (one shape function for every component: 3D)
      do e = s%t%pptr(j), s%t%pptr(j + 1) - 1
        x = x + s%t%pn(1, e)*d(:, s%t%pnbr(e))
      end do
    else
      do e = s%t%pptr(j), s%t%pptr(j + 1) - 1
        x = x + s%t%pn(:, e)*d(:, s%t%pnbr(e))
      end do
    end if
    x = s%x0(:, j) + x
  end subroutine point_position

  !> Contact forces of the step start at zero (solid_predict also clears them).
  subroutine solid_clear_contact(s)
    type(solid_t), intent(inout) :: s
    s%fcon = 0.0_wp
    s%fpoint = 0.0_wp
  end subroutine solid_clear_contact

  !> Point forces fphys (2, np) acting at the physical points of the nodes, spread onto the
  !! nodal coefficients and added to fcon (N): f_I = sum_J N_I(X_J) f_J (eq. 98); for
  !! interpolating tables (element nodes) f_I = f_J (eq. 99). Only non-zero forces cost work.
  subroutine solid_add_point_forces(s, fphys)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: fphys(:, :)
    integer :: j, e, i, jj, n, k0
    ! (subcycling: only the nodes of the rate being stepped have forces)
    k0 = 0
    n = s%np
    if (s%sub%rate >= 0) then
      k0 = s%sub%nptr(s%sub%rate) - 1
      n = s%sub%nptr(s%sub%rate + 1) - s%sub%nptr(s%sub%rate)
    end if
    do jj = 1, n
      j = jj
      if (s%sub%rate >= 0) j = s%sub%nlist(k0 + jj)
      if (all(fphys(:, j) == 0.0_wp)) cycle
      s%fpoint(:, j) = s%fpoint(:, j) + fphys(:, j)
      if (s%t%interpolating) then
        s%fcon(:, j) = s%fcon(:, j) + fphys(:, j)
        cycle
      end if
      if (s%t%dims%npos == 1) then
        do e = s%t%pptr(j), s%t%pptr(j + 1) - 1
          i = s%t%pnbr(e)
          s%fcon(:, i) = s%fcon(:, i) + s%t%pn(1, e)*fphys(:, j)
        end do
      else
        do e = s%t%pptr(j), s%t%pptr(j + 1) - 1
          i = s%t%pnbr(e)
          s%fcon(:, i) = s%fcon(:, i) + s%t%pn(:, e)*fphys(:, j)
        end do
      end if
    end do
  end subroutine solid_add_point_forces

  !> a_n corrected by the contact forces fcon and the prediction of eq. (64) redone.
  subroutine solid_correct(s, dt)
    type(solid_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    integer :: i, k, k0, n
    ! subcycling: only the nodes of the rate being stepped
    k0 = 0
    n = s%np
    if (s%sub%rate >= 0) then
      k0 = s%sub%nptr(s%sub%rate) - 1
      n = s%sub%nptr(s%sub%rate + 1) - s%sub%nptr(s%sub%rate)
    end if
    !$omp parallel do default(none) shared(s, dt, n, k0) private(i) schedule(static)
    do k = 1, n
      i = k
      if (s%sub%rate >= 0) i = s%sub%nlist(k0 + k)
      s%state%a(:, i) = s%state%a_old(:, i) + s%fcon(:, i)/s%t%mass(i)
      where (s%pres(:, i)) s%state%a(:, i) = 0.0_wp
      s%state%d(:, i) = s%state%d_old(:, i) + dt*s%state%v(:, i) + 0.5_wp*dt*dt*s%state%a(:, i)
    end do
    !$omp end parallel do
  end subroutine solid_correct

  !> The health of integration point q after the material update of a step dt: J inside
  !! j_bounds, finite stress, epsbar and its increment dt epsdot under their limits.
  pure integer function point_health(s, q, dt) result(code)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: q
    real(wp), intent(in) :: dt
    real(wp) :: jq
    code = health_ok
    jq = jacobian(s%state%f(:, q))
    if (.not. (jq > s%opt%j_bounds(1) .and. jq < s%opt%j_bounds(2))) then
      code = health_j
    else if (.not. all(abs(s%state%st%tau(:, q)) < huge(1.0_wp))) then
      code = health_stress
    else if (.not. (s%state%st%epsbar(q) <= s%opt%epsbar_limit)) then
      code = health_epsbar
    else if (.not. (dt*s%state%st%epsdot(q) <= s%opt%deps_limit)) then
      code = health_deps
    end if
  end function point_health

  !> The node whose coefficient or velocity is non-finite (the first), else the fastest
  !! node; vmax its speed (m/s, huge if non-finite).
  subroutine solid_worst_node(s, j, vmax)
    type(solid_t), intent(in) :: s
    integer, intent(out) :: j
    real(wp), intent(out) :: vmax
    integer :: i, k, jbad
    real(wp) :: v2, v2max
    j = 1
    jbad = 0
    v2max = -1.0_wp
    if (.not. s%part%on) then
      do i = 1, s%np
        if (.not. all(abs(s%state%d(:, i)) < huge(1.0_wp) &
            .and. abs(s%state%v(:, i)) < huge(1.0_wp))) then
          jbad = i
          exit
        end if
        v2 = sum(s%state%v(:, i)**2)
        if (v2 > v2max) then
          v2max = v2
          j = i
        end if
      end do
    else
      ! a rank's part: its owned nodes, and among equals the lower number in the whole
      ! solid, as the serial loop finds them
      do k = 1, size(s%part%own_n)
        i = s%part%own_n(k)
        if (.not. all(abs(s%state%d(:, i)) < huge(1.0_wp) &
            .and. abs(s%state%v(:, i)) < huge(1.0_wp))) then
          if (jbad == 0) jbad = i
          if (solid_node_number(s, i) < solid_node_number(s, jbad)) jbad = i
          cycle
        end if
        v2 = sum(s%state%v(:, i)**2)
        if (v2 > v2max .or. (v2 == v2max .and. solid_node_number(s, i) < &
            solid_node_number(s, j))) then
          v2max = v2
          j = i
        end if
      end do
    end if
    if (jbad > 0) then
      j = jbad
      vmax = huge(1.0_wp)
      return
    end if
    vmax = sqrt(max(v2max, 0.0_wp))
  end subroutine solid_worst_node

  !> The number of node i of solid s in the whole solid (a rank's part numbers its own).
  !> The whole solid's node count of s (a region shell's np_whole, else s%np).
  pure integer function solid_np_whole(s) result(n)
    type(solid_t), intent(in) :: s
    n = s%np
    if (s%part%region .or. s%part%on) n = s%part%np_whole
  end function solid_np_whole

  !> The whole solid's integration point count of s (a region shell's nq_whole, else s%nq).
  pure integer function solid_nq_whole(s) result(n)
    type(solid_t), intent(in) :: s
    n = s%nq
    if (s%part%region .or. s%part%on) n = s%part%nq_whole
  end function solid_nq_whole

  !> The place in solid s of node j of the whole solid: j itself, or in a region shell
  !! its place among the region's nodes (0: not in the region).
  pure integer function solid_node_place(s, j) result(i)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: j
    i = j
    if (s%part%region) i = sorted_place(s%part%nglob, j)
  end function solid_node_place

  pure integer function solid_node_number(s, i) result(g)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: i
    g = i
    if ((s%part%on .or. s%part%region) .and. allocated(s%part%nglob)) g = s%part%nglob(i)
  end function solid_node_number

  !> The number of integration point q of solid s in the whole solid.
  pure integer function solid_point_number(s, q) result(g)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: q
    g = q
    if ((s%part%on .or. s%part%region) .and. allocated(s%part%qglob)) g = s%part%qglob(q)
  end function solid_point_number
end module solid_m
