!> Energy bookkeeping and run health of a dynamic run, for any set of solids: the energy
!! totals and residual (kinetic + internal - initial kinetic - external - contact work), and
!! the guards that stop a run going unstable (non-finite values, J <= 0, energy growth),
!! each with a message that says where.
module run_health_m
  use kinds_m, only: wp
  use strings_m, only: itoa, rtoa
  use solid_m, only: solid_t, solid_first_bad
  implicit none
  private
  public :: energies_t, energy_totals, check_solid, check_energy, fastest_node

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
      en%ke = en%ke + solids(k)%ke
      en%ke0 = en%ke0 + solids(k)%ke0
      en%w_int = en%w_int + solids(k)%w_int + solids(k)%e_stab
      en%w_plastic = en%w_plastic + solids(k)%w_plastic
      en%w_ext = en%w_ext + solids(k)%w_ext + solids(k)%w_bc
      en%w_contact = en%w_contact + solids(k)%w_contact
    end do
    en%residual = en%ke + en%w_int - en%ke0 - en%w_ext - en%w_contact
    en%scale = max(en%ke0, en%ke, abs(en%w_int), abs(en%w_ext), abs(en%w_contact), &
      tiny(1.0_wp))
  end subroutine energy_totals

  !> After the forces of step n: a point with J <= 0 or a non-finite stress (bad_q > 0, from
  !! solid_internal_force) or a non-finite coefficient or velocity fails the run; reason
  !! says where. Leaves failed and reason alone when the solid is healthy.
  subroutine check_solid(s, n, bad_q, bad_j, failed, reason)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: n, bad_q
    real(wp), intent(in) :: bad_j
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    integer :: j
    if (failed) return
    if (bad_q > 0) then
      failed = .true.
      reason = 'step '//itoa(n)//', body '''//trim(s%name)//''', integration point '// &
        itoa(bad_q)//trim(owner_text(bad_q))//': J = '//rtoa(bad_j)// &
        ' (must stay > 0) or non-finite stress'
      return
    end if
    j = solid_first_bad(s)
    if (j > 0) then
      failed = .true.
      reason = 'step '//itoa(n)//', body '''//trim(s%name)// &
        ''': non-finite displacement or velocity (node '//itoa(j)//')'
    end if
  contains
    function owner_text(q) result(txt)
      integer, intent(in) :: q
      character(len=:), allocatable :: txt
      txt = ''
      if (s%t%owner(q) > 0) txt = ' (particle '//itoa(s%t%owner(q))//')'
    end function owner_text
  end subroutine check_solid

  !> The energy guard: growth of |residual| beyond tol x scale fails the run. An impulsive
  !! start (a velocity jump at t = 0) leaves a one-time residual of order dt that is large
  !! against the small energies of the first steps, so the guard is armed after warmup steps.
  subroutine check_energy(en, n, warmup, tol, solids, failed, reason)
    type(energies_t), intent(in) :: en
    integer, intent(in) :: n, warmup
    real(wp), intent(in) :: tol
    type(solid_t), intent(in) :: solids(:)
    logical, intent(inout) :: failed
    character(len=:), allocatable, intent(inout) :: reason
    if (failed .or. n <= warmup) return
    if (abs(en%residual) > tol*en%scale) then
      failed = .true.
      reason = 'step '//itoa(n)//': energy residual '//rtoa(en%residual)//' exceeds '// &
        'energy_tol x energy scale = '//rtoa(tol*en%scale)//'; '//fastest_node(solids)
    end if
  end subroutine check_energy

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
        v = norm2(solids(k)%v(:, j))
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
