!> Energy bookkeeping and run health of a dynamic run, for any set of solids: the energy
!! totals and residual (kinetic + internal - initial kinetic - external - contact work), and
!! the guards that stop a run going unstable (non-finite values, J <= 0, energy growth),
!! each with a message that says where.
module run_health_m
  use kinds_m, only: wp
  use strings_m, only: itoa, rtoa
  use solid_m, only: solid_t, solid_worst_node, health_j, health_stress, health_epsbar
  use stable_step_m, only: step_control_t, dt_collapse, step_limit_text
  implicit none
  private
  public :: energies_t, energy_totals, check_solid, check_energy, fastest_node, check_step
  public :: set_health_limits

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

  !> Totals and residual; the scale is the largest account (the residual's reference).
  subroutine energy_totals(solids, en)
    type(solid_t), intent(in) :: solids(:)
    type(energies_t), intent(out) :: en
    integer :: k
    do k = 1, size(solids)
      en%ke = en%ke + solids(k)%acc%ke
      en%ke0 = en%ke0 + solids(k)%acc%ke0
      en%w_int = en%w_int + solids(k)%acc%w_int + solids(k)%acc%e_stab
      en%w_plastic = en%w_plastic + solids(k)%acc%w_plastic
      en%w_ext = en%w_ext + solids(k)%acc%w_ext + solids(k)%acc%w_bc
      en%w_contact = en%w_contact + solids(k)%acc%w_contact
    end do
    en%residual = en%ke + en%w_int - en%ke0 - en%w_ext - en%w_contact
    en%scale = max(en%ke0, en%ke, abs(en%w_int), abs(en%w_ext), abs(en%w_contact), &
      tiny(1.0_wp))
  end subroutine energy_totals

  !> Local health limits of every solid: node speed below 5 v_ref + 0.2 c_d, with v_ref the
  !! fastest initial or prescribed speed of any solid and c_d the solid's dilatational wave
  !! speed. Impact and wave-induced speeds of the bulk stay below 2 v_ref (a free-end
  !! reflection doubles v; the Taylor bars' fastest node in every snapshot: 1.8 v_ref), but a
  !! light node at a contact surface can spike for a step (the paper-dt FEM Taylor bar's
  !! axis node: 1208 m/s = 6 v_ref at 5.8 us, harmless to the run), so the limit leaves room
  !! for that; an instability grows past any bound (the one first reported: 6238 m/s)
  !! and is caught a few steps later; epsbar below
  !! epsbar_limit; its increment in one step below deps_limit; J inside j_limits.
  subroutine set_health_limits(solids)
    type(solid_t), intent(inout) :: solids(:)
    real(wp) :: vref
    integer :: k
    vref = 0.0_wp
    do k = 1, size(solids)
      vref = max(vref, sqrt(maxval(sum(solids(k)%state%v**2, dim=1))), &
        sqrt(maxval(sum(solids(k)%vpres**2, dim=1))))
    end do
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
  !! quantity and the likely fix. Leaves failed and reason alone when the solid is healthy.
  subroutine check_solid(s, n, bad_q, bad_j, failed, reason)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: n, bad_q
    real(wp), intent(in) :: bad_j
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    integer :: j
    real(wp) :: vmax
    if (failed) return
    if (bad_q > 0) then
      failed = .true.
      reason = 'step '//itoa(n)//', body '''//trim(s%name)//''', integration point '// &
        itoa(bad_q)//trim(owner_text(bad_q))//': '//point_text(bad_q)
      return
    end if
    call solid_worst_node(s, j, vmax)
    if (.not. (vmax <= s%opt%v_limit)) then
      failed = .true.
      if (vmax >= huge(1.0_wp)) then
        reason = 'step '//itoa(n)//', body '''//trim(s%name)// &
          ''': non-finite displacement or velocity (node '//itoa(j)//'); '//fix_text(s)
      else
        reason = 'step '//itoa(n)//', body '''//trim(s%name)//''', node '//itoa(j)// &
          ': speed '//rtoa(vmax)//' m/s above the limit '//rtoa(s%opt%v_limit)// &
          ' m/s (5 x the fastest initial or prescribed speed + 0.2 c_d): a local '// &
          'instability; '//fix_text(s)
      end if
    end if
  contains
    function owner_text(q) result(txt)
      integer, intent(in) :: q
      character(len=:), allocatable :: txt
      txt = ''
      if (s%t%owner(q) > 0) txt = ' (particle '//itoa(s%t%owner(q))//')'
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
  subroutine check_step(c, solids, n, failed, reason)
    type(step_control_t), intent(in) :: c
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: n
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    character(len=:), allocatable :: fix
    if (failed) return
    if (c%dtc < dt_collapse*c%dtc0) then
      failed = .true.
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
  subroutine check_energy(en, n, warmup, tol, solids, over, failed, reason)
    type(energies_t), intent(in) :: en
    integer, intent(in) :: n, warmup
    real(wp), intent(in) :: tol
    type(solid_t), intent(in) :: solids(:)
    integer, intent(inout) :: over
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
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
        fastest_node(solids)//'; '//fix_text_all(solids)
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
  function fastest_node(solids) result(msg)
    type(solid_t), intent(in) :: solids(:)
    character(len=:), allocatable :: msg
    integer :: k, j, kb, jb
    real(wp) :: vmax, v
    vmax = -1.0_wp
    kb = 1
    jb = 1
    do k = 1, size(solids)
      do j = 1, solids(k)%np
        v = norm2(solids(k)%state%v(:, j))
        if (v > vmax) then
          vmax = v
          kb = k
          jb = j
        end if
      end do
    end do
    msg = 'fastest node '//itoa(jb)//' of body '''//trim(solids(kb)%name)// &
      ''' (|v| = '//rtoa(vmax)//' m/s)'
  end function fastest_node
end module run_health_m
