!> A deformable particle body in the explicit total-Lagrangian RKPM solver: its reference
!! tables, material and state, the coefficient vectors of eqs. (62)-(64), kinematic
!! conditions, and the energy accounts of the step.
module tl_body_m
  use omp_lib, only: omp_get_wtime
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use body_m, only: body_t
  use deck_m, only: deck_t, body_spec_t
  use material_m, only: material_t, material_state_t, make_material
  use solid_tables_m, only: solid_tables_t
  use rkpm_tl_m, only: tl_build, scheme_id
  use tl_kinematics_m, only: deformation_gradient, rate_of_deformation, piola_stress, &
    internal_force, physical_positions, jacobian
  implicit none
  private
  public :: tl_body_t, tl_body_init, tl_body_forces, tl_apply_bc, tl_kinetic_energy

  type :: tl_body_t
    integer :: ibody = 0                         !< index among the deck's bodies
    integer :: np = 0, nq = 0
    type(solid_tables_t) :: t
    class(material_t), allocatable :: mat
    type(material_state_t) :: st
    real(wp), allocatable :: x0(:, :)            !< reference positions (2, np) (m)
    real(wp), allocatable :: d(:, :), v(:, :), a(:, :)   !< coefficients, eqs. (65)-(67)
    real(wp), allocatable :: d_old(:, :)         !< d at the start of the step
    real(wp), allocatable :: fint(:, :), fext(:, :)      !< (2, np) (N)
    real(wp), allocatable :: x(:, :)             !< physical positions (2, np) (m)
    real(wp), allocatable :: f(:, :), f_old(:, :)        !< F (5, nq)
    real(wp), allocatable :: p(:, :), p_old(:, :)        !< first Piola-Kirchhoff (5, nq) (Pa)
    real(wp), allocatable :: dr(:, :), w12(:), dwp(:)    !< D (4, nq), W12, plastic work
    logical, allocatable :: pres(:, :)           !< prescribed velocity component (2, np)
    real(wp), allocatable :: vpres(:, :)         !< its value (m/s)
    ! energy accounts since t = 0 (J, or J/m in plane strain)
    real(wp) :: ke0 = 0.0_wp, ke = 0.0_wp, w_int = 0.0_wp, w_plastic = 0.0_wp, w_bc = 0.0_wp
    real(wp) :: w_ext = 0.0_wp, w_contact = 0.0_wp
    real(wp), allocatable :: freac_old(:, :)     !< reaction at prescribed components (N)
    real(wp), allocatable :: freac(:, :)
    real(wp) :: wall(3) = 0.0_wp                 !< seconds in kinematics, material, forces
    real(wp) :: stab_normal = 0.0_wp, stab_shear = 0.0_wp  !< alpha (lambda + 2 mu), alpha mu
    real(wp) :: e_stab = 0.0_wp                  !< stabilization energy (J)
    real(wp), allocatable :: stab(:, :)          !< its stresses (4, nq), work space
    real(wp), allocatable :: a_old(:, :)         !< a_n during the step
    real(wp), allocatable :: v_old(:, :)         !< v_n during the step
    real(wp), allocatable :: fcon(:, :)          !< contact forces on the coefficients (N)
  end type tl_body_t

contains

  !> Tables, material, state and kinematic conditions of body k of the deck.
  subroutine tl_body_init(deck, k, b, axisym, tb, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(body_t), intent(in) :: b
    logical, intent(in) :: axisym
    type(tl_body_t), intent(out) :: tb
    type(error_t), allocatable, intent(inout) :: err
    type(body_spec_t) :: s
    integer :: j, i, c, nsel
    type(error_t), allocatable :: e2
    s = deck%bodies(k)
    tb%ibody = k
    call make_material(deck%materials(s%imat)%params, tb%mat, e2)
    if (.not. allocated(e2)) call tl_build(b, axisym, scheme_id(s%integration), &
      deck%materials(s%imat)%params%density, tb%t, e2)
    if (allocated(e2)) then
      call set_error(err, "deck '"//deck%path//"', group &body (body "//itoa(k)//", '"// &
        trim(b%name)//"'): "//e2%message)
      return
    end if
    tb%np = b%np
    tb%nq = tb%t%nq
    allocate(tb%stab(4, tb%nq))
    tb%stab = 0.0_wp
    tb%stab_normal = s%stabilization*(tb%mat%lambda + 2.0_wp*tb%mat%g)
    tb%stab_shear = s%stabilization*tb%mat%g
    call tb%st%init(tb%nq)
    tb%x0 = b%x
    allocate(tb%d(2, b%np), tb%v(2, b%np), tb%a(2, b%np), tb%fint(2, b%np), &
      tb%fext(2, b%np), tb%x(2, b%np), tb%d_old(2, b%np), tb%pres(2, b%np), &
      tb%vpres(2, b%np), tb%freac_old(2, b%np), tb%freac(2, b%np), tb%a_old(2, b%np), &
      tb%v_old(2, b%np), tb%fcon(2, b%np))
    allocate(tb%f(5, tb%nq), tb%f_old(5, tb%nq), tb%p(5, tb%nq), tb%p_old(5, tb%nq), &
      tb%dr(4, tb%nq), tb%w12(tb%nq), tb%dwp(tb%nq))
    tb%d = 0.0_wp
    tb%a = 0.0_wp
    tb%fext = 0.0_wp
    tb%freac_old = 0.0_wp
    tb%fcon = 0.0_wp
    do i = 1, b%np
      tb%v(:, i) = s%velocity(1:2)
    end do
    tb%x = b%x
    ! kinematic conditions: the axis (u_r = 0), then the deck's &bc groups
    tb%pres = .false.
    tb%vpres = 0.0_wp
    tb%pres(1, :) = tb%t%fix1
    do j = 1, deck%nbcs
      if (deck%bcs(j)%ibody /= k) cycle
      c = deck%bcs(j)%component
      nsel = 0
      do i = 1, b%np
        if (all(b%x(:, i) >= deck%bcs(j)%region_lo(1:2)) .and. &
          all(b%x(:, i) <= deck%bcs(j)%region_hi(1:2))) then
          tb%pres(c, i) = .true.
          tb%vpres(c, i) = merge(deck%bcs(j)%value, 0.0_wp, deck%bcs(j)%kind == 'velocity')
          nsel = nsel + 1
        end if
      end do
      if (nsel == 0) then
        call set_error(err, "deck '"//deck%path//"', group &bc (bc "//itoa(j)// &
          "), variable region_lo/region_hi: the box holds no particle of body '"// &
          trim(b%name)//"'; enlarge it (reference coordinates, m)")
        return
      end if
    end do
    where (tb%pres) tb%v = tb%vpres
    tb%f = 0.0_wp
    tb%f(1, :) = 1.0_wp
    tb%f(4, :) = 1.0_wp
    tb%f(5, :) = 1.0_wp
    tb%p = 0.0_wp
    tb%fint = 0.0_wp
    tb%ke0 = tl_kinetic_energy(tb)
    tb%ke = tb%ke0
  end subroutine tl_body_init

  !> F and P of the last step kept for the step's work and rates (parallel copy).
  subroutine copy_state(tb)
    type(tl_body_t), intent(inout) :: tb
    integer :: q
    !$omp parallel do default(none) shared(tb) schedule(static)
    do q = 1, tb%nq
      tb%f_old(:, q) = tb%f(:, q)
      tb%p_old(:, q) = tb%p(:, q)
    end do
    !$omp end parallel do
  end subroutine copy_state

  !> Prescribed components: velocity set, acceleration zero.
  subroutine tl_apply_bc(tb)
    type(tl_body_t), intent(inout) :: tb
    where (tb%pres)
      tb%v = tb%vpres
      tb%a = 0.0_wp
    end where
  end subroutine tl_apply_bc

  !> 1/2 sum m |v|^2 (J; J/m in plane strain).
  pure real(wp) function tl_kinetic_energy(tb) result(ke)
    type(tl_body_t), intent(in) :: tb
    ke = 0.5_wp*sum(tb%t%mass*(tb%v(1, :)**2 + tb%v(2, :)**2))
  end function tl_kinetic_energy

  !> At the new coefficients d: F, D and W from the old F, the material update, P, the
  !! internal force, a = (f_ext - f_int)/m (eq. 62), and the step's internal and plastic
  !! work. Returns the first point with J <= 0 or a non-finite stress in bad_q (0 if none).
  subroutine tl_body_forces(tb, dt, bad_q, bad_j)
    type(tl_body_t), intent(inout) :: tb
    real(wp), intent(in) :: dt
    integer, intent(out) :: bad_q
    real(wp), intent(out) :: bad_j
    integer :: q, nthreads_blocks, i0, i1, blk
    real(wp) :: dw, dwp, jq, t0, t1, t2
    integer, parameter :: block = 256
    t0 = omp_get_wtime()
    call copy_state(tb)
    if (tb%stab_normal > 0.0_wp) then
      call deformation_gradient(tb%t, tb%d, tb%f, [tb%stab_normal, tb%stab_shear], tb%stab, &
        tb%e_stab)
    else
      call deformation_gradient(tb%t, tb%d, tb%f)
    end if
    call rate_of_deformation(tb%nq, dt, tb%f_old, tb%f, tb%dr, tb%w12)
    t1 = omp_get_wtime()
    nthreads_blocks = (tb%nq + block - 1)/block
    !$omp parallel do default(none) shared(tb, dt, nthreads_blocks) private(i0, i1) &
    !$omp schedule(dynamic, 4)
    do blk = 1, nthreads_blocks
      i0 = (blk - 1)*block + 1
      i1 = min(blk*block, tb%nq)
      call tb%mat%update(dt, tb%dr, tb%w12, tb%st, i0, i1, tb%dwp)
    end do
    !$omp end parallel do
    t2 = omp_get_wtime()
    call piola_stress(tb%nq, tb%f, tb%st%tau, tb%p)
    if (tb%stab_normal > 0.0_wp) then
      call internal_force(tb%t, tb%p, tb%fint, tb%stab)
    else
      call internal_force(tb%t, tb%p, tb%fint)
    end if
    bad_q = 0
    bad_j = 1.0_wp
    dw = 0.0_wp
    dwp = 0.0_wp
    !$omp parallel do default(none) shared(tb) private(jq) reduction(+: dw, dwp) &
    !$omp reduction(max: bad_q) schedule(static)
    do q = 1, tb%nq
      dw = dw + tb%t%wgt(q)*0.5_wp*sum((tb%p_old(:, q) + tb%p(:, q))*(tb%f(:, q) - tb%f_old(:, q)))
      dwp = dwp + tb%t%wgt(q)*tb%dwp(q)
      jq = jacobian(tb%f(:, q))
      if (.not. (jq > 0.0_wp) .or. .not. all(abs(tb%st%tau(:, q)) < huge(1.0_wp))) &
        bad_q = max(bad_q, q)
    end do
    !$omp end parallel do
    if (bad_q > 0) bad_j = jacobian(tb%f(:, bad_q))
    tb%w_int = tb%w_int + dw
    tb%w_plastic = tb%w_plastic + dwp
    !$omp parallel do default(none) shared(tb) schedule(static)
    do q = 1, tb%np
      tb%a(:, q) = (tb%fext(:, q) - tb%fint(:, q))/tb%t%mass(q)
    end do
    !$omp end parallel do
    tb%wall = tb%wall + [t1 - t0, t2 - t1, omp_get_wtime() - t2]
  end subroutine tl_body_forces
end module tl_body_m
