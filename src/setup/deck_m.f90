!> The namelist deck: one group per concern (&run, &body repeatable, &detection, &output).
!! Defaults are set before each read, every read has iostat/iomsg, ranges are checked after,
!! and every message names the deck, the group, the variable, the value and the fix.
!! Variables, units, defaults and ranges are documented in doc/deck.md.
module deck_m
  use kinds_m, only: wp, i64
  use strings_m, only: lower, itoa, join_names, rtoa_plain => rtoa, edit_distance
  use errors_m, only: error_t, set_error
  use kernels_m, only: kernel_id, kernel_names, window_shape_id, window_shape_names
  use basis_m, only: basis_id, basis_names, basis_order
  use material_m, only: material_params_t, check_material_params, material_names, &
    material_constant_names, material_constant_units, material_constant_meaning, &
    model_uses, model_default, &
    material_constant, set_material_constant, material_presets
  use geometry_m, only: polygon_crossing
  use generators_m, only: max_perturbation
  use file_system_m, only: read_plain_file, is_dir
  use geo_script_m, only: geo_model_t, geo_parse, geo_min_triangles, geo_max_bytes
  use, intrinsic :: iso_fortran_env, only: iostat_end
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  implicit none
  private
  public :: deck_t, run_params_t, body_spec_t, detection_spec_t, output_spec_t
  public :: material_spec_t, solver_spec_t, bc_spec_t, contact_spec_t
  public :: read_deck, max_vertices, max_points, max_geo_numbers, unset
  public :: deck_var_t, deck_vars, var_index, choices_text
  public :: body_count_var, body_place_var, body_make_vars

  integer, parameter :: max_vertices = 64
  integer, parameter :: max_points = 32
  !> Most gmsh parser numbers of a shape = 'geo' body (geo_names, geo_values).
  integer, parameter :: max_geo_numbers = 16
  !> The limits on meshing a shape = 'geo' script unless the deck gives its own
  !! (geo_time_limit, s; geo_max_elements, triangles): far above the meshes mfcd runs (the
  !! paper's Taylor bar has 43,200 triangles; gmsh makes about 20,000 triangles a second
  !! on one core), so that a hostile or mistaken script ends with a message instead of a
  !! hang.
  real(wp), parameter :: default_geo_time_limit = 600.0_wp
  integer, parameter :: default_geo_max_elements = 2000000
  integer, parameter :: max_bodies = 16
  !> Most particles of a generated 2D lattice (rectangle, polygon, annulus sector).
  integer(i64), parameter :: max_lattice = 50000000_i64
  !> Most query points of one &detection set (line or grid).
  integer(i64), parameter :: max_queries = 100000000_i64
  include 'deck_lengths.inc'
  !> Largest deck read (bytes): a deck is a page of namelists.
  integer, parameter :: max_deck_bytes = 16777216
  !> Marks an array entry the deck did not set.
  real(wp), parameter :: unset = -huge(1.0_wp)

  character(len=*), parameter :: known_groups(8) = [character(len=9) :: &
    'run', 'body', 'detection', 'output', 'material', 'solver', 'bc', 'contact']
  !> The groups a deck may give more than once (each of the others at most once).
  character(len=*), parameter :: repeatable_groups(4) = [character(len=8) :: &
    'body', 'material', 'bc', 'contact']
  integer, parameter :: max_materials = 8
  integer, parameter :: max_bcs = 32
  integer, parameter :: max_snapshots = 256
  integer, parameter :: max_contacts = 8

  !> A deck variable (src/setup/deck_vars.tsv, whose header says what each column means): its
  !! group and name; typ 'r' real, 'i' integer, 'l' logical, 's' string; how many values
  !! it holds; a string's characters (0 for the others); unit; what a given value must be
  !! (any, one of 'a' 'b' ..., an interval [a, b] (a, b] [a, b) (a, b), or > a, >= a, < a,
  !! <= a); and the hint said when a value is refused.
  type :: deck_var_t
    character(len=9) :: group
    character(len=17) :: name
    character :: typ
    integer :: size
    integer :: length
    character(len=8) :: unit
    character(len=96) :: valid
    character(len=192) :: hint
  end type deck_var_t

  include 'deck_vars_table.inc'

  !> Where check_groups is in the deck text t (n characters): at t(i), on line lineno, in
  !! group (its text for messages gtext, its index ig in known_groups) or not, after the
  !! variable var (nvals values so far; subscripted: var(...) =); per group how many were
  !! given (nth), the line of the first and of the end of the last.
  type :: deck_scan_t
    character(len=:), allocatable :: t
    integer :: n = 0, i = 1, lineno = 1, ig = 0, nvals = 0
    logical :: in_group = .false., subscripted = .false.
    character(len=:), allocatable :: group, var, gtext
    integer :: nth(size(known_groups)) = 0, first(size(known_groups)) = 0
    integer :: last_end(size(known_groups)) = 0
  end type deck_scan_t

  type :: run_params_t
    character(len=run_title_len) :: title
    character(len=run_mode_len) :: mode
    integer :: ndim
    character(len=run_geometry_len) :: geometry
    real(wp) :: gravity(3) = 0.0_wp   !< uniform body force per unit mass (m/s^2)
  end type run_params_t

  type :: body_spec_t
    character(len=body_name_len) :: name
    character(len=body_shape_len) :: shape
    real(wp) :: lo(3), hi(3)
    integer :: n(3)
    real(wp) :: vertices(2, max_vertices)
    integer :: nvert = 0
    real(wp) :: spacing(3)
    real(wp) :: origin(2)
    real(wp) :: center(2)
    real(wp) :: r_inner, r_outer
    real(wp) :: radius      !< shape 'disk': its radius (m), about center
    real(wp) :: extrude(2)  !< shape 'polygon' in 3D, 'cylinder': the z range (m)
    real(wp) :: theta_start, theta_end   !< degrees in the deck
    character(len=body_file_len) :: file
    !> shape 'geo': the gmsh parser numbers set before the .geo script is read, as names
    !! (ngeo of them) and values
    character(len=body_geo_names_len) :: geo_names(max_geo_numbers)
    real(wp) :: geo_values(max_geo_numbers)
    integer :: ngeo = 0
    !> shape 'geo': the limits on meshing the script, wall-clock seconds and triangles
    real(wp) :: geo_time_limit
    integer :: geo_max_elements
    !> shape 'geo': the script's model, read once when the deck is checked (geo_script_m);
    !! what is meshed is exactly what was checked
    type(geo_model_t) :: geo
    character(len=body_kernel_len) :: kernel
    character(len=body_window_len) :: window
    character(len=body_basis_len) :: basis
    real(wp) :: support_factor(3)
    character(len=body_role_len) :: role
    character(len=body_material_len) :: material
    real(wp) :: velocity(3)   !< initial velocity (m/s)
    !> initial angular velocity about the body's centre of mass, out of the plane,
    !! counter-clockwise (rad/s); plane strain only
    real(wp) :: angular_velocity = 0.0_wp
    !> placement: the body as built (generated, meshed or read) turned by rotate degrees
    !! counter-clockwise about its centroid, then moved by translate (m)
    real(wp) :: translate(3) = 0.0_wp
    real(wp) :: rotate = 0.0_wp
    character(len=body_integration_len) :: integration
    real(wp) :: stabilization   !< SCNI sub-cell stabilization alpha (0: off)
    !> 'rkpm' (particles) or 'fem' (CST4 elements on the n(1) x n(2) lattice's boxes)
    character(len=body_discretization_len) :: discretization
    !> random offset of the interior particles, a fraction of the spacing (0: the lattice)
    real(wp) :: perturbation
    integer :: perturbation_seed   !< seed of the offsets (xorshift64)
    integer :: kid = 0, wshape = 0, bid = 0
    integer :: imat = 0   !< index into deck%materials
  end type body_spec_t

  !> A named material (&material): its constitutive model and parameters.
  type :: material_spec_t
    character(len=material_name_len) :: name = ''
    type(material_params_t) :: params
    character(len=16) :: preset = ''    !< the preset the group named (material_presets)
    !> where each constant (material_constant_names) came from: 'given', 'preset',
    !! 'default' (b and theta only), '' (not a constant of the model)
    character(len=7) :: source(size(material_constant_names)) = ''
  end type material_spec_t

  !> Time integration and run control (&solver).
  type :: solver_spec_t
    real(wp) :: t_end   !< end time (s)
    real(wp) :: dt   !< fixed step (s); 0: cfl x critical step
    real(wp) :: cfl   !< fraction of the estimated critical step
    integer :: log_every   !< log line every N steps (0: about 50 lines a run)
    integer :: history_every   !< history row every N steps (0: as log_every)
    real(wp) :: snapshot_times(max_snapshots)
    integer :: nsnap = 0
    real(wp) :: energy_tol   !< stop when |residual| > tol x energy scale
    integer :: max_steps
    !> points whose nodes all still move in the body's initial uniform translation skip F,
    !! the material update and the internal force (exact to round-off)
    logical :: skip_quiet
    !> split a step where a few points' critical step falls below it: those points and
    !! their nodes advance in 2^L sub-steps, the rest once (element meshes against rigid
    !! masters; doc/solver.md, "Subcycling")
    logical :: subcycle
  end type solver_spec_t

  !> A kinematic condition (&bc) on the particles of a body inside a reference box.
  type :: bc_spec_t
    character(len=bc_body_len) :: body
    real(wp) :: region_lo(3), region_hi(3)
    integer :: component   !< 1 or 2
    character(len=bc_kind_len) :: kind   !< 'fixed' or 'velocity'
    real(wp) :: value   !< prescribed velocity (m/s)
    integer :: ibody = 0
  end type bc_spec_t

  !> A master/slave contact pair (&contact), Sections 2 and 5.
  type :: contact_spec_t
    character(len=contact_master_len) :: master
    character(len=contact_slave_len) :: slave
    real(wp) :: eps_cr   !< det(M_master) threshold (paper: 5e-10)
    real(wp) :: eps_rel   !< or a fraction of the master's plateau
    real(wp) :: mu   !< Coulomb friction coefficient
    !> 'det_m' (the paper's det(M) screen, eqs. 25-28) or 'node_to_segment' (a bucket-sorted
    !! closest-segment search, Benson-Hallquist style: the paper's comparison)
    character(len=contact_detector_len) :: detector
    logical :: compare_detectors   !< also evaluate the other detector, for counters
    !> skip slave particles that cannot have reached the master's box since they were last
    !! found outside it (a bound on their motion); exact: the same results
    logical :: skip_far
    real(wp) :: edge_point(3)   !< reference point of a slave particle whose
                                           !< contact and separation times are reported (m)
    !> eq. (93) against a deformable master with the master nodes' masses shared among the
    !! particles that push them (contact_params_t%shared_mass)
    logical :: shared_mass
    !> master = slave: self-contact; a point's reference neighbours, within self_radius
    !! times its largest support or theirs, take no part in its det(M) or its gap
    real(wp) :: self_radius
    integer :: imaster = 0, islave = 0
  end type contact_spec_t

  type :: detection_spec_t
    logical :: present = .false.
    character(len=detection_body_len) :: body
    real(wp) :: eps_cr
    real(wp) :: eps_rel
    real(wp) :: line_from(3), line_to(3)
    integer :: line_n
    real(wp) :: grid_lo(3), grid_hi(3)
    integer :: grid_n(3)
    real(wp) :: points(3, max_points)
    integer :: npoints = 0
  end type detection_spec_t

  type :: output_spec_t
    character(len=output_file_len) :: file
    logical :: overwrite
    !> det(M) of each contact pair's master and slave on a grid at every snapshot (Figs. 9-10)
    logical :: det_fields
    real(wp) :: det_grid_lo(2), det_grid_hi(2)
    integer :: det_grid_n(2)
    !> mode dynamic: a checkpoint (<stem>.checkpoint.h5) every this many steps; 0: none
    integer :: checkpoint_every
  end type output_spec_t

  type :: deck_t
    character(len=:), allocatable :: path
    character(len=:), allocatable :: text   !< the deck verbatim
    type(run_params_t) :: run
    integer :: nbodies = 0
    type(body_spec_t), allocatable :: bodies(:)
    type(detection_spec_t) :: detection
    type(output_spec_t) :: output
    integer :: nmaterials = 0
    type(material_spec_t), allocatable :: materials(:)
    type(solver_spec_t) :: solver
    integer :: nbcs = 0
    type(bc_spec_t), allocatable :: bcs(:)
    integer :: ncontacts = 0
    type(contact_spec_t), allocatable :: contacts(:)
  end type deck_t

contains

  !> Read and validate the whole deck at path. Nothing is written anywhere.
  subroutine read_deck(path, deck, err)
    character(len=*), intent(in) :: path
    type(deck_t), intent(out) :: deck
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: problem
    integer :: u, ios
    character(len=512) :: msg
    logical :: exists
    deck%path = path
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call set_error(err, "deck '"//path//"' not found: check the path (run mfcd --help)")
      return
    end if
    ! read once as a plain file (a FIFO or device would give gfortran's second read, below,
    ! other bytes than the ones checked here)
    call read_plain_file(path, max_deck_bytes, deck%text, problem, follow_links=.true.)
    if (len(problem) > 0) then
      call set_error(err, "deck '"//path//"' "//problem//": give the path of a plain "// &
        "text deck of at most "//itoa(max_deck_bytes)//" bytes")
      return
    end if
    call check_groups(deck, err)
    if (allocated(err)) return
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(err, "deck '"//path//"' cannot be opened: "//trim(msg))
      return
    end if
    call read_run(u, deck, err)
    if (.not. allocated(err)) call read_materials(u, deck, err)
    if (.not. allocated(err)) call read_bodies(u, deck, err)
    if (.not. allocated(err)) call read_detection(u, deck, err)
    if (.not. allocated(err)) call read_solver(u, deck, err)
    if (.not. allocated(err)) call read_bcs(u, deck, err)
    if (.not. allocated(err)) call read_contacts(u, deck, err)
    if (.not. allocated(err)) call read_output(u, deck, err)
    close(u)
    if (.not. allocated(err)) call check_across(deck, err)
    if (.not. allocated(err)) call check_subcycle(deck, err)
    if (.not. allocated(err)) call check_3d(deck, err)
  end subroutine read_deck

  !> What a 3D dynamic run does not have (doc/3d.md): the node-to-segment detector; RKPM
  !! bodies integrated otherwise than by SCNI.
  subroutine check_3d(deck, err)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    if (deck%run%ndim /= 3 .or. deck%run%mode /= 'dynamic') return
    do k = 1, deck%nbodies
      if (deck%bodies(k)%role == 'rigid') cycle
      if (deck%bodies(k)%discretization == 'fem') cycle
      if (deck%bodies(k)%integration /= 'scni') then
        call bad(deck, 'body', 'integration', "'"//trim(deck%bodies(k)%integration)// &
          "' (body '"//trim(deck%bodies(k)%name)//"')", "3D RKPM bodies are integrated "// &
          "by SCNI over their cells: give integration = 'scni'", err)
        return
      end if
    end do
    do k = 1, deck%ncontacts
      associate (c => deck%contacts(k))
        if (c%detector /= 'det_m' .or. c%compare_detectors) then
          call bad(deck, 'contact', 'detector', "'"//trim(c%detector)//"'", "3D contact "// &
            "detects by det(M) of the master: give detector = 'det_m' and "// &
            "compare_detectors = .false.", err)
        end if
      end associate
      if (allocated(err)) return
    end do
  end subroutine check_3d

  !> &solver subcycle needs element meshes (a contact force on an element node moves that
  !! node only) against rigid masters (a sub-step corrects only the slave's fast nodes).
  subroutine check_subcycle(deck, err)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    if (.not. deck%solver%subcycle .or. deck%run%mode /= 'dynamic') return
    do k = 1, deck%nbodies
      if (deck%bodies(k)%role == 'rigid') cycle
      if (deck%bodies(k)%discretization /= 'fem') then
        call bad(deck, 'solver', 'subcycle', '.true.', "body '"// &
          trim(deck%bodies(k)%name)//"' is RKPM; subcycling splits element meshes only: "// &
          "give it discretization = 'fem' or set subcycle = .false.", err)
        return
      end if
    end do
    do k = 1, deck%ncontacts
      associate (c => deck%contacts(k))
        if (c%imaster == c%islave .or. deck%bodies(c%imaster)%role /= 'rigid') then
          call bad(deck, 'solver', 'subcycle', '.true.', "contact "//itoa(k)//" ('"// &
            trim(c%master)//"' on '"//trim(c%slave)//"') has a deformable master; "// &
            "subcycling needs rigid masters: set subcycle = .false.", err)
          return
        end if
      end associate
    end do
  end subroutine check_subcycle

  !> Checks that span groups, after every group is read and checked on its own.
  subroutine check_across(deck, err)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, j
    real(wp) :: steps
    if (deck%run%mode == 'dynamic' .and. deck%solver%dt > 0.0_wp) then
      ! the step counter is a default integer
      steps = deck%solver%t_end/deck%solver%dt
      if (steps > real(huge(1), wp)) then
        call bad(deck, 'solver', 'dt', rtoa(deck%solver%dt), 't_end/dt = '//rtoa(steps)// &
          ' steps, more than the '//itoa(huge(1))//' a run can count; give a larger dt or '// &
          'a shorter t_end', err)
        return
      end if
    end if
    do k = 2, deck%ncontacts
      do j = 1, k - 1
        if (deck%contacts(k)%imaster == deck%contacts(j)%imaster .and. &
          deck%contacts(k)%islave == deck%contacts(j)%islave) then
          call bad(deck, 'contact (contact '//itoa(k)//')', 'slave', "'"// &
            trim(deck%contacts(k)%slave)//"'", "contact "//itoa(j)//" pairs the same master '"// &
            trim(deck%contacts(k)%master)//"' and slave already: its forces would be applied "// &
            "twice; give each pair once", err)
          return
        end if
      end do
    end do
  end subroutine check_across


  !> Scan the deck before gfortran reads it, so that every mistake is named by line, group
  !! and variable instead of by gfortran's "Cannot match namelist object name ...":
  !! - every group name and every variable name must be known (gfortran skips unknown groups
  !!   silently, and after an array it may blame the previous variable for a misspelt one);
  !!   the message gives the nearest valid name;
  !! - &run, &detection, &solver and &output at most once (gfortran reads only the first);
  !! - names and unquoted values in ASCII (a typographic quote is the usual culprit);
  !! - every value of the type of its variable (check_value): reals finite (gfortran takes
  !!   NaN, Infinity and 1e400 without a word), integers without a decimal point and in
  !!   range, strings quoted. Values of a variable whose type is not listed in var_type
  !!   still may not be NaN or Infinity.
  subroutine check_groups(deck, err)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    type(deck_scan_t) :: sc
    integer :: j
    sc%t = deck%text
    sc%n = len(sc%t)
    do while (sc%i <= sc%n)
      select case (sc%t(sc%i:sc%i))
      case (achar(10))
        sc%lineno = sc%lineno + 1
        sc%i = sc%i + 1
      case ("'", '"')
        call scan_quoted(deck, sc, err)
      case ('!')
        j = index(sc%t(sc%i:), achar(10))
        sc%i = merge(sc%n + 1, sc%i + j - 1, j == 0)
      case ('&')
        call scan_group_start(deck, sc, err)
      case ('/')
        if (sc%in_group) sc%last_end(sc%ig) = sc%lineno
        sc%in_group = .false.
        sc%i = sc%i + 1
      case (' ', ',', '=', achar(9), achar(13))
        sc%i = sc%i + 1
      case default
        if (sc%in_group) then
          call scan_word(deck, sc, err)
        else
          sc%i = sc%i + 1
        end if
      end select
      if (allocated(err)) return
    end do
  end subroutine check_groups

  !> A quoted string at t(i) (quotes included, a doubled quote inside it): its value
  !! checked when it is in a group; i moves past it.
  subroutine scan_quoted(deck, sc, err)
    type(deck_t), intent(in) :: deck
    type(deck_scan_t), intent(inout) :: sc
    type(error_t), allocatable, intent(inout) :: err
    integer :: j, line0
    character :: qc
    associate (t => sc%t, n => sc%n, i => sc%i)
      qc = t(i:i)
      line0 = sc%lineno
      j = i + 1
      do while (j <= n)
        if (t(j:j) == qc) then
          ! a doubled quote is a quote inside the string
          if (j == n) exit
          if (t(j + 1:j + 1) /= qc) exit
          j = j + 1
        else if (t(j:j) == achar(10)) then
          sc%lineno = sc%lineno + 1
        end if
        j = j + 1
      end do
      if (sc%in_group) then
        call check_value(deck, sc%lineno, sc%group, sc%gtext, sc%var, t(i:min(j, n)), &
          .true., err)
        if (.not. allocated(err)) call scan_count_values(deck, sc, t(i:min(j, n)), err)
      end if
      i = j + 1
    end associate
  end subroutine scan_quoted

  !> A group starts at t(i) ('&name'): known, not repeated unless it may be, and on a line
  !! of its own; i moves past the name.
  subroutine scan_group_start(deck, sc, err)
    type(deck_t), intent(in) :: deck
    type(deck_scan_t), intent(inout) :: sc
    type(error_t), allocatable, intent(inout) :: err
    integer :: j
    character(len=:), allocatable :: at
    associate (t => sc%t, n => sc%n, i => sc%i, ig => sc%ig, nth => sc%nth)
      at = "deck '"//deck%path//"' line "//itoa(sc%lineno)
      j = name_end(t, i + 1)
      if (j <= n) then
        if (is_non_ascii(t(j:j))) then
          call non_ascii_error(deck, sc%lineno, 'the group name', &
            t(i:name_end(t, j, .true.) - 1), err)
          return
        end if
      end if
      sc%group = lower(t(i + 1:j - 1))
      i = j
      sc%in_group = sc%group /= 'end'
      sc%var = ''
      if (.not. sc%in_group) return
      ! (gfortran 12's findloc does not pad a shorter character value)
      do ig = size(known_groups), 1, -1
        if (known_groups(ig) == sc%group) exit
      end do
      if (ig == 0) then
        call set_error(err, at//": unknown namelist group &"//sc%group//"; valid groups: "// &
          join_names(known_groups)//" (see doc/deck.md)")
        return
      end if
      nth(ig) = nth(ig) + 1
      if (nth(ig) == 1) sc%first(ig) = sc%lineno
      if (nth(ig) > 1 .and. .not. any(repeatable_groups == sc%group)) then
        call set_error(err, at//": group &"//sc%group//" is given a second time (first at "// &
          "line "//itoa(sc%first(ig))//"); give it once: only the first would be read "// &
          "(repeatable groups: "//join_names(repeatable_groups)//")")
      else if (nth(ig) > 1 .and. sc%last_end(ig) == sc%lineno) then
        ! gfortran reads on from the line after the one where a group ends
        call set_error(err, at//": group &"//sc%group//" "//itoa(nth(ig))//" starts on "// &
          "the line where &"//sc%group//" "//itoa(nth(ig) - 1)//" ends, and would be skipped; "// &
          "start each group on a new line")
      end if
      sc%gtext = ", group &"//sc%group
      if (any(repeatable_groups == sc%group)) sc%gtext = sc%gtext//' ('//sc%group//' '// &
        itoa(nth(ig))//')'
    end associate
  end subroutine scan_group_start

  !> In a group, at t(i): a variable (name [(subscript)] =), which must be known, or an
  !! unquoted value of the current variable, checked; i moves past it.
  subroutine scan_word(deck, sc, err)
    type(deck_t), intent(in) :: deck
    type(deck_scan_t), intent(inout) :: sc
    type(error_t), allocatable, intent(inout) :: err
    integer :: j, k
    associate (t => sc%t, n => sc%n, i => sc%i)
      j = name_end(t, i)
      if (is_name_start(t(i:i)) .and. j <= n) then
        if (is_non_ascii(t(j:j))) then
          call non_ascii_error(deck, sc%lineno, sc%gtext(3:)//': the variable name', &
            t(i:name_end(t, j, .true.) - 1), err)
          return
        end if
      end if
      k = after_subscript(t, j)
      if (is_name_start(t(i:i)) .and. k <= n) then
        if (t(k:k) == '=' .and. .not. is_value_word(lower(t(i:j - 1)))) then
          sc%var = lower(t(i:j - 1))
          sc%nvals = 0
          sc%subscripted = index(t(j:k), "(") > 0
          if (.not. var_known(sc%group, sc%var)) call set_error(err, "deck '"//deck%path// &
            "' line "//itoa(sc%lineno)//", group &"//sc%group//": unknown variable '"// &
            sc%var//"'"//nearest_hint(sc%group, sc%var)//"; variables of &"//sc%group// &
            ": "//group_vars(sc%group)//" (see doc/deck.md)")
          i = k + 1
          return
        end if
      end if
      ! an unquoted value: up to the next separator
      j = i
      do while (j <= n)
        if (index(" ,/!&'"""//achar(9)//achar(10)//achar(13), t(j:j)) > 0) exit
        j = j + 1
      end do
      if (any([(is_non_ascii(t(k:k)), k = i, j - 1)])) then
        call non_ascii_error(deck, sc%lineno, sc%gtext(3:)//', variable '//sc%var// &
          ': the value', t(i:j - 1), err)
        return
      end if
      call check_value(deck, sc%lineno, sc%group, sc%gtext, sc%var, t(i:j - 1), .false., &
        err)
      if (.not. allocated(err)) call scan_count_values(deck, sc, t(i:j - 1), err)
      i = j
    end associate
  end subroutine scan_word

  !> Count the values tok stands for (r*c: r of them) and refuse more than the variable
  !! holds, unless a subscript placed them (lo(2) = ...).
  subroutine scan_count_values(deck, sc, tok, err)
    type(deck_t), intent(in) :: deck
    type(deck_scan_t), intent(inout) :: sc
    character(len=*), intent(in) :: tok
    type(error_t), allocatable, intent(inout) :: err
    integer :: star, r, ios, nmax
    character(len=:), allocatable :: where
    r = 1
    star = index(tok, '*')
    if (star > 1) then
      read(tok(1:star - 1), *, iostat=ios) r
      if (ios /= 0) r = 1
    end if
    sc%nvals = sc%nvals + r
    nmax = var_size(sc%group, sc%var)
    if (sc%subscripted .or. nmax == 0 .or. sc%nvals <= nmax) return
    where = "deck '"//deck%path//"' line "//itoa(sc%lineno)//sc%gtext//", variable "//sc%var
    if (nmax == 1) then
      call set_error(err, where//": takes one value, and the deck gives more (the last "// &
        tok//"); remove the extra values, or the missing 'name =' before them")
    else
      call set_error(err, where//": takes at most "//itoa(nmax)//" values, and the deck "// &
        "gives "//itoa(sc%nvals)//"; remove the extra values")
    end if
  end subroutine scan_count_values

  !> One past the last name character from i (also past non-ASCII bytes when greedy).
  pure integer function name_end(t, i, greedy) result(j)
    character(len=*), intent(in) :: t
    integer, intent(in) :: i
    logical, intent(in), optional :: greedy
    logical :: g
    g = .false.
    if (present(greedy)) g = greedy
    j = i
    do while (j <= len(t))
      if (.not. (is_name_char(t(j:j)) .or. (g .and. is_non_ascii(t(j:j))))) exit
      j = j + 1
    end do
  end function name_end

  !> Position of the first non-blank after j, skipping one (subscript) if there is one.
  pure integer function after_subscript(t, j) result(k)
    character(len=*), intent(in) :: t
    integer, intent(in) :: j
    integer :: depth
    k = j
    do while (k <= len(t))
      if (t(k:k) /= ' ' .and. t(k:k) /= achar(9)) exit
      k = k + 1
    end do
    if (k > len(t)) return
    if (t(k:k) /= '(') return
    depth = 0
    do while (k <= len(t))
      if (t(k:k) == '(') depth = depth + 1
      if (t(k:k) == ')') depth = depth - 1
      k = k + 1
      if (depth == 0) exit
    end do
    do while (k <= len(t))
      if (t(k:k) /= ' ' .and. t(k:k) /= achar(9)) exit
      k = k + 1
    end do
  end function after_subscript

  subroutine non_ascii_error(deck, lineno, what, word, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: lineno
    character(len=*), intent(in) :: what, word
    type(error_t), allocatable, intent(inout) :: err
    call set_error(err, "deck '"//deck%path//"' line "//itoa(lineno)//": "//what//" '"// &
      word//"' holds a character outside ASCII; names are ASCII letters, digits and '_', "// &
      "strings are quoted with ' or "" (a typographic quote copied from a document is the "// &
      "usual culprit)")
  end subroutine non_ascii_error

  !> One value tok of variable var of group (at line lineno; gtext ", group &body (body 2)"),
  !! checked against the type of var; quoted says tok is a quoted string (quotes included).
  !! A repeat count (3*1.0) and null values (3*, or nothing between commas) are allowed, as
  !! gfortran reads them.
  subroutine check_value(deck, lineno, group, gtext, var, tok, quoted, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: lineno
    character(len=*), intent(in) :: group, gtext, var, tok
    logical, intent(in) :: quoted
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: v, expect, where
    character :: typ
    integer :: star, ios
    real(wp) :: x
    integer(i64) :: ix
    !> Reals from 10**max_magnitude on are refused (huge(1.0_wp) is 1.8e308).
    integer, parameter :: max_magnitude = range(1.0_wp) + 1
    character(len=*), parameter :: range_text = 'beyond the range of a real (1e308 and '// &
      'more); give a finite value in the units of the variable'
    where = "deck '"//deck%path//"' line "//itoa(lineno)//gtext
    if (len(var) == 0) then
      call set_error(err, where//": value "//tok//" without a variable; write name = value "// &
        "(variables of &"//group//": "//group_vars(group)//")")
      return
    end if
    typ = var_type(group, var)
    select case (typ)
    case ('r')
      expect = 'a real number (e.g. 1.0e-3)'
    case ('i')
      expect = 'an integer, without a decimal point (e.g. 2)'
    case ('l')
      expect = '.true. or .false.'
    case ('s')
      expect = "a quoted string: "//var//" = '"//tok//"'"
    case default
      expect = ''
    end select
    if (quoted) then
      if (typ /= 's' .and. typ /= ' ') call type_error('is a quoted string; '//var// &
        ' takes '//expect)
      ! gfortran would cut a longer string to the variable's length without a word (a long
      ! output path would then name another file)
      if (typ == 's' .and. string_length(group, var) > 0) then
        if (quoted_length(tok) > string_length(group, var)) then
          call type_error('longer than '//itoa(string_length(group, var))//' characters, '// &
            'the most '//var//' holds; give a shorter value (a path: a shorter or a '// &
            'relative one)')
          return
        end if
      end if
      ! the value as the reader keeps it: quotes off, a doubled quote one, blanks trimmed
      if (typ == 's') call valid_or_error(trim(unquoted(tok)), 0.0_wp)
      return
    end if
    ! an optional repeat count r*
    v = lower(tok)
    star = index(v, '*')
    if (star > 1) then
      if (verify(v(1:star - 1), '0123456789') == 0) v = v(star + 1:)
    end if
    if (len(v) == 0) return
    if (is_non_finite_word(v)) then
      call type_error('not a finite number; give a finite value (NaN and Infinity are '// &
        'not accepted)')
      return
    end if
    select case (typ)
    case ('r')
      if (verify(v, '0123456789.+-ed') /= 0 .or. scan(v, '0123456789') == 0) then
        call type_error('not a number; '//var//' takes '//expect)
        return
      end if
      ! a literal beyond the range is refused before it is read: reading it overflows
      if (decimal_magnitude(v) >= max_magnitude) then
        call type_error(range_text)
        return
      end if
      read(v, *, iostat=ios) x
      if (ios /= 0) then
        call type_error('not a number; '//var//' takes '//expect)
      else if (.not. ieee_is_finite(x)) then
        call type_error(range_text)
      else
        call valid_or_error(tok, x)
      end if
    case ('i')
      if (verify(v, '0123456789+-') /= 0 .or. scan(v, '0123456789') == 0) then
        call type_error('not an integer; '//var//' takes '//expect)
        return
      end if
      read(v, *, iostat=ios) ix
      if (ios /= 0 .or. abs(ix) > int(huge(1), i64)) then
        call type_error('outside the integer range (at most '//itoa(huge(1))//'); give a '// &
          'smaller count')
      else
        call valid_or_error(tok, real(ix, wp))
      end if
    case ('l')
      if (v(1:1) == '.') v = v(2:)
      if (len(v) == 0) then
        call type_error('not a logical; '//var//' takes '//expect)
      else if (v(1:1) /= 't' .and. v(1:1) /= 'f') then
        call type_error('not a logical; '//var//' takes '//expect)
      end if
    case ('s')
      call type_error('not quoted; '//var//' takes '//expect)
    case default
      ! a type not listed: only a number out of range is caught here
      if (verify(v, '0123456789.+-ed') == 0 .and. scan(v, '0123456789') > 0) then
        if (decimal_magnitude(v) >= max_magnitude) call type_error(range_text)
      end if
    end select
  contains
    subroutine type_error(why)
      character(len=*), intent(in) :: why
      call set_error(err, where//", variable "//var//" = "//tok//": "//why//" (see "// &
        "doc/deck.md)")
    end subroutine type_error
    !> The value (text t, number x) against what the variable's description allows.
    subroutine valid_or_error(t, x)
      character(len=*), intent(in) :: t
      real(wp), intent(in) :: x
      character(len=:), allocatable :: why
      why = value_fault(var_index(group, var), t, x)
      if (len(why) > 0) call type_error(why)
    end subroutine valid_or_error
  end subroutine check_value

  !> The text of the quoted string q: its quotes taken off, a doubled quote one.
  pure function unquoted(q) result(t)
    character(len=*), intent(in) :: q
    character(len=:), allocatable :: t
    integer :: j
    t = ''
    if (len(q) < 2) return
    j = 2
    do while (j < len(q))
      t = t//q(j:j)
      if (q(j:j) == q(1:1) .and. j + 1 < len(q)) then
        if (q(j + 1:j + 1) == q(1:1)) j = j + 1
      end if
      j = j + 1
    end do
  end function unquoted

  !> The characters of the quoted string q (its quotes taken off, a doubled quote one).
  pure integer function quoted_length(q) result(n)
    character(len=*), intent(in) :: q
    n = len(unquoted(q))
  end function quoted_length

  !> The decimal exponent of the leading digit of the real literal v (12.5e3: 4, 0.03: -2,
  !! 0: -huge), from its text alone; v holds digits, '.', an exponent letter e or d and
  !! signs (an optional leading one). Text that is no number gives some value; the read
  !! that follows refuses it.
  pure integer function decimal_magnitude(v) result(mag)
    character(len=*), intent(in) :: v
    character(len=:), allocatable :: w, mant, ipart, fpart
    integer :: e, dot, ios, k, ex
    w = v
    if (len(w) > 0) then
      if (w(1:1) == '+' .or. w(1:1) == '-') w = w(2:)
    end if
    e = scan(w, 'ed')
    mant = w
    ex = 0
    if (e > 0) then
      mant = w(1:e - 1)
      if (len(w) - e > 6) then
        ! more exponent digits than any real: its sign decides
        ex = merge(-1000000, 1000000, index(w(e + 1:), '-') > 0)
      else
        read(w(e + 1:), *, iostat=ios) ex
        if (ios /= 0) ex = 0
      end if
    end if
    dot = index(mant, '.')
    if (dot > 0) then
      ipart = mant(1:dot - 1)
      fpart = mant(dot + 1:)
    else
      ipart = mant
      fpart = ''
    end if
    k = verify(ipart, '0')
    if (k > 0) then
      mag = ex + (len(ipart) - k)
      return
    end if
    k = verify(fpart, '0')
    if (k == 0) then
      mag = -huge(1)
    else
      mag = ex - k
    end if
  end function decimal_magnitude

  !> NaN, Inf, Infinity with an optional sign, and NaN(...) as gfortran reads them.
  pure logical function is_non_finite_word(v)
    character(len=*), intent(in) :: v
    character(len=:), allocatable :: w
    w = v
    if (len(w) > 0) then
      if (w(1:1) == '+' .or. w(1:1) == '-') w = w(2:)
    end if
    is_non_finite_word = w == 'nan' .or. w == 'inf' .or. w == 'infinity' .or. &
      index(w, 'nan(') == 1
  end function is_non_finite_word

  pure logical function is_non_ascii(c)
    character, intent(in) :: c
    is_non_ascii = iachar(c) > 127 .or. iachar(c) < 0
  end function is_non_ascii

  pure logical function is_name_start(c)
    character, intent(in) :: c
    is_name_start = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z')
  end function is_name_start

  pure logical function is_name_char(c)
    character, intent(in) :: c
    is_name_char = is_name_start(c) .or. (c >= '0' .and. c <= '9') .or. c == '_'
  end function is_name_char

  !> Words that can stand before '=' but are values (none in mfcd's decks; kept explicit).
  pure logical function is_value_word(w)
    character(len=*), intent(in) :: w
    is_value_word = w == 'true' .or. w == 'false' .or. w == 't' .or. w == 'f'
  end function is_value_word

  pure logical function var_known(group, word)
    character(len=*), intent(in) :: group, word
    var_known = var_index(group, word) > 0
  end function var_known

  !> "; did you mean 'basis'?" for the valid name at the smallest edit distance (<= 3).
  pure function nearest_hint(group, word) result(hint)
    character(len=*), intent(in) :: group, word
    character(len=:), allocatable :: hint, best
    integer :: i, d, dbest
    hint = ''
    best = ''
    dbest = 4
    do i = 1, size(deck_vars)
      if (deck_vars(i)%group /= group) cycle
      d = edit_distance(trim(deck_vars(i)%name), word)
      if (d < dbest) then
        dbest = d
        best = trim(deck_vars(i)%name)
      end if
    end do
    if (len(best) > 0) hint = "; did you mean '"//best//"'?"
  end function nearest_hint

  subroutine read_run(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios
    character(len=512) :: msg
    include 'deck_nml_run.inc'
    include 'deck_default_run.inc'
    rewind(u)
    read(u, nml=run, iostat=ios, iomsg=msg)
    if (ios == iostat_end) then
      call set_error(err, "deck '"//deck%path//"': group &run is missing; add "// &
        "&run ndim = 2, mode = 'detect' / (see doc/deck.md)")
      return
    else if (ios /= 0) then
      call nml_error(deck, 'run', '', msg, err)
      return
    end if
    mode = lower(mode)
    geometry = lower(geometry)
    if (geometry == 'axisymmetric' .and. ndim /= 2) then
      call bad(deck, 'run', 'geometry', "'axisymmetric'", 'axisymmetric runs need ndim = 2', err)
    end if
    if (.not. allocated(err) .and. geometry == 'axisymmetric' .and. gravity(1) /= 0.0_wp) &
      call bad(deck, 'run', 'gravity', rtoa(gravity(1))//' (radial)', 'in axisymmetry '// &
      'gravity lies along the axis: give gravity = 0, g_z', err)
    if (.not. allocated(err) .and. any(gravity(ndim + 1:) /= 0.0_wp)) &
      call bad(deck, 'run', 'gravity', 'component '//itoa(ndim + 1), 'give ndim = '// &
      itoa(ndim)//' components', err)
    deck%run%title = title
    deck%run%mode = mode
    deck%run%ndim = ndim
    deck%run%geometry = geometry
    deck%run%gravity = gravity
  end subroutine read_run

  subroutine read_bodies(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, k
    character(len=512) :: msg
    type(body_spec_t) :: s, dflt
    type(body_spec_t), allocatable :: tmp(:)
    include 'deck_nml_body.inc'
    allocate(tmp(max_bodies))
    rewind(u)
    k = 0
    do
      include 'deck_default_body.inc'
      read(u, nml=body, iostat=ios, iomsg=msg)
      if (ios == iostat_end) exit
      k = k + 1
      if (ios /= 0) then
        call nml_error(deck, 'body', ' (body '//itoa(k)//')', msg, err)
        return
      end if
      if (k > max_bodies) then
        call set_error(err, "deck '"//deck%path//"': more than "//itoa(max_bodies)// &
          " &body groups; merge bodies or raise max_bodies in src/setup/deck_m.f90")
        return
      end if
      s = dflt
      s%name = name
      s%shape = lower(shape)
      s%lo = lo
      s%hi = hi
      s%n = n
      s%vertices = vertices
      s%nvert = count(vertices(1, :) /= unset .and. vertices(2, :) /= unset)
      s%spacing = spacing
      s%origin = origin
      s%center = center
      s%r_inner = r_inner
      s%r_outer = r_outer
      s%radius = radius
      s%extrude = extrude
      s%theta_start = theta_start
      s%theta_end = theta_end
      s%file = file
      s%kernel = lower(kernel)
      s%window = lower(window)
      s%basis = lower(basis)
      s%support_factor = support_factor
      s%role = lower(role)
      s%material = material
      s%velocity = velocity
      s%angular_velocity = angular_velocity
      s%translate = translate
      s%rotate = rotate
      s%integration = lower(integration)
      s%stabilization = stabilization
      s%discretization = lower(discretization)
      s%perturbation = perturbation
      s%perturbation_seed = perturbation_seed
      s%geo_names = geo_names
      s%geo_values = geo_values
      s%geo_time_limit = geo_time_limit
      s%geo_max_elements = geo_max_elements
      call check_body(deck, k, tmp(1:k - 1), s, err)
      if (allocated(err)) return
      tmp(k) = s
    end do
    if (k == 0) then
      call set_error(err, "deck '"//deck%path//"': no &body group; add at least one, e.g. "// &
        "&body name = 'block', shape = 'rectangle', lo = 0, 0, hi = 1, 1, n = 11, 11 /")
      return
    end if
    deck%nbodies = k
    deck%bodies = tmp(1:k)
  end subroutine read_bodies

  !> Body k against the deck and the bodies before it (prev).
  subroutine check_body(deck, k, prev, s, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(body_spec_t), intent(in) :: prev(:)
    type(body_spec_t), intent(inout) :: s
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: grp
    integer :: nd, j
    nd = deck%run%ndim
    grp = 'body'
    if (len_trim(s%name) == 0) s%name = 'body'//itoa(k)
    grp = "body (body "//itoa(k)//", '"//trim(s%name)//"')"
    do j = 1, size(prev)
      if (prev(j)%name == s%name) then
        call bad(deck, grp, 'name', "'"//trim(s%name)//"'", 'give every body its own name '// &
          '(body '//itoa(j)//' has it already; names key the output and &contact, &bc)', err)
        return
      end if
    end do
    ! (each value given is of its type and in its range already: check_value)
    if (s%angular_velocity /= 0.0_wp .and. (nd /= 2 .or. &
      deck%run%geometry /= 'plane' .or. s%role == 'rigid')) then
      call bad(deck, grp, 'angular_velocity', rtoa(s%angular_velocity), 'an initial '// &
        'spin is for a deformable body in plane strain (ndim = 2, geometry = ''plane''); '// &
        'give 0', err)
      return
    end if
    if (s%role == 'rigid' .and. deck%run%geometry == 'axisymmetric' .and. &
      s%velocity(1) /= 0.0_wp) then
      call bad(deck, grp, 'velocity', rtoa(s%velocity(1))//' (radial)', 'a rigid body of '// &
        'revolution moves along its axis only: give velocity = 0, vz', err)
      return
    end if
    if (s%rotate /= 0.0_wp .and. nd /= 2) then
      call bad(deck, grp, 'rotate', rtoa(s%rotate), 'a rotation is in the plane (ndim = '// &
        '2); give 0', err)
      return
    end if
    if (s%rotate /= 0.0_wp .and. deck%run%geometry == 'axisymmetric') then
      call bad(deck, grp, 'rotate', rtoa(s%rotate), 'a body of revolution keeps its axis: '// &
        'give 0 (translate moves it along the axis)', err)
      return
    end if
    if (deck%run%geometry == 'axisymmetric' .and. s%translate(1) /= 0.0_wp) then
      call bad(deck, grp, 'translate', rtoa(s%translate(1))//' (radial)', 'a body of '// &
        'revolution stays on its axis: give translate = 0, dz', err)
      return
    end if
    if (any(s%translate(nd + 1:) /= 0.0_wp)) then
      call bad(deck, grp, 'translate', 'component '//itoa(nd + 1), 'give ndim = '// &
        itoa(nd)//' components', err)
      return
    end if
    if (len_trim(s%shape) == 0) then
      call bad(deck, grp, 'shape', "''", 'give the shape, one of: '// &
        choices_text('body', 'shape'), err)
      return
    end if
    ! before the basis: a basis that does not exist in ndim is a symptom, the shape the cause
    if (s%shape == 'geo' .and. nd == 1) then
      call bad(deck, grp, 'shape', "'geo'", "a gmsh script is meshed in 2D (triangles) "// &
        "or 3D (tetrahedra): give &run ndim = 2 or 3 (this deck has ndim = 1)", err)
      return
    end if
    if (shape_ndim(s%shape) > 0 .and. shape_ndim(s%shape) /= nd) then
      call bad(deck, grp, 'shape', "'"//trim(s%shape)//"'", "a '"//trim(s%shape)// &
        "' needs &run ndim = "//itoa(shape_ndim(s%shape))//" (this deck has ndim = "// &
        itoa(nd)//"); use shape = 'file' for other dimensions", err)
      return
    end if
    call check_body_modes(deck, grp, s, err)
    if (allocated(err)) return
    s%kid = kernel_id(s%kernel)
    s%wshape = window_shape_id(s%window)
    s%bid = basis_id(s%basis, nd)
    if (s%bid == 0) then
      call bad(deck, grp, 'basis', "'"//trim(s%basis)//"'", 'use one of: '// &
        join_names(basis_names)//" that exists in ndim = "//itoa(nd)// &
        " (bilinear: 2D; trilinear: 3D; quadratic: 1D/2D; counterexample_1xy: 2D)", err)
      return
    end if
    if (s%support_factor(1) == unset) then
      ! 2 dx suits linear and multilinear bases; a quadratic basis needs three particles per
      ! direction at a corner, so rho > 2 dx (Theorem 3.1)
      s%support_factor = merge(2.5_wp, 2.0_wp, basis_order(s%bid) > 1)
    else
      do j = 2, 3
        if (s%support_factor(j) == unset) s%support_factor(j) = s%support_factor(j - 1)
      end do
    end if
    call check_body_shape(deck, grp, s, err)
    if (allocated(err)) return
    if (s%shape == 'geo') return
    if (any(s%geo_names /= '')) then
      call bad(deck, grp, 'geo_names', "'"//trim(s%geo_names(1))//"', ...", "gmsh parser "// &
        "numbers are read by shape = 'geo' only (this body: shape '"//trim(s%shape)// &
        "'); remove geo_names and geo_values", err)
    else if (any(s%geo_values /= unset)) then
      call bad(deck, grp, 'geo_values', rtoa(s%geo_values(1))//', ...', "gmsh parser "// &
        "numbers are read by shape = 'geo' only (this body: shape '"//trim(s%shape)// &
        "'); remove geo_values", err)
    else if (s%geo_time_limit /= unset) then
      call bad(deck, grp, 'geo_time_limit', rtoa(s%geo_time_limit), "the limits of "// &
        "meshing a gmsh script are read by shape = 'geo' only (this body: shape '"// &
        trim(s%shape)//"'); remove geo_time_limit", err)
    else if (s%geo_max_elements /= -1) then
      call bad(deck, grp, 'geo_max_elements', itoa(s%geo_max_elements), "the limits of "// &
        "meshing a gmsh script are read by shape = 'geo' only (this body: shape '"// &
        trim(s%shape)//"'); remove geo_max_elements", err)
    end if
  end subroutine check_body

  !> Body s (group text grp) against its discretization, role and the run's mode.
  subroutine check_body_modes(deck, grp, s, err)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: grp
    type(body_spec_t), intent(inout) :: s
    type(error_t), allocatable, intent(inout) :: err
    integer :: j, nd
    nd = deck%run%ndim
    if (s%discretization == 'fem' .and. nd == 3 .and. s%shape /= 'box' .and. &
      s%shape /= 'cylinder' .and. s%shape /= 'polygon' .and. s%shape /= 'geo' .and. &
      s%shape /= 'file') then
      call bad(deck, grp, 'discretization', "'fem'", "3D finite elements (linear "// &
        "tetrahedra with averaged nodal pressure) are generated on a 'box', a 'cylinder' "// &
        "or an extruded 'polygon', meshed from a gmsh script (shape = 'geo') or read "// &
        "from an HDF5 particle file with /mesh/tetrahedra (tools/mesh_body.py --3d); use "// &
        "discretization = 'rkpm' for shape '"//trim(s%shape)//"'", err)
      return
    end if
    if (s%discretization == 'fem' .and. nd /= 3 .and. ((s%shape /= 'rectangle' .and. &
      s%shape /= 'annulus_sector' .and. s%shape /= 'file' .and. s%shape /= 'geo') .or. &
      nd /= 2)) then
      call bad(deck, grp, 'discretization', "'fem'", "finite elements are generated on a "// &
        "'rectangle' or an 'annulus_sector' (CST4; n = nodes per direction: n - 1 boxes, "// &
        "n(2) around a full ring), meshed from a gmsh script (shape = 'geo') or read from "// &
        "an HDF5 particle file with /mesh/triangles (tools/mesh_body.py), in 2D; use "// &
        "discretization = 'rkpm' for shape '"// &
        trim(s%shape)//"'", err)
      return
    end if
    if (s%perturbation > 0.0_wp .and. (s%discretization /= 'rkpm' .or. nd /= 2 .or. &
      (s%shape /= 'rectangle' .and. s%shape /= 'polygon'))) then
      call bad(deck, grp, 'perturbation', rtoa(s%perturbation), "particles are moved off "// &
        "the lattice of an RKPM 'rectangle' or 'polygon' body only (this body: shape '"// &
        trim(s%shape)//"', discretization '"//trim(s%discretization)//"'); give "// &
        "perturbation = 0 here", err)
      return
    end if
    if (deck%run%mode == 'dynamic' .and. s%role == 'deformable' .and. &
      s%discretization == 'rkpm') then
      ! what the RKPM tables would refuse at set-up (rkpm_tl_m), named here
      ! (a 'file' body brings its cells, or the body set-up says it has none)
      if (nd == 3 .and. s%shape /= 'box' .and. s%shape /= 'polygon' .and. &
        s%shape /= 'cylinder' .and. s%shape /= 'geo' .and. s%shape /= 'file') then
        call bad(deck, grp, 'shape', "'"//trim(s%shape)//"'", "a deformable 3D RKPM body "// &
          "is integrated over the prism cells of an extruded body or the median-dual "// &
          "cells of a tetrahedral mesh: use shape = 'box', 'cylinder', 'polygon' (with "// &
          "extrude), 'geo' or 'file' (an HDF5 file with /mesh/tetrahedra, "// &
          "tools/mesh_body.py --3d)", err)
        return
      end if
      if (nd == 2 .and. s%integration /= 'direct' .and. s%shape /= 'rectangle' .and. &
        s%shape /= 'polygon' .and. s%shape /= 'disk' .and. s%shape /= 'file' .and. &
        s%shape /= 'geo') then
        call bad(deck, grp, 'integration', "'"//trim(s%integration)//"'", trim(s%integration)// &
          " integrates over the cells of a 'rectangle', 'polygon' or 'disk' body, of a "// &
          "gmsh mesh (shape = 'geo') or of a particle file that carries them (/cells, "// &
          "tools/mesh_body.py), and shape '"//trim(s%shape)//"' has none; use shape = "// &
          "'rectangle', 'polygon', 'disk', 'geo' or 'file' (or integration = 'direct', a "// &
          "negative control, in plane strain)", err)
        return
      end if
      if (s%integration == 'direct' .and. deck%run%geometry == 'axisymmetric') then
        call bad(deck, grp, 'integration', "'direct'", "direct nodal integration is a "// &
          "plane-strain negative control only; use integration = 'scni' (the default) or "// &
          "'gauss' in an axisymmetric run", err)
        return
      end if
    end if
    if (deck%run%mode == 'dynamic' .and. s%role == 'deformable') then
      s%imat = 0
      do j = 1, deck%nmaterials
        if (deck%materials(j)%name == s%material) s%imat = j
      end do
      if (s%imat == 0) then
        if (deck%nmaterials == 0) then
          call bad(deck, grp, 'material', "'"//trim(s%material)//"'", 'a deformable body '// &
            "needs a material: add a &material group (name = 'steel', model = "// &
            "'viscoplastic', ...) and give its name here", err)
        else
          call bad(deck, grp, 'material', "'"//trim(s%material)//"'", 'name one of the '// &
            '&material groups: '//join_names(deck%materials(1:deck%nmaterials)%name), err)
        end if
        return
      end if
    end if
  end subroutine check_body_modes

  !> Body s (group text grp): the variables its shape needs, given and consistent.
  subroutine check_body_shape(deck, grp, s, err)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: grp
    type(body_spec_t), intent(inout) :: s
    type(error_t), allocatable, intent(inout) :: err
    integer :: j, nd, e1, e2
    logical :: exists
    nd = deck%run%ndim
    select case (s%shape)
    case ('segment')
      if (s%lo(1) == unset .or. s%hi(1) == unset .or. .not. s%hi(1) > s%lo(1)) then
        call bad(deck, grp, 'lo/hi', 'missing or hi <= lo', 'give lo = a, hi = b with b > a', err)
      else if (s%n(1) < 2 .or. s%n(1) > 10000000) then
        call bad(deck, grp, 'n', itoa(s%n(1)), 'give n = number of particles, 2 .. 1e7', err)
      end if
    case ('box')
      if (any(s%lo(1:3) == unset) .or. any(s%hi(1:3) == unset) .or. &
        any(.not. s%hi(1:3) > s%lo(1:3))) then
        call bad(deck, grp, 'lo/hi', 'missing or hi <= lo', 'give lo = x0, y0, z0 and '// &
          'hi = x1, y1, z1 with x1 > x0, y1 > y0 and z1 > z0', err)
      else if (any(s%n(1:3) < 2) .or. int(s%n(1), i64)*s%n(2)*s%n(3) > max_lattice) then
        call bad(deck, grp, 'n', itoa(s%n(1))//', '//itoa(s%n(2))//', '//itoa(s%n(3)), &
          'give n = nx, ny, nz with each >= 2 (at most 5e7 particles)', err)
      end if
    case ('rectangle')
      if (any(s%lo(1:2) == unset) .or. any(s%hi(1:2) == unset) .or. &
        any(.not. s%hi(1:2) > s%lo(1:2))) then
        call bad(deck, grp, 'lo/hi', 'missing or hi <= lo', &
          'give lo = x0, y0 and hi = x1, y1 with x1 > x0 and y1 > y0', err)
      else if (any(s%n(1:2) < 2) .or. int(s%n(1), i64)*s%n(2) > max_lattice) then
        call bad(deck, grp, 'n', itoa(s%n(1))//', '//itoa(s%n(2)), &
          'give n = nx, ny with nx, ny >= 2 (at most 5e7 particles)', err)
      end if
    case ('polygon')
      if (nd /= 2 .and. nd /= 3) then
        call bad(deck, grp, 'shape', "'polygon'", "a polygon needs &run ndim = 2 (or 3, "// &
          "extruded along z); use shape = 'file' for other dimensions", err)
      else if (nd == 3 .and. (any(s%extrude == unset) .or. .not. s%extrude(2) > &
        s%extrude(1))) then
        call bad(deck, grp, 'extrude', 'missing or z1 <= z0', 'in 3D a polygon (in x, y) '// &
          'is extruded along z: give extrude = z0, z1 with z1 > z0 (m) and spacing = dx, '// &
          'dy, dz', err)
      else if (nd == 2 .and. any(s%extrude /= unset)) then
        call bad(deck, grp, 'extrude', 'given in 2D', 'extrude is for a 3D polygon '// &
          '(ndim = 3); leave it out', err)
      else if (s%nvert < 3) then
        call bad(deck, grp, 'vertices', itoa(s%nvert)//' vertices', &
          'give at least 3 vertices: vertices = x1, y1, x2, y2, x3, y3, ...', err)
      else if (any(s%spacing(1:nd) == unset) .or. any(s%spacing(1:nd) <= 0.0_wp)) then
        call bad(deck, grp, 'spacing', 'missing or <= 0', 'give spacing = dx, dy'// &
          trim(merge(', dz', '    ', nd == 3))//' > 0 (m)', err)
      else if (any(s%vertices(:, 1:s%nvert) == unset)) then
        call bad(deck, grp, 'vertices', itoa(count(s%vertices(:, 1:s%nvert) /= unset))// &
          ' values', 'give every vertex both coordinates, in order: vertices = x1, y1, '// &
          'x2, y2, ... (no gaps)', err)
      else
        call polygon_crossing(s%vertices, s%nvert, e1, e2)
        if (e1 > 0 .and. e1 == e2) then
          call bad(deck, grp, 'vertices', 'vertex '//itoa(e1)//' = vertex '// &
            itoa(merge(1, e1 + 1, e1 == s%nvert)), 'remove the repeated vertex (the '// &
            'polygon closes itself: do not repeat the first vertex at the end)', err)
        else if (e1 > 0) then
          call bad(deck, grp, 'vertices', 'edges '//itoa(e1)//' and '//itoa(e2)//' meet', &
            'the outline crosses or touches itself (edge k joins vertex k to k + 1); give '// &
            'the vertices of one simple polygon in order around it', err)
        else if (product((maxval(s%vertices(:, 1:s%nvert), dim=2) - &
          minval(s%vertices(:, 1:s%nvert), dim=2))/s%spacing(1:2) + 1.0_wp)* &
          merge((s%extrude(2) - s%extrude(1))/s%spacing(3) + 1.0_wp, 1.0_wp, nd == 3) > &
          real(max_lattice, wp)) then
          call bad(deck, grp, 'spacing', rtoa(s%spacing(1))//', '//rtoa(s%spacing(2)), &
            'the lattice over the polygon would have more than 5e7 points; give a '// &
            'coarser spacing', err)
        end if
      end if
      if (.not. allocated(err) .and. s%origin(1) == unset) s%origin = s%vertices(:, 1)
    case ('annulus_sector')
      if (.not. (s%r_outer > s%r_inner .and. s%r_inner >= 0.0_wp)) then
        call bad(deck, grp, 'r_inner/r_outer', rtoa(s%r_inner)//', '//rtoa(s%r_outer), &
          'give 0 < r_inner < r_outer (m)', err)
      else if (s%r_inner == 0.0_wp) then
        call bad(deck, grp, 'r_inner', '0', 'the polar lattice would put all n_angular '// &
          'particles of its first ring on the centre, one on top of the other; give a '// &
          "small hole (r_inner > 0, e.g. half the radial spacing), or make a full disc "// &
          "with shape = 'disk' (center, radius, spacing)", err)
      else if (.not. (s%theta_end > s%theta_start .and. &
        s%theta_end - s%theta_start <= 360.0_wp)) then
        call bad(deck, grp, 'theta_start/theta_end', rtoa(s%theta_start)//', '// &
          rtoa(s%theta_end), 'give theta_start < theta_end <= theta_start + 360 (degrees)', err)
      else if (any(s%n(1:2) < 2) .or. int(s%n(1), i64)*s%n(2) > max_lattice) then
        call bad(deck, grp, 'n', itoa(s%n(1))//', '//itoa(s%n(2)), &
          'give n = n_radial, n_angular, both >= 2 (at most 5e7 particles)', err)
      end if
    case ('cylinder')
      if (.not. (s%radius > 0.0_wp)) then
        call bad(deck, grp, 'radius', rtoa(s%radius), 'give the cylinder''s radius > 0 (m), '// &
          'about center (its axis along z)', err)
      else if (any(s%extrude == unset) .or. .not. s%extrude(2) > s%extrude(1)) then
        call bad(deck, grp, 'extrude', 'missing or z1 <= z0', 'give extrude = z0, z1 with '// &
          'z1 > z0 (m): the cylinder''s ends', err)
      else if (s%spacing(1) == unset .or. .not. (s%spacing(1) > 0.0_wp)) then
        call bad(deck, grp, 'spacing', 'missing or <= 0', 'give spacing = h > 0 (m): the '// &
          'distance between the rings of particles (and, unless a third value dz is given, '// &
          'between the layers)', err)
      else if (s%spacing(2) /= unset) then
        call bad(deck, grp, 'spacing', 'a second value', 'a cylinder''s rings have one '// &
          'spacing: give spacing = h, or h with the layers'' dz as the third value '// &
          '(spacing(3) = dz)', err)
      else if (s%radius/s%spacing(1) > 2.0e4_wp) then
        call bad(deck, grp, 'spacing', rtoa(s%spacing(1)), 'the cylinder''s disk would '// &
          'have more than about 1.3e9 particles; give a coarser spacing', err)
      end if
      if (.not. allocated(err) .and. s%spacing(3) == unset) s%spacing(3) = s%spacing(1)
      if (.not. allocated(err) .and. .not. (s%spacing(3) > 0.0_wp)) call bad(deck, grp, &
        'spacing', rtoa(s%spacing(3)), 'give a positive layer spacing dz (m)', err)
    case ('disk')
      if (.not. (s%radius > 0.0_wp)) then
        call bad(deck, grp, 'radius', rtoa(s%radius), 'give the disk''s radius > 0 (m), '// &
          'about center', err)
      else if (s%spacing(1) == unset .or. .not. (s%spacing(1) > 0.0_wp)) then
        call bad(deck, grp, 'spacing', 'missing or <= 0', 'give spacing = h > 0 (m): the '// &
          'distance between the rings of particles (and along each ring)', err)
      else if (s%radius/s%spacing(1) > 2.0e4_wp) then
        call bad(deck, grp, 'spacing', rtoa(s%spacing(1)), 'the disk would have more than '// &
          'about 1.3e9 particles; give a coarser spacing', err)
      else if (any(s%spacing(2:) /= unset)) then
        call bad(deck, grp, 'spacing', 'more than one value', 'a disk has one spacing '// &
          '(rings and particles along them alike): give spacing = h', err)
      end if
    case ('file', 'geo')
      do j = 2, 3
        if (s%spacing(j) == unset) s%spacing(j) = s%spacing(j - 1)
      end do
      if (s%spacing(1) /= unset .and. any(s%spacing(1:nd) <= 0.0_wp)) then
        call bad(deck, grp, 'spacing', rtoa(minval(s%spacing(1:nd))), 'give a positive '// &
          'particle spacing (m), or leave it out to use the cube root of the mean volume', err)
        return
      end if
      inquire(file=trim(s%file), exist=exists)
      if (s%shape == 'geo') then
        call check_geo(deck, grp, s, exists, err)
      else if (len_trim(s%file) == 0 .or. .not. exists) then
        call bad(deck, grp, 'file', "'"//trim(s%file)//"'", 'give the path of an existing '// &
          'particle file (HDF5 .h5 or plain columns; see doc/deck.md)', err)
      else if (is_dir(trim(s%file))) then
        call bad(deck, grp, 'file', "'"//trim(s%file)//"'", 'this is a directory; give '// &
          'the path of a particle file in it (HDF5 .h5 or plain columns)', err)
      end if
    end select
    ! a disk's or a cylinder's sector: a half or a quarter from angle 0 (symmetry planes)
    if (.not. allocated(err) .and. (s%shape == 'disk' .or. s%shape == 'cylinder') .and. &
      (s%theta_start /= 0.0_wp .or. .not. any(s%theta_end == [90.0_wp, 180.0_wp, 360.0_wp]))) &
      call bad(deck, grp, 'theta_start/theta_end', rtoa(s%theta_start)//', '// &
      rtoa(s%theta_end), "a "//trim(s%shape)//" is whole (0, 360) or a sector from 0 "// &
      "to 90 or 180 degrees (its straight sides on the axes through center, for symmetry "// &
      "planes)", err)
  end subroutine check_body_shape

  !> A shape = 'geo' body: file names a plain gmsh script (.geo) of at most geo_max_bytes,
  !! read once here; the parser numbers are pairs geo_names(k) = geo_values(k) given in a
  !! row, each name a gmsh name given once (the values are finite reals: check_groups saw
  !! to that); the script is in the subset mfcd reads and reads every number the deck
  !! gives (geo_script_m), and its sizes do not already ask for more than geo_max_elements
  !! triangles. Its model is kept in s%geo: set-up meshes exactly what was checked.
  subroutine check_geo(deck, grp, s, exists, err)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: grp
    type(body_spec_t), intent(inout) :: s
    logical, intent(in) :: exists
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: text, name, problem, msg, where, path, which, numbers
    integer :: nn, nv, k, j
    real(wp) :: nmin
    path = trim(s%file)
    if (len(path) == 0) then
      call bad(deck, grp, 'file', "''", "give the path of a gmsh geometry script (.geo), "// &
        "e.g. file = 'input/hertz_sphere.geo'", err)
      return
    else if (.not. exists) then
      call bad(deck, grp, 'file', "'"//path//"'", "no such file: give the path of "// &
        "a gmsh geometry script (.geo), relative to where mfcd runs", err)
      return
    end if
    if (len(path) < 5) then
      name = ''
    else
      name = path(len(path) - 3:)
    end if
    if (name /= '.geo') then
      call bad(deck, grp, 'file', "'"//path//"'", "mfcd meshes gmsh scripts named *.geo "// &
        "only (and never reads another file as one, so no other file's words reach a "// &
        "message): give the script's path, ending in .geo", err)
      return
    end if
    if (s%geo_time_limit == unset) s%geo_time_limit = default_geo_time_limit
    if (s%geo_max_elements == -1) s%geo_max_elements = default_geo_max_elements
    if (s%geo_time_limit <= 0.0_wp .or. s%geo_time_limit > 86400.0_wp) then
      call bad(deck, grp, 'geo_time_limit', rtoa(s%geo_time_limit), "give the longest "// &
        "time meshing the script may take, in seconds, above 0 and at most a day (86400)", err)
      return
    end if
    if (s%geo_max_elements < 1) then
      call bad(deck, grp, 'geo_max_elements', itoa(s%geo_max_elements), "give the most "// &
        "elements (triangles, or tetrahedra in 3D) the mesh may have, at least 1 (the "// &
        "default is "// &
        itoa(default_geo_max_elements)//")", err)
      return
    end if
    call read_plain_file(path, geo_max_bytes, text, problem)
    if (len(problem) > 0) then
      call bad(deck, grp, 'file', "'"//path//"'", "the gmsh script "//problem//"; give "// &
        "the path of a plain text .geo file itself (mfcd follows no link to a script) of "// &
        "at most "//itoa(geo_max_bytes)//" bytes", err)
      return
    end if
    nn = 0
    nv = 0
    do k = 1, max_geo_numbers
      if (s%geo_names(k) /= '') nn = k
      if (s%geo_values(k) /= unset) nv = k
    end do
    do k = 1, nn
      if (s%geo_names(k) == '') then
        call bad(deck, grp, 'geo_names', "entry "//itoa(k)//" empty", "give the names in a "// &
          "row, geo_names = 'a', 'b', ... (no empty entry before the last)", err)
        return
      end if
    end do
    do k = 1, nv
      if (s%geo_values(k) == unset) then
        call bad(deck, grp, 'geo_values', "entry "//itoa(k)//" unset", "give the values "// &
          "in a row, geo_values = 1.0e-3, 0.4e-3, ... (no gap before the last)", err)
        return
      end if
    end do
    if (nv /= nn) then
      call bad(deck, grp, 'geo_values', itoa(nv)//" value(s)", "geo_names gives "// &
        itoa(nn)//" name(s); give one value per name, in the same order (geo_names = "// &
        "'hc', 'a' with geo_values = 0.1e-3, 0.4e-3 sets hc = 0.1e-3 and a = 0.4e-3)", err)
      return
    end if
    do k = 1, nn
      name = trim(adjustl(s%geo_names(k)))
      if (.not. is_geo_name(name)) then
        call bad(deck, grp, 'geo_names', "'"//trim(s%geo_names(k))//"'", "not a gmsh parser "// &
          "name: give letters, digits and '_', starting with a letter or '_' (the name the "// &
          "script uses, e.g. 'hc')", err)
        return
      end if
      s%geo_names(k) = name
      do j = 1, k - 1
        if (s%geo_names(j) == name) then
          call bad(deck, grp, 'geo_names', "'"//name//"'", "given twice (entries "// &
            itoa(j)//" and "//itoa(k)//"); give each parser number once", err)
          return
        end if
      end do
    end do
    call geo_parse(text, s%geo_names(1:nn), s%geo_values(1:nn), s%geo, msg, where, which)
    if (len(msg) > 0) then
      if (where == 'geo_names') then
        ! "..., line 3: sets 'h' before ..." or "... never uses a number 'h' ..."
        if (index(msg, 'line ') == 1) then
          msg = ', '//msg
        else
          msg = ' '//msg
        end if
        call bad(deck, grp, 'geo_names', "'"//which//"'", "the gmsh script '"//path// &
          "'"//msg//"; fix geo_names or the script", err)
      else if (nn > 0) then
        numbers = ''
        do k = 1, nn
          if (k > 1) numbers = numbers//', '
          numbers = numbers//trim(s%geo_names(k))//' = '//rtoa(s%geo_values(k))
        end do
        call bad(deck, grp, 'file', "'"//path//"'", msg//" (with "//numbers// &
          " from geo_names, geo_values); fix the script or the numbers", err)
      else
        call bad(deck, grp, 'file', "'"//path//"'", msg//"; fix the script", err)
      end if
      return
    end if
    nmin = geo_min_triangles(s%geo)
    if (deck%run%ndim == 3) then
      ! the plane surfaces' triangles bound the volume's boundary, each a face of one
      ! tetrahedron, and a tetrahedron has four faces
      nmin = 0.25_wp*nmin
      if (nmin > real(s%geo_max_elements, wp)) then
        call bad(deck, grp, 'geo_max_elements', itoa(s%geo_max_elements), "the sizes of "// &
          "the gmsh script '"//path//"' ask for at least about "//rtoa(nmin)// &
          " tetrahedra (the plane surfaces' area over the square of an upper bound of "// &
          "the mesh size, a quarter of that: each face of the boundary is a face of one "// &
          "tetrahedron): give the script larger mesh sizes, or raise geo_max_elements "// &
          "if a mesh that large is meant", err)
        return
      end if
    else if (nmin > real(s%geo_max_elements, wp)) then
      call bad(deck, grp, 'geo_max_elements', itoa(s%geo_max_elements), "the sizes of "// &
        "the gmsh script '"//path//"' ask for at least about "//rtoa(nmin)//" triangles "// &
        "(an area over the square of an upper bound of the mesh size; gmsh makes about "// &
        "2.3 times that): give the script larger mesh sizes, or raise geo_max_elements "// &
        "if a mesh that large is meant", err)
      return
    end if
    s%ngeo = nn
  end subroutine check_geo

  !> A gmsh parser name: a letter or '_', then letters, digits and '_'.
  pure logical function is_geo_name(w)
    character(len=*), intent(in) :: w
    integer :: i
    is_geo_name = len(w) > 0
    if (.not. is_geo_name) return
    is_geo_name = is_name_start(w(1:1)) .or. w(1:1) == '_'
    do i = 2, len(w)
      if (.not. is_name_char(w(i:i))) is_geo_name = .false.
    end do
  end function is_geo_name

  subroutine read_detection(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, nd, j, nset
    character(len=512) :: msg
    type(detection_spec_t) :: d
    include 'deck_nml_detection.inc'
    include 'deck_default_detection.inc'
    rewind(u)
    read(u, nml=detection, iostat=ios, iomsg=msg)
    d%body = body
    d%eps_cr = eps_cr
    d%eps_rel = eps_rel
    d%line_from = line_from
    d%line_to = line_to
    d%line_n = line_n
    d%grid_lo = grid_lo
    d%grid_hi = grid_hi
    d%grid_n = grid_n
    deck%detection = d
    if (ios == iostat_end) then
      if (deck%run%mode == 'detect') call set_error(err, "deck '"//deck%path// &
        "': mode = 'detect' needs a &detection group (see doc/deck.md)")
      return
    else if (ios /= 0) then
      call nml_error(deck, 'detection', '', msg, err)
      return
    end if
    nd = deck%run%ndim
    d%present = .true.
    ! points are consecutive ndim-tuples: points = x1, y1, x2, y2, ...
    nset = 0
    do j = 1, size(points)
      if (points(j) /= unset) nset = j
    end do
    if (mod(nset, nd) /= 0 .or. any(points(1:nset) == unset)) then
      call bad(deck, 'detection', 'points', itoa(nset)//' values', &
        'give whole points: ndim coordinates each, points = x1, y1, x2, y2, ...', err)
      return
    end if
    d%npoints = nset/nd
    if (d%npoints > max_points) then
      call bad(deck, 'detection', 'points', itoa(d%npoints)//' points', 'give at most '// &
        itoa(max_points)//' points (use line_n or grid_n for more)', err)
      return
    end if
    do j = 1, d%npoints
      d%points(1:nd, j) = points((j - 1)*nd + 1:j*nd)
    end do
    if (len_trim(body) == 0) body = deck%bodies(1)%name
    d%body = body
    if (.not. any(deck%bodies%name == body)) then
      call bad(deck, 'detection', 'body', "'"//trim(body)//"'", 'name one of the bodies: '// &
        join_names(deck%bodies%name), err)
    else if (line_n /= 0 .and. (line_n < 2 .or. any(line_from(1:nd) == unset) .or. &
      any(line_to(1:nd) == unset))) then
      call bad(deck, 'detection', 'line_n/line_from/line_to', itoa(line_n), &
        'give line_n >= 2 and both end points (ndim coordinates each), or line_n = 0', err)
    else if (any(grid_n(1:nd) /= 0) .and. (any(grid_n(1:nd) < 1) .or. &
      count(grid_n(1:nd) >= 2) < min(2, nd) .or. &
      any(grid_lo(1:nd) == unset) .or. any(grid_hi(1:nd) == unset))) then
      call bad(deck, 'detection', 'grid_n/grid_lo/grid_hi', itoa(grid_n(1)), &
        'give grid_n >= 2 in every direction (or 1 in one direction of a 3D grid, a plane '// &
        'where grid_lo = grid_hi) with grid_lo and grid_hi, or leave grid_n = 0', err)
    else if (any(grid_n(1:nd) /= 0) .and. any(grid_n(1:nd) >= 2 .and. &
      .not. grid_hi(1:nd) > grid_lo(1:nd))) then
      call bad(deck, 'detection', 'grid_hi', 'not above grid_lo', &
        'give grid_hi > grid_lo in every direction with grid_n >= 2', err)
    else if (any(grid_n(1:nd) == 1 .and. grid_hi(1:nd) /= grid_lo(1:nd))) then
      call bad(deck, 'detection', 'grid_hi', 'differs from grid_lo where grid_n = 1', &
        'a direction with one grid point is a plane: give grid_lo = grid_hi there', err)
    else if (product(int(max(grid_n(1:nd), 1), i64)) > max_queries) then
      call bad(deck, 'detection', 'grid_n', 'more than 1e8 points', &
        'use a coarser grid (memory)', err)
    else if (line_n == 0 .and. all(grid_n(1:nd) == 0) .and. d%npoints == 0) then
      call bad(deck, 'detection', 'line_n/grid_n/points', 'nothing to evaluate', &
        'give a query line (line_n), a grid (grid_n) or points', err)
    end if
    deck%detection = d
  end subroutine read_detection

  subroutine read_materials(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, k, j
    character(len=512) :: msg
    type(material_spec_t) :: tmp(max_materials)
    type(error_t), allocatable :: e2
    include 'deck_nml_material.inc'
    rewind(u)
    k = 0
    do
      include 'deck_default_material.inc'
      read(u, nml=material, iostat=ios, iomsg=msg)
      if (ios == iostat_end) exit
      k = k + 1
      if (ios /= 0) then
        call nml_error(deck, 'material', ' (material '//itoa(k)//')', msg, err)
        return
      end if
      if (k > max_materials) then
        call set_error(err, "deck '"//deck%path//"': more than "//itoa(max_materials)// &
          " &material groups")
        return
      end if
      if (len_trim(name) == 0) name = 'material'//itoa(k)
      do j = 1, k - 1
        if (tmp(j)%name == name) then
          call bad(deck, 'material', 'name', "'"//trim(name)//"'", &
            'give every material its own name', err)
          return
        end if
      end do
      tmp(k)%name = name
      tmp(k)%params%model = lower(model)
      tmp(k)%preset = lower(preset)
      ! the group's constants in the order of material_constant_names
      call material_constants(deck, k, tmp(k), [density, youngs_modulus, poisson_ratio, &
        sigma0, hardening_n, rate_m, eps0, eps1, epsdot0, back_stress_b, theta, &
        yield_stress, hardening_modulus], err)
      if (allocated(err)) return
      call check_material_params(tmp(k)%params, e2)
      if (allocated(e2)) then
        call set_error(err, "deck '"//deck%path//"', group &material (material "//itoa(k)// &
          ", '"//trim(name)//"'): "//e2%message)
        return
      end if
    end do
    deck%nmaterials = k
    deck%materials = tmp(1:k)
  end subroutine read_materials

  !> Material k's constants from the values its group gave (given(j) = unset: left out),
  !! in the order of material_constant_names: a constant of the model is the group's, or
  !! the preset's when the group names one, or, for b and theta only (model_default),
  !! material_params_t's; any other constant the model uses is missing (an error naming
  !! it), and a constant the model does not use is an error too. m%source records where
  !! each came from (the log and /materials show it).
  subroutine material_constants(deck, k, m, given, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(material_spec_t), intent(inout) :: m
    real(wp), intent(in) :: given(:)
    type(error_t), allocatable, intent(inout) :: err
    type(material_params_t) :: ref
    character(len=:), allocatable :: grp, model, uses, c, ut
    integer :: j
    grp = "material (material "//itoa(k)//", '"//trim(m%name)//"')"
    model = trim(m%params%model)
    if (len_trim(m%preset) > 0 .and. .not. any(material_presets == m%preset)) then
      call bad(deck, grp, 'preset', "'"//trim(m%preset)//"'", 'use one of: '// &
        join_names(material_presets)//' (or give every constant of the model)', err)
      return
    end if
    if (.not. any(material_names == model)) return   ! check_material_params says so
    uses = join_names(pack(material_constant_names, [(model_uses(model, j), j = 1, &
      size(material_constant_names))]))
    m%source = ''
    do j = 1, size(material_constant_names)
      if (model_uses(model, j) .or. given(j) == unset) cycle
      call bad(deck, grp, trim(material_constant_names(j)), rtoa(given(j)), &
        "not a constant of model '"//model//"' (its constants: "//uses//"); remove it, "// &
        "or choose the model it belongs to (doc/materials.md)", err)
      return
    end do
    do j = 1, size(material_constant_names)
      c = trim(material_constant_names(j))
      if (.not. model_uses(model, j)) then
        cycle
      else if (given(j) /= unset) then
        call set_material_constant(m%params, j, given(j))
        m%source(j) = 'given'
      else if (len_trim(m%preset) > 0) then
        call set_material_constant(m%params, j, material_constant(ref, j))
        m%source(j) = 'preset'
      else if (model_default(j)) then
        call set_material_constant(m%params, j, material_constant(ref, j))
        m%source(j) = 'default'
      else
        ut = ''
        if (material_constant_units(j) /= '-') ut = ', in '//trim(material_constant_units(j))
        call bad(deck, grp, c, '(missing)', "model '"//model//"' needs it ("// &
          trim(material_constant_meaning(j))//ut//"); give it, or preset = 'paper_steel' "// &
          "for the paper's steel ("//c//' = '//rtoa(material_constant(ref, j))// &
          '); every constant of the model is given or preset, none is assumed', err)
        return
      end if
    end do
  end subroutine material_constants

  subroutine read_solver(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, j, jp
    character(len=512) :: msg
    type(solver_spec_t) :: sv
    include 'deck_nml_solver.inc'
    include 'deck_default_solver.inc'
    rewind(u)
    read(u, nml=solver, iostat=ios, iomsg=msg)
    sv%t_end = t_end
    sv%dt = dt
    sv%cfl = cfl
    sv%log_every = log_every
    sv%history_every = history_every
    sv%energy_tol = energy_tol
    sv%max_steps = max_steps
    sv%skip_quiet = skip_quiet
    sv%subcycle = subcycle
    sv%snapshot_times = unset
    deck%solver = sv
    if (ios == iostat_end) then
      if (deck%run%mode == 'dynamic') call set_error(err, "deck '"//deck%path// &
        "': mode = 'dynamic' needs a &solver group with t_end (see doc/deck.md)")
      return
    else if (ios /= 0) then
      call nml_error(deck, 'solver', '', msg, err)
      return
    end if
    sv%nsnap = 0
    do j = 1, max_snapshots
      if (snapshot_times(j) /= unset) sv%nsnap = j
    end do
    sv%snapshot_times(1:sv%nsnap) = snapshot_times(1:sv%nsnap)
    ! (each value given is in its range already: check_value)
    if (.not. (t_end > 0.0_wp)) then
      call bad(deck, 'solver', 't_end', rtoa(t_end), 'give the end time in s (> 0)', err)
    else if (dt > t_end) then
      call bad(deck, 'solver', 'dt', rtoa(dt), 'give 0 (automatic: cfl x critical step) '// &
        'or a fixed step in (0, t_end] s', err)
    else
      ! the first entry that is missing (a gap in the list), outside [0, t_end] or not
      ! after the one before, by its number and value
      do j = 1, sv%nsnap
        if (snapshot_times(j) == unset) then
          call bad(deck, 'solver', 'snapshot_times', 'entry '//itoa(j)//' missing', &
            'give snapshot times in [0, t_end] s, one after another, without gaps', err)
        else if (snapshot_times(j) < 0.0_wp .or. snapshot_times(j) > t_end) then
          call bad(deck, 'solver', 'snapshot_times', 'entry '//itoa(j)//' = '// &
            rtoa(snapshot_times(j)), 'give snapshot times in [0, t_end] s (t_end = '// &
            rtoa(t_end)//' s)', err)
        else if (j > 1) then
          ! (max: the compiler does not see that j > 1 here, and warns of entry 0)
          jp = max(j - 1, 1)
          if (snapshot_times(j) <= snapshot_times(jp)) call bad(deck, 'solver', &
            'snapshot_times', 'entry '//itoa(j)//' = '//rtoa(snapshot_times(j))// &
            ' after entry '//itoa(jp)//' = '//rtoa(snapshot_times(jp)), &
            'give the snapshot times in increasing order', err)
        end if
        if (allocated(err)) exit
      end do
    end if
    deck%solver = sv
  end subroutine read_solver

  subroutine read_bcs(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, k, j
    character(len=512) :: msg
    type(bc_spec_t) :: tmp(max_bcs)
    character(len=:), allocatable :: grp
    include 'deck_nml_bc.inc'
    rewind(u)
    k = 0
    do
      include 'deck_default_bc.inc'
      read(u, nml=bc, iostat=ios, iomsg=msg)
      if (ios == iostat_end) exit
      k = k + 1
      grp = 'bc (bc '//itoa(k)//')'
      if (ios /= 0) then
        call nml_error(deck, 'bc', ' (bc '//itoa(k)//')', msg, err)
        return
      end if
      if (k > max_bcs) then
        call set_error(err, "deck '"//deck%path//"': more than "//itoa(max_bcs)//" &bc groups")
        return
      end if
      tmp(k)%body = body
      tmp(k)%kind = lower(kind)
      tmp(k)%region_lo = region_lo
      tmp(k)%region_hi = region_hi
      tmp(k)%component = component
      tmp(k)%value = value
      tmp(k)%ibody = 0
      do j = 1, deck%nbodies
        if (deck%bodies(j)%name == body) tmp(k)%ibody = j
      end do
      if (tmp(k)%ibody == 0) then
        call bad(deck, grp, 'body', "'"//trim(body)//"'", 'name one of the bodies: '// &
          join_names(deck%bodies%name), err)
      else if (component < 1 .or. component > deck%run%ndim) then
        call bad(deck, grp, 'component', itoa(component), 'give the velocity component, 1 .. '// &
          itoa(deck%run%ndim), err)
      else if (any(region_lo(1:deck%run%ndim) > region_hi(1:deck%run%ndim))) then
        call bad(deck, grp, 'region_lo/region_hi', 'region_lo > region_hi', 'the box holds '// &
          'nothing; give region_lo <= region_hi in every direction (reference coordinates, '// &
          'm)', err)
      end if
      if (allocated(err)) return
    end do
    deck%nbcs = k
    deck%bcs = tmp(1:k)
  end subroutine read_bcs

  subroutine read_contacts(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, k, j
    character(len=512) :: msg
    type(contact_spec_t) :: tmp(max_contacts)
    character(len=:), allocatable :: grp
    include 'deck_nml_contact.inc'
    rewind(u)
    k = 0
    do
      include 'deck_default_contact.inc'
      read(u, nml=contact, iostat=ios, iomsg=msg)
      if (ios == iostat_end) exit
      k = k + 1
      grp = 'contact (contact '//itoa(k)//')'
      if (ios /= 0) then
        call nml_error(deck, 'contact', ' (contact '//itoa(k)//')', msg, err)
        return
      end if
      if (k > max_contacts) then
        call set_error(err, "deck '"//deck%path//"': more than "//itoa(max_contacts)// &
          " &contact groups")
        return
      end if
      detector = lower(detector)
      tmp(k) = contact_spec_t(master=master, slave=slave, eps_cr=eps_cr, eps_rel=eps_rel, &
        mu=mu, detector=detector, compare_detectors=compare_detectors, skip_far=skip_far, &
        shared_mass=shared_mass, edge_point=edge_point, self_radius=self_radius)
      do j = 1, deck%nbodies
        if (deck%bodies(j)%name == master) tmp(k)%imaster = j
        if (deck%bodies(j)%name == slave) tmp(k)%islave = j
      end do
      if (tmp(k)%imaster == 0) then
        call bad(deck, grp, 'master', "'"//trim(master)//"'", 'name one of the bodies: '// &
          join_names(deck%bodies%name), err)
      else if (tmp(k)%islave == 0) then
        call bad(deck, grp, 'slave', "'"//trim(slave)//"'", 'name one of the bodies: '// &
          join_names(deck%bodies%name), err)
      else if (deck%bodies(tmp(k)%islave)%role /= 'deformable') then
        call bad(deck, grp, 'slave', "'"//trim(slave)//"'", 'the slave must be a '// &
          "deformable body (role = 'deformable')", err)
      else if (tmp(k)%imaster == tmp(k)%islave .and. detector /= 'det_m') then
        call bad(deck, grp, 'detector', "'"//trim(detector)//"'", "self-contact (master = "// &
          "slave) needs 'det_m': a closest-segment search cannot tell a face folded onto "// &
          "the body from the body's own curved surface, det(M) of the non-neighbours can", err)
      else if (tmp(k)%imaster == tmp(k)%islave .and. compare_detectors) then
        call bad(deck, grp, 'compare_detectors', '.true.', 'self-contact (master = slave) '// &
          'has no node-to-segment detector to compare with; give .false.', err)
      else if (deck%run%mode /= 'dynamic') then
        call bad(deck, grp, 'master', "'"//trim(master)//"'", "contact pairs act in "// &
          "mode = 'dynamic' only", err)
      end if
      if (allocated(err)) return
    end do
    deck%ncontacts = k
    deck%contacts = tmp(1:k)
  end subroutine read_contacts

  subroutine read_output(u, deck, err)
    integer, intent(in) :: u
    type(deck_t), intent(inout) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios
    character(len=512) :: msg
    character(len=:), allocatable :: given
    logical :: found
    include 'deck_nml_output.inc'
    include 'deck_default_output.inc'
    ! gfortran reads overwrite = 'no' as an unknown name ("Cannot match namelist object
    ! name 'no'") and overwrite = fred as .false.: check the text before it reads it
    call group_value(deck%text, 'output', 'overwrite', given, found)
    if (found) then
      if (.not. is_logical_text(given)) then
        call bad(deck, 'output', 'overwrite', given, 'not a logical; give .true. or .false. '// &
          '(unquoted): with .false. an existing result is an error instead of being '// &
          'replaced', err)
        return
      end if
    end if
    rewind(u)
    read(u, nml=output, iostat=ios, iomsg=msg)
    if (ios /= 0 .and. ios /= iostat_end) then
      call nml_error(deck, 'output', '', msg, err)
      return
    end if
    if (len_trim(file) == 0) then
      call bad(deck, 'output', 'file', "''", &
        "give the HDF5 output path, e.g. &output file = 'output/run.h5' /", err)
      return
    end if
    if (det_fields .and. (deck%ncontacts == 0 .or. any(det_grid_lo == unset) .or. &
      any(det_grid_hi == unset))) then
      call bad(deck, 'output', 'det_fields', '.true.', 'det(M) fields need a &contact pair '// &
        'and the grid: det_grid_lo = x0, y0, det_grid_hi = x1, y1 (m)', err)
      return
    end if
    if (det_fields .and. (any(det_grid_n < 2) .or. any(.not. det_grid_hi > det_grid_lo) .or. &
      real(det_grid_n(1), wp)*det_grid_n(2) > 1.0e7_wp)) then
      call bad(deck, 'output', 'det_grid_n/det_grid_lo/det_grid_hi', itoa(det_grid_n(1))// &
        ', '//itoa(det_grid_n(2)), 'give 2 .. 1e7 points with det_grid_hi > det_grid_lo', err)
      return
    end if
    deck%output%file = file
    deck%output%overwrite = overwrite
    deck%output%det_fields = det_fields
    deck%output%det_grid_lo = det_grid_lo
    deck%output%det_grid_hi = det_grid_hi
    deck%output%det_grid_n = det_grid_n
    deck%output%checkpoint_every = checkpoint_every
  end subroutine read_output

  !> The value text v of variable var in the first &group of deck text t: a quoted string
  !! with its quotes, or the characters up to the next separator ('' for a null value);
  !! found is .false. when the group or the variable is absent. Comments and strings in
  !! the deck are skipped.
  subroutine group_value(t, group, var, v, found)
    character(len=*), intent(in) :: t, group, var
    character(len=:), allocatable, intent(out) :: v
    logical, intent(out) :: found
    character(len=*), parameter :: blanks = ' '//achar(9)//achar(10)//achar(13)
    character(len=*), parameter :: ends = ' ,/!'//achar(9)//achar(10)//achar(13)
    integer :: i, j, n
    logical :: inside
    n = len(t)
    i = 1
    inside = .false.
    found = .false.
    v = ''
    do while (i <= n)
      select case (t(i:i))
      case ("'", '"')
        j = index(t(i + 1:), t(i:i))
        if (j == 0) return
        i = i + j + 1
      case ('!')
        j = index(t(i:), achar(10))
        if (j == 0) return
        i = i + j
      case ('&')
        j = i + 1
        do while (j <= n)
          if (.not. is_name_char(t(j:j))) exit
          j = j + 1
        end do
        if (inside) return
        inside = lower(t(i + 1:j - 1)) == group
        i = j
      case ('/')
        if (inside) return
        i = i + 1
      case default
        if (.not. (inside .and. is_name_start(t(i:i)))) then
          i = i + 1
          cycle
        end if
        j = i
        do while (j <= n)
          if (.not. is_name_char(t(j:j))) exit
          j = j + 1
        end do
        if (lower(t(i:j - 1)) == var .and. (i == 1 .or. .not. is_name_char(t(i - 1:i - 1)))) then
          i = j - 1 + verify(t(j:), blanks)
          if (i < j) return
          if (t(i:i) == '=') then
            found = .true.
            j = i + verify(t(i + 1:), blanks)
            if (j <= i) return
            if (t(j:j) == "'" .or. t(j:j) == '"') then
              i = index(t(j + 1:), t(j:j))
              if (i == 0) i = n - j
              v = t(j:j + i)
            else
              i = scan(t(j:), ends)
              if (i == 0) i = n - j + 2
              v = t(j:j + i - 2)
            end if
            return
          end if
        end if
        i = j
      end select
    end do
  end subroutine group_value

  !> A Fortran logical as a deck should give it: .true., .false., t, f, true, false,
  !! with or without the dots, any case.
  pure logical function is_logical_text(s)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: w
    integer :: a, z
    w = lower(trim(adjustl(s)))
    a = 1
    z = len(w)
    if (z >= 1) then
      if (w(1:1) == '.') a = 2
    end if
    if (z >= a) then
      if (w(z:z) == '.') z = z - 1
    end if
    is_logical_text = any(w(a:max(z, a - 1)) == [character(len=5) :: 't', 'true', 'f', 'false'])
  end function is_logical_text

  subroutine nml_error(deck, group, which, msg, err)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: group, which, msg
    type(error_t), allocatable, intent(inout) :: err
    call set_error(err, "deck '"//deck%path//"', group &"//group//which//": "//trim(msg)// &
      "; fix the spelling or the value (variables of &"//group//": "// &
      group_vars(group)//"; see doc/deck.md)")
  end subroutine nml_error

  !> The variable that sets how many particles a body of this shape has (for messages).
  pure function body_count_var(shape) result(v)
    character(len=*), intent(in) :: shape
    character(len=:), allocatable :: v
    select case (shape)
    case ('polygon', 'disk', 'cylinder')
      v = 'spacing'
    case ('box')
      v = 'n'
    case ('file', 'geo')
      v = 'file'
    case default
      v = 'n'
    end select
  end function body_count_var

  !> The variables that place a body of this shape (for messages).
  pure function body_place_var(shape) result(v)
    character(len=*), intent(in) :: shape
    character(len=:), allocatable :: v
    select case (shape)
    case ('rectangle', 'segment', 'box')
      v = 'lo/hi'
    case ('polygon')
      v = 'vertices'
    case ('annulus_sector', 'disk', 'cylinder')
      v = 'center'
    case default
      v = 'file'
    end select
  end function body_place_var

  !> The variables that make a body of this shape (for messages).
  pure function body_make_vars(shape) result(v)
    character(len=*), intent(in) :: shape
    character(len=:), allocatable :: v
    select case (shape)
    case ('segment', 'rectangle', 'box')
      v = 'lo/hi/n'
    case ('polygon')
      v = 'vertices/spacing'
    case ('annulus_sector')
      v = 'r_inner/r_outer/n'
    case ('disk')
      v = 'radius/spacing'
    case ('cylinder')
      v = 'radius/extrude/spacing'
    case default
      v = 'file'
    end select
  end function body_make_vars

  !> The dimension a generated shape needs; 0 for a particle file or a gmsh script (more
  !! than one).
  pure integer function shape_ndim(shape)
    character(len=*), intent(in) :: shape
    select case (shape)
    case ('segment')
      shape_ndim = 1
    case ('rectangle', 'annulus_sector', 'disk')
      shape_ndim = 2
    case ('box', 'cylinder')
      shape_ndim = 3
    case default
      shape_ndim = 0
    end select
  end function shape_ndim

  !> Where variable var of group is in deck_vars, 0 when it is not a deck variable.
  pure integer function var_index(group, var) result(i)
    character(len=*), intent(in) :: group, var
    do i = 1, size(deck_vars)
      if (deck_vars(i)%group == group .and. deck_vars(i)%name == var) return
    end do
    i = 0
  end function var_index

  !> The variables of group, 'a, b, c' (for messages).
  pure function group_vars(group) result(s)
    character(len=*), intent(in) :: group
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(deck_vars)
      if (deck_vars(i)%group /= group) cycle
      if (len(s) > 0) s = s//', '
      s = s//trim(deck_vars(i)%name)
    end do
  end function group_vars

  !> The type of variable var of group: 'r' real, 'i' integer, 'l' logical, 's' string, or
  !! ' ' when it is no deck variable.
  pure function var_type(group, var) result(typ)
    character(len=*), intent(in) :: group, var
    character :: typ
    integer :: i
    i = var_index(group, var)
    typ = ' '
    if (i > 0) typ = deck_vars(i)%typ
  end function var_type

  !> How many values variable var of group holds: its array size, 1 for a scalar, 0 when
  !! it is no deck variable.
  pure integer function var_size(group, var) result(n)
    character(len=*), intent(in) :: group, var
    integer :: i
    i = var_index(group, var)
    n = 0
    if (i > 0) n = deck_vars(i)%size
  end function var_size

  !> The most characters the string variable var of group holds, 0 when var is not a string.
  pure integer function string_length(group, var) result(n)
    character(len=*), intent(in) :: group, var
    integer :: i
    i = var_index(group, var)
    n = 0
    if (i > 0) n = deck_vars(i)%length
  end function string_length

  !> The values variable var of group may take, "'a', 'b'" (for messages); '' when any.
  pure function choices_text(group, var) result(s)
    character(len=*), intent(in) :: group, var
    character(len=:), allocatable :: s, v
    integer :: i
    i = var_index(group, var)
    s = ''
    if (i == 0) return
    v = trim(deck_vars(i)%valid)
    if (index(v, 'one of ') /= 1) return
    s = v(8:)
    do while (index(s, "' '") > 0)
      i = index(s, "' '")
      s = s(1:i)//', '//s(i + 2:)
    end do
  end function choices_text

  !> Whether w is one of the quoted words of list ("'a' 'b' 'c'").
  pure logical function is_choice(list, w)
    character(len=*), intent(in) :: list, w
    integer :: a, z
    is_choice = .false.
    a = 1
    do while (a < len(list))
      z = a + index(list(a + 1:), "'")
      if (z == a) exit
      if (list(a + 1:z - 1) == w .and. len(w) == z - a - 1) is_choice = .true.
      a = z + 2
    end do
  end function is_choice

  !> '' when the value x (text tok) of deck variable i is valid, else why not and the fix.
  !! Strings are compared lower-cased with the choices; numbers with the interval.
  pure function value_fault(i, tok, x) result(why)
    integer, intent(in) :: i
    character(len=*), intent(in) :: tok
    real(wp), intent(in) :: x
    character(len=:), allocatable :: why, v, hint
    real(wp) :: a, b
    integer :: c, ios
    logical :: ok
    why = ''
    v = trim(deck_vars(i)%valid)
    hint = trim(deck_vars(i)%hint)
    if (len(hint) > 0) hint = ' ('//hint//')'
    if (v == 'any') return
    if (index(v, 'one of ') == 1) then
      if (.not. is_choice(v(8:), lower(tok))) why = 'use one of: '// &
        choices_text(deck_vars(i)%group, deck_vars(i)%name)//hint
      return
    end if
    if (v(1:1) == '[' .or. v(1:1) == '(') then
      c = index(v, ',')
      read(v(2:c - 1), *, iostat=ios) a
      if (ios == 0) read(v(c + 1:len(v) - 1), *, iostat=ios) b
      ok = merge(x >= a, x > a, v(1:1) == '[') .and. merge(x <= b, x < b, v(len(v):) == ']')
    else
      c = scan(v, ' ')
      read(v(c + 1:), *, iostat=ios) a
      select case (v(1:c - 1))
      case ('>')
        ok = x > a
      case ('>=')
        ok = x >= a
      case ('<')
        ok = x < a
      case default
        ok = x <= a
      end select
    end if
    if (ios /= 0) then
      why = 'the deck description (src/setup/deck_vars.tsv) has no valid range: '//v
    else if (.not. ok .and. scan(v(1:1), '[(') > 0) then
      why = 'give a value in '//v//hint
    else if (.not. ok) then
      why = 'give a value '//v//hint
    end if
  end function value_fault

  subroutine bad(deck, group, var, value, fix, err)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: group, var, value, fix
    type(error_t), allocatable, intent(inout) :: err
    call set_error(err, "deck '"//deck%path//"', group &"//group//", variable "//var// &
      " = "//value//": "//fix)
  end subroutine bad

  !> A deck value as text, '(unset)' for entries the deck did not give.
  pure function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    if (x == unset) then
      s = '(unset)'
    else
      s = rtoa_plain(x)
    end if
  end function rtoa
end module deck_m
