!> Energy bookkeeping and run health of a dynamic run, for any set of solids: the energy
!! totals and residual (kinetic + internal - initial kinetic - external - contact work), and
!! the guards that stop a run going unstable (non-finite values, J <= 0, energy growth),
!! each with a message that says where.
module run_health_m
  use kinds_m, only: wp
  use rank_comm_m, only: rank_comm_t
  use strings_m, only: itoa, rtoa
  use solid_m, only: solid_t, solid_worst_node, health_j, health_stress, health_epsbar, &
    solid_energies, solid_node_number, solid_point_number
  use stable_step_m, only: step_control_t, dt_collapse, step_limit_text
  implicit none
  private
  public :: energies_t, energy_totals, energies_of, check_solid, check_energy, fastest_node, &
    check_step
  public :: set_health_limits, fail_key_size, fail_key_first

  !> Local limits (set_health_limits). epsbar 100: only runaway local flow gets there. The
  !! softening of eq. (80) (g at epsbar = 1 is 39 MPa, at 10 under 1 MPa) lets a one-point
  !! element at the Taylor bar's lip localise: it reaches 48 at 24 us on the adaptive step
  !! (input/taylor_bar_fem_cfl.nml) while the run stays sound; particles reach 3.1.
  real(wp), parameter :: epsbar_limit = 100.0_wp
  !> 0.2 in one step: a resolved motion strains a cell by about |dv| dt/h <= cfl |dv|/c_d
  !! per step, so 0.2 means a velocity jump of 0.4 c_d (2400 m/s in steel) across one cell.
  real(wp), parameter :: deps_limit = 0.2_wp
  !> A volume change by a factor 20 needs a mean stress of 3 K (hypoelastic, tau_m = K ln J):
  !! no solid here gets there except through an inverting or exploding cell.
  real(wp), parameter :: j_limits(2) = [0.05_wp, 20.0_wp]
  !> The energy guard's window (steps over the limit in a row) and burst factor (fails at
  !! once); see check_energy.
  integer, parameter :: energy_window = 50

  !> A failure's key: its place in the order a serial run finds failures in, so that ranks
  !! which fail at one step in different places report the one the serial run reports
  !! (fail_key_first): the solid (its own checks in solid order; then the step's collapse,
  !! then the energy guard), the kind (1 a point out of its limits, 2 a non-finite node, 3 a
  !! node too fast, 4 the collapse, 5 the energy guard), then what decides within the kind
  !! (the highest point number, the lowest non-finite node, the fastest node and the lowest
  !! number among equals), each the lower the earlier.
  integer, parameter :: fail_key_size = 5
  real(wp), parameter :: energy_burst = 10.0_wp
  !> The likely fixes of a failure: fix_particles for RKPM solids, fix_elements for element
  !! meshes, which have no SCNI stabilization to raise (the FEM Taylor bar at 400-600 m/s
  !! stops on runaway flow of one-point elements at the lip: doc/stability.md).
  character(len=*), parameter :: fix_particles = 'try a smaller cfl (or a fixed dt below '// &
    'the critical step), a finer body there, or the SCNI stabilization (&body stabilization)'
  character(len=*), parameter :: fix_elements = 'try a smaller cfl (or a fixed dt below '// &
    'the critical step) or a finer mesh there (&body n)'

  !> Energy totals over the solids (J; J/m in plane strain).
  type :: energies_t
    real(wp) :: ke = 0.0_wp, ke0 = 0.0_wp, w_int = 0.0_wp, w_plastic = 0.0_wp
    real(wp) :: w_ext = 0.0_wp, w_contact = 0.0_wp, residual = 0.0_wp, scale = 0.0_wp
  end type energies_t

contains

  !> Totals and residual of the solids' running accounts; the scale is the largest account
  !! (the residual's reference).
  subroutine energy_totals(solids, en)
    type(solid_t), intent(in) :: solids(:)
    type(energies_t), intent(out) :: en
    integer :: k
    en = energies_of(reshape([(solid_energies(solids(k)), k = 1, size(solids))], &
      [8, size(solids)]))
  end subroutine energy_totals

  !> Totals, residual and scale from each solid's accounts e(:, k) in solid_energies'
  !! order (ke0, ke, w_int, w_plastic, w_bc, w_ext, w_contact, e_stab), added solid by
  !! solid: w_int takes the stabilization energy, w_ext the kinematic conditions' work.
  pure function energies_of(e) result(en)
    real(wp), intent(in) :: e(:, :)
    type(energies_t) :: en
    integer :: k
    do k = 1, size(e, 2)
      en%ke0 = en%ke0 + e(1, k)
      en%ke = en%ke + e(2, k)
      en%w_int = en%w_int + e(3, k) + e(8, k)
      en%w_plastic = en%w_plastic + e(4, k)
      en%w_ext = en%w_ext + e(6, k) + e(5, k)
      en%w_contact = en%w_contact + e(7, k)
    end do
    en%residual = en%ke + en%w_int - en%ke0 - en%w_ext - en%w_contact
    en%scale = max(en%ke0, en%ke, abs(en%w_int), abs(en%w_ext), abs(en%w_contact), &
      tiny(1.0_wp))
  end function energies_of

  !> Local health limits of every solid: node speed below 5 v_ref + 0.2 c_d, with v_ref the
  !! fastest initial or prescribed speed of any solid and c_d the solid's dilatational wave
  !! speed. Impact and wave-induced speeds of the bulk stay below 2 v_ref (a free-end
  !! reflection doubles v; the Taylor bars' fastest node in every snapshot: 1.8 v_ref), but a
  !! light node at a contact surface can spike for a step (the paper-dt FEM Taylor bar's
  !! axis node: 1208 m/s = 6 v_ref at 5.8 us, harmless to the run), so the limit leaves room
  !! for that; an instability grows past any bound (the one first reported: 6238 m/s)
  !! and is caught a few steps later; epsbar below
  !! epsbar_limit; its increment in one step below deps_limit; J inside j_limits.
  !! On ranks (comm) the set-up's solids may be region shells (solid_part_t region):
  !! v_ref is then the largest over the ranks, whose regions cover every particle.
  subroutine set_health_limits(solids, comm)
    type(solid_t), intent(inout) :: solids(:)
    class(rank_comm_t), intent(inout) :: comm
    real(wp) :: vref, v(1)
    integer :: k
    vref = 0.0_wp
    do k = 1, size(solids)
      ! (a region with no particle: none; maxval of nothing is -huge)
      if (solids(k)%np == 0) cycle
      vref = max(vref, sqrt(maxval(sum(solids(k)%state%v**2, dim=1))), &
        sqrt(maxval(sum(solids(k)%vpres**2, dim=1))))
    end do
    v = vref
    call comm%max_real(v)
    vref = v(1)
    do k = 1, size(solids)
      solids(k)%opt%v_limit = 5.0_wp*vref + 0.2_wp*solids(k)%mat%dilatational_speed()
      solids(k)%opt%epsbar_limit = epsbar_limit
      solids(k)%opt%deps_limit = deps_limit
      solids(k)%opt%j_bounds = j_limits
    end do
  end subroutine set_health_limits

  !> After the forces of step n: an integration point out of its limits (bad_q > 0, from
  !! solid_internal_force, code in s%bad_code) or a node with a non-finite coefficient or
  !! velocity or above the speed limit fails the run; reason names the point or node, the
  !! quantity and the likely fix, by their numbers in the whole solid (on ranks too).
  !! Leaves failed and reason alone when the solid is healthy. key: the failure's place in
  !! the order the serial run finds failures in (fail_key_t), its solid left to the caller.
  subroutine check_solid(s, n, bad_q, bad_j, failed, reason, key)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: n, bad_q
    real(wp), intent(in) :: bad_j
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    real(wp), intent(out), optional :: key(fail_key_size)
    integer :: j, g
    real(wp) :: vmax, k(fail_key_size)
    if (failed) return
    if (bad_q > 0) then
      failed = .true.
      g = solid_point_number(s, bad_q)
      reason = 'step '//itoa(n)//', body '''//trim(s%name)//''', integration point '// &
        itoa(g)//trim(owner_text(bad_q))//': '//point_text(bad_q)
      ! (the serial run names the highest bad point)
      k = [0.0_wp, 1.0_wp, -real(g, wp), 0.0_wp, 0.0_wp]
      if (present(key)) key = k
      return
    end if
    call solid_worst_node(s, j, vmax)
    if (.not. (vmax <= s%opt%v_limit)) then
      failed = .true.
      g = solid_node_number(s, j)
      if (vmax >= huge(1.0_wp)) then
        reason = 'step '//itoa(n)//', body '''//trim(s%name)// &
          ''': non-finite displacement or velocity (node '//itoa(g)//'); '//fix_text(s)
        ! (the lowest such node)
        k = [0.0_wp, 2.0_wp, real(g, wp), 0.0_wp, 0.0_wp]
      else
        reason = 'step '//itoa(n)//', body '''//trim(s%name)//''', node '//itoa(g)// &
          ': speed '//rtoa(vmax)//' m/s above the limit '//rtoa(s%opt%v_limit)// &
          ' m/s (5 x the fastest initial or prescribed speed + 0.2 c_d): a local '// &
          'instability; '//fix_text(s)
        ! (the fastest node, the lowest among equals)
        k = [0.0_wp, 3.0_wp, -vmax, real(g, wp), 0.0_wp]
      end if
      if (present(key)) key = k
    end if
  contains
    function owner_text(q) result(txt)
      integer, intent(in) :: q
      character(len=:), allocatable :: txt
      txt = ''
      if (s%t%owner(q) > 0) txt = ' (particle '//itoa(solid_node_number(s, s%t%owner(q)))//')'
    end function owner_text
    function point_text(q) result(txt)
      integer, intent(in) :: q
      character(len=:), allocatable :: txt
      select case (s%bad_code)
      case (health_j)
        txt = 'J = '//rtoa(bad_j)//' outside ('//rtoa(s%opt%j_bounds(1))//', '// &
          rtoa(s%opt%j_bounds(2))//'): the cell is inverting or exploding; '//fix_text(s)
      case (health_stress)
        txt = 'non-finite stress (J = '//rtoa(bad_j)//'); '//fix_text(s)
      case (health_epsbar)
        txt = 'effective plastic strain '//rtoa(s%state%st%epsbar(q))//' above the limit '// &
          rtoa(s%opt%epsbar_limit)//': runaway local plastic flow; '//fix_text(s)
      case default
        txt = 'effective plastic strain rate '//rtoa(s%state%st%epsdot(q))//' /s: increment '// &
          'in one step above '//rtoa(s%opt%deps_limit)//', the step does not resolve the '// &
          'motion; '//fix_text(s)
      end select
    end function point_text
  end subroutine check_solid

  !> The critical step collapsing (below dt_collapse of its initial value) fails the run: a
  !! cell or element is being crushed to nothing; reason names it.
  subroutine check_step(c, solids, n, failed, reason, key)
    type(step_control_t), intent(in) :: c
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: n
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    real(wp), intent(out), optional :: key(fail_key_size)
    character(len=:), allocatable :: fix
    if (failed) return
    if (c%dtc < dt_collapse*c%dtc0) then
      failed = .true.
      ! (after every solid's own checks; the same on every rank)
      if (present(key)) key = [real(size(solids) + 1, wp), 4.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
      fix = 'refine the body there, raise the SCNI stabilization or lower the impact speed'
      if (c%solid >= 1 .and. c%solid <= size(solids)) then
        if (solids(c%solid)%t%interpolating) fix = 'refine the mesh there (&body n) or '// &
          'lower the impact speed'
      end if
      reason = 'step '//itoa(n)//': the critical time step fell to '//rtoa(c%dtc/c%dtc0)// &
        ' of its initial value at '//step_limit_text(c, solids, .false.)//': that cell '// &
        'or element is collapsing; '//fix
    end if
  end subroutine check_step

  !> The energy guard: |residual| above tol x scale for energy_window consecutive steps, or
  !! above energy_burst x tol x scale at any step, fails the run. A contact onset or an
  !! impact can lift the residual over the limit for a few steps and let it fall back (one
  !! step's contact correction is not yet balanced by the work it does over the next); an
  !! instability grows without bound, so it stays over the limit and soon passes the burst
  !! level. An impulsive start (a velocity jump at t = 0) leaves a one-time residual of
  !! order dt that is large against the small energies of the first steps, so the guard is
  !! armed after warmup steps. over counts the consecutive steps over the limit.
  subroutine check_energy(en, n, warmup, tol, solids, over, failed, reason, key)
    type(energies_t), intent(in) :: en
    integer, intent(in) :: n, warmup
    real(wp), intent(in) :: tol
    type(solid_t), intent(in) :: solids(:)
    integer, intent(inout) :: over
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    real(wp), intent(out), optional :: key(fail_key_size)
    real(wp) :: fk(3)
    if (failed .or. n <= warmup) return
    if (abs(en%residual) > tol*en%scale) then
      over = over + 1
    else
      over = 0
    end if
    if (over >= energy_window .or. .not. (abs(en%residual) <= energy_burst*tol*en%scale)) then
      failed = .true.
      reason = 'step '//itoa(n)//': energy residual '//rtoa(en%residual)//' exceeds '// &
        'energy_tol x energy scale = '//rtoa(tol*en%scale)//' ('//itoa(over)// &
        ' steps in a row; the limit is '//itoa(energy_window)//' steps, or '// &
        itoa(nint(energy_burst))//' x at once); '//energy_parts(en)//'; '// &
        fastest_node(solids, fk)//'; '//fix_text_all(solids)
      ! (after the step's collapse; the same on every rank but for the fastest node)
      if (present(key)) key = [real(size(solids) + 1, wp), 5.0_wp, -fk(1), fk(2), fk(3)]
    end if
  end subroutine check_energy

  !> The residual's two parts, ke + w_int - ke(0) - w_ext (the bodies' own balance) and
  !! w_contact, and which of them broke it: contact when w_contact is at least half the
  !! residual (a balance that closes without contact, with contact work that does not
  !! match it), else the bodies' own motion.
  function energy_parts(en) result(msg)
    type(energies_t), intent(in) :: en
    character(len=:), allocatable :: msg
    real(wp) :: own
    own = en%ke + en%w_int - en%ke0 - en%w_ext
    msg = 'of it ke + w_int - ke(0) - w_ext = '//rtoa(own)//' and w_contact = '// &
      rtoa(en%w_contact)
    if (en%w_contact /= 0.0_wp .and. abs(en%w_contact) >= 0.5_wp*abs(en%residual)) then
      msg = msg//': the contact work broke the balance (against fixed or deformable '// &
        'masters contact can only take energy out, through inelastic stops and friction; '// &
        'w_contact > 0 there means its corrections pushed bodies apart; a moving rigid '// &
        'master puts in its own work): check the &contact pairs (against a deformable '// &
        'master keep shared_mass = .true., the default, and slave and master spacings within a '// &
        'factor of about two), then the step below'
    else
      msg = msg//': the bodies'' own motion broke the balance'
    end if
  end function energy_parts

  !> Which of the keys a(:, r) (fail_key_size each; huge where nothing failed) comes first:
  !! the lowest in lexicographic order, the lowest r among equals.
  pure integer function fail_key_first(a) result(best)
    real(wp), intent(in) :: a(:, :)
    integer :: r, c
    best = 1
    do r = 2, size(a, 2)
      do c = 1, size(a, 1)
        if (a(c, r) < a(c, best)) then
          best = r
          exit
        end if
        if (a(c, r) > a(c, best)) exit
      end do
    end do
  end function fail_key_first

  !> The likely fixes of a local failure of solid s.
  pure function fix_text(s) result(txt)
    type(solid_t), intent(in) :: s
    character(len=:), allocatable :: txt
    if (s%t%interpolating) then
      txt = fix_elements
    else
      txt = fix_particles
    end if
  end function fix_text

  !> The likely fixes of a failure of the whole run: the particles' when any solid has them.
  pure function fix_text_all(solids) result(txt)
    type(solid_t), intent(in) :: solids(:)
    character(len=:), allocatable :: txt
    integer :: k
    txt = fix_elements
    do k = 1, size(solids)
      if (.not. solids(k)%t%interpolating) txt = fix_particles
    end do
  end function fix_text_all

  !> 'fastest node J of body B (|v| = ...)': where an instability usually grows.
  function fastest_node(solids, key) result(msg)
    type(solid_t), intent(in) :: solids(:)
    !> |v|, the solid and the node's number in it: the order among ranks' answers
    real(wp), intent(out), optional :: key(3)
    character(len=:), allocatable :: msg
    integer :: k, j, jj, kb, jb, n
    real(wp) :: vmax, v
    vmax = -1.0_wp
    kb = 1
    jb = 1
    do k = 1, size(solids)
      ! (a rank's part: its owned nodes, by their numbers in the whole solid)
      n = solids(k)%np
      if (solids(k)%part%on) n = size(solids(k)%part%own_n)
      do jj = 1, n
        j = jj
        if (solids(k)%part%on) j = solids(k)%part%own_n(jj)
        v = norm2(solids(k)%state%v(:, j))
        if (v > vmax .or. (v == vmax .and. k == kb .and. solid_node_number(solids(k), j) < jb)) &
          then
          vmax = v
          kb = k
          jb = solid_node_number(solids(k), j)
        end if
      end do
    end do
    msg = 'fastest node '//itoa(jb)//' of body '''//trim(solids(kb)%name)// &
      ''' (|v| = '//rtoa(vmax)//' m/s)'
    if (present(key)) key = [vmax, real(kb, wp), real(jb, wp)]
  end function fastest_node
end module run_health_m
