!> Hot kernels of the total-Lagrangian solver in the plane (dims_plane of dims_m: plane
!! strain and axisymmetry), on the tables of rkpm_tl_m and cst4_m:
!! deformation gradients at the integration points, rate of deformation and spin between
!! two configurations, first Piola-Kirchhoff stress from Kirchhoff stress, the internal force
!! (eq. 72) gathered per particle, and physical positions x_J = X_J + sum_I N_I(X_J) d_I.
!!
!! Layouts (plane strain and axisymmetric share them; the hoop terms vanish in plane strain):
!!  F(5, nq), P(5, nq): components 11, 12, 21, 22, 33 (33 = hoop r/R in axisymmetry);
!!  tau(4, nq), d(4, nq): 11, 22, 33, 12 (symmetric); d(2, np): coefficients (m).
!!
!! The dimension is chosen once, by the tables (t%dims) or the extent of F: each public
!! kernel here hands 3D data (dims_3d) to its counterpart in tl_kinematics3d_m, so the
!! solid and the step estimate call one interface whatever the geometry. The spin differs
!! in shape (W12 (nq) here, W (3, nq) in 3D): rate_of_deformation takes it as (nspin, nq).
module tl_kinematics_m
  use kinds_m, only: wp
  use solid_tables_m, only: solid_tables_t
  use tl_kinematics3d_m, only: deformation_gradient_3d, deformation_gradient_list_3d, &
    rate_of_deformation_3d, rate_of_deformation_list_3d, piola_stress_3d, &
    piola_stress_list_3d, internal_force_3d, internal_force_list_3d, stabilization_force_3d, &
    physical_positions_3d, linear_elastic_piola_3d, jacobian_3d, f_identity_3d
  implicit none
  private
  public :: deformation_gradient, rate_of_deformation, piola_stress, internal_force
  public :: physical_positions, jacobian, stabilization_force, f_identity, linear_elastic_piola
  public :: deformation_gradient_list, rate_of_deformation_list, piola_stress_list, &
    internal_force_list

  !> F = I in the plane layout.
  real(wp), parameter :: f_identity(5) = [1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp]

contains

  !> P of the linear elastic law at the displacement gradient F - I (small strain, Lame
  !! constants lam, mu; Pa): the operator K of the critical-step power iteration.
  pure subroutine linear_elastic_piola(lam, mu, f, p)
    real(wp), intent(in) :: lam, mu, f(:)
    real(wp), intent(out) :: p(:)
    real(wp) :: eps(4), tr
    if (size(f) == size(f_identity_3d)) then
      call linear_elastic_piola_3d(lam, mu, f, p)
      return
    end if
    eps = [f(1) - 1.0_wp, f(4) - 1.0_wp, f(5) - 1.0_wp, 0.5_wp*(f(2) + f(3))]
    tr = eps(1) + eps(2) + eps(3)
    p = [lam*tr + 2.0_wp*mu*eps(1), 2.0_wp*mu*eps(4), 2.0_wp*mu*eps(4), &
      lam*tr + 2.0_wp*mu*eps(2), lam*tr + 2.0_wp*mu*eps(3)]
  end subroutine linear_elastic_piola

  !> F at every integration point from the coefficients d (2, np). With stab = [c_normal,
  !! c_shear] given, the same pass also forms the SCNI stabilization stresses s (4, nq) and
  !! their energy (see stabilization_force), and with energy_q (nq) each point's share of it
  !! (the points not evaluated keep theirs).
  subroutine deformation_gradient(t, d, f, stab, s, energy, active, energy_q)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :)
    real(wp), intent(inout) :: f(:, :)
    real(wp), intent(in), optional :: stab(2)
    real(wp), intent(inout), optional :: s(:, :)
    real(wp), intent(out), optional :: energy
    !> only the points marked here (the others keep their F and s: quiet points in uniform
    !! translation, F = I)
    logical, intent(in), optional :: active(:)
    real(wp), intent(inout), optional :: energy_q(:)
    integer :: q
    real(wp) :: en, eq
    logical :: with_stab, masked, each
    if (t%dims%ndim == 3) then
      call deformation_gradient_3d(t, d, f, stab, s, energy, active, energy_q)
      return
    end if
    with_stab = present(stab)
    masked = present(active)
    each = present(energy_q)
    en = 0.0_wp
    !$omp parallel do default(none) shared(t, d, f, stab, s, with_stab, masked, active, &
    !$omp each, energy_q) private(eq) reduction(+: en) schedule(static)
    do q = 1, t%nq
      if (masked) then
        if (.not. active(q)) cycle
      end if
      if (with_stab) then
        call point_deformation_gradient_stab(t, d, q, stab, f(:, q), s(:, q), eq)
        en = en + eq
        if (each) energy_q(q) = eq
      else
        call point_deformation_gradient(t, d, q, f(:, q))
      end if
    end do
    !$omp end parallel do
    if (present(energy)) energy = en
  end subroutine deformation_gradient

  !> F at the integration points list(1:n) only; with stab given, also their SCNI
  !! stabilization stresses s and their energy (as deformation_gradient, energy_q too).
  subroutine deformation_gradient_list(t, d, f, list, n, stab, s, energy, energy_q)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :)
    real(wp), intent(inout) :: f(:, :)
    integer, intent(in) :: list(:), n
    real(wp), intent(in), optional :: stab(2)
    real(wp), intent(inout), optional :: s(:, :)
    real(wp), intent(out), optional :: energy
    real(wp), intent(inout), optional :: energy_q(:)
    integer :: k
    real(wp) :: en, eq
    logical :: with_stab, each
    if (t%dims%ndim == 3) then
      call deformation_gradient_list_3d(t, d, f, list, n, stab, s, energy, energy_q)
      return
    end if
    with_stab = present(stab)
    each = present(energy_q)
    en = 0.0_wp
    !$omp parallel do default(none) shared(t, d, f, list, n, stab, s, with_stab, each, &
    !$omp energy_q) private(eq) reduction(+: en) schedule(static)
    do k = 1, n
      if (with_stab) then
        call point_deformation_gradient_stab(t, d, list(k), stab, f(:, list(k)), &
          s(:, list(k)), eq)
        en = en + eq
        if (each) energy_q(list(k)) = eq
      else
        call point_deformation_gradient(t, d, list(k), f(:, list(k)))
      end if
    end do
    !$omp end parallel do
    if (present(energy)) energy = en
  end subroutine deformation_gradient_list

  !> F (5), the stabilization stresses s (4) and their energy at point q (one pass over its
  !! row: see deformation_gradient).
  pure subroutine point_deformation_gradient_stab(t, d, q, stab, f, s, energy)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :), stab(2)
    integer, intent(in) :: q
    real(wp), intent(out) :: f(5), s(4), energy
    integer :: e, i
    real(wp) :: a11, a12, a21, a22, a33, dh(4)
    a11 = 0.0_wp
    a12 = 0.0_wp
    a21 = 0.0_wp
    a22 = 0.0_wp
    a33 = 0.0_wp
    dh = 0.0_wp
    do e = t%ptr(q), t%ptr(q + 1) - 1
      i = t%nbr(e)
      a11 = a11 + d(1, i)*t%g(1, e)
      a12 = a12 + d(1, i)*t%g(2, e)
      a21 = a21 + d(2, i)*t%g(3, e)
      a22 = a22 + d(2, i)*t%g(4, e)
      a33 = a33 + d(1, i)*t%h(e)
      dh(1) = dh(1) + d(1, i)*t%gs(1, e)
      dh(2) = dh(2) + d(2, i)*t%gs(2, e)
      dh(3) = dh(3) + d(1, i)*t%gs(3, e)
      dh(4) = dh(4) + d(2, i)*t%gs(4, e)
    end do
    s = [t%ws(1, q)*stab(1)*dh(1), t%ws(1, q)*stab(2)*dh(2), t%ws(2, q)*stab(2)*dh(3), &
      t%ws(2, q)*stab(1)*dh(4)]
    energy = 0.5_wp*sum(s*dh)
    f = [1.0_wp + a11, a12, a21, 1.0_wp + a22, 1.0_wp + a33]
  end subroutine point_deformation_gradient_stab

  !> F (5) at integration point q from the coefficients d.
  pure subroutine point_deformation_gradient(t, d, q, f)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :)
    integer, intent(in) :: q
    real(wp), intent(out) :: f(5)
    integer :: e, i
    real(wp) :: a11, a12, a21, a22, a33
    a11 = 0.0_wp
    a12 = 0.0_wp
    a21 = 0.0_wp
    a22 = 0.0_wp
    a33 = 0.0_wp
    do e = t%ptr(q), t%ptr(q + 1) - 1
      i = t%nbr(e)
      a11 = a11 + d(1, i)*t%g(1, e)
      a12 = a12 + d(1, i)*t%g(2, e)
      a21 = a21 + d(2, i)*t%g(3, e)
      a22 = a22 + d(2, i)*t%g(4, e)
      a33 = a33 + d(1, i)*t%h(e)
    end do
    f = [1.0_wp + a11, a12, a21, 1.0_wp + a22, 1.0_wp + a33]
  end subroutine point_deformation_gradient

  !> J = det F (the plane layout, or the 3D one by the extent of f).
  pure real(wp) function jacobian(f) result(j)
    real(wp), intent(in) :: f(:)
    if (size(f) == size(f_identity_3d)) then
      j = jacobian_3d(f)
    else
      j = (f(1)*f(4) - f(2)*f(3))*f(5)
    end if
  end function jacobian

  !> D (4, nq) and W12 (1, nq) between F0 and F1 a step dt apart: L dt = (F1 - F0) Fm^-1
  !! with the midpoint Fm = (F0 + F1)/2, so a rigid rotation gives D = 0 exactly (Cayley
  !! form). In 3D D (6, nq) and W (3, nq).
  subroutine rate_of_deformation(nq, dt, f0, f1, d, w)
    integer, intent(in) :: nq
    real(wp), intent(in) :: dt, f0(:, :), f1(:, :)
    real(wp), intent(out) :: d(:, :), w(:, :)
    integer :: q
    real(wp) :: rdt
    if (size(f0, 1) == size(f_identity_3d)) then
      call rate_of_deformation_3d(nq, dt, f0, f1, d, w)
      return
    end if
    rdt = 1.0_wp/dt
    !$omp parallel do default(none) shared(nq, f0, f1, d, w, rdt) schedule(static)
    do q = 1, nq
      call point_rate(rdt, f0(:, q), f1(:, q), d(:, q), w(1, q))
    end do
    !$omp end parallel do
  end subroutine rate_of_deformation

  !> rate_of_deformation at the integration points list(1:n) only.
  subroutine rate_of_deformation_list(dt, f0, f1, d, w, list, n)
    real(wp), intent(in) :: dt, f0(:, :), f1(:, :)
    real(wp), intent(inout) :: d(:, :), w(:, :)
    integer, intent(in) :: list(:), n
    integer :: k, q
    real(wp) :: rdt
    if (size(f0, 1) == size(f_identity_3d)) then
      call rate_of_deformation_list_3d(dt, f0, f1, d, w, list, n)
      return
    end if
    rdt = 1.0_wp/dt
    !$omp parallel do default(none) shared(f0, f1, d, w, rdt, list, n) private(q) &
    !$omp schedule(static)
    do k = 1, n
      q = list(k)
      call point_rate(rdt, f0(:, q), f1(:, q), d(:, q), w(1, q))
    end do
    !$omp end parallel do
  end subroutine rate_of_deformation_list

  !> D (4) and W12 of one point between f0 and f1, rdt = 1/dt (see rate_of_deformation).
  pure subroutine point_rate(rdt, f0, f1, d, w12)
    real(wp), intent(in) :: rdt, f0(5), f1(5)
    real(wp), intent(out) :: d(4), w12
    real(wp) :: fm(5), df(5), det, inv(4), l11, l12, l21, l22
    fm = 0.5_wp*(f0 + f1)
    df = f1 - f0
    det = fm(1)*fm(4) - fm(2)*fm(3)
    inv = [fm(4), -fm(2), -fm(3), fm(1)]/det
    l11 = df(1)*inv(1) + df(2)*inv(3)
    l12 = df(1)*inv(2) + df(2)*inv(4)
    l21 = df(3)*inv(1) + df(4)*inv(3)
    l22 = df(3)*inv(2) + df(4)*inv(4)
    d(1) = l11*rdt
    d(2) = l22*rdt
    d(3) = df(5)/fm(5)*rdt
    d(4) = 0.5_wp*(l12 + l21)*rdt
    w12 = 0.5_wp*(l12 - l21)*rdt
  end subroutine point_rate

  !> P = tau F^-T (P_iJ = tau_ik Finv_Jk); P33 = tau33/F33.
  subroutine piola_stress(nq, f, tau, p)
    integer, intent(in) :: nq
    real(wp), intent(in) :: f(:, :), tau(:, :)
    real(wp), intent(out) :: p(:, :)
    integer :: q
    if (size(f, 1) == size(f_identity_3d)) then
      call piola_stress_3d(nq, f, tau, p)
      return
    end if
    !$omp parallel do default(none) shared(nq, f, tau, p) schedule(static)
    do q = 1, nq
      call point_piola(f(:, q), tau(:, q), p(:, q))
    end do
    !$omp end parallel do
  end subroutine piola_stress

  !> piola_stress at the integration points list(1:n) only.
  subroutine piola_stress_list(f, tau, p, list, n)
    real(wp), intent(in) :: f(:, :), tau(:, :)
    real(wp), intent(inout) :: p(:, :)
    integer, intent(in) :: list(:), n
    integer :: k, q
    if (size(f, 1) == size(f_identity_3d)) then
      call piola_stress_list_3d(f, tau, p, list, n)
      return
    end if
    !$omp parallel do default(none) shared(f, tau, p, list, n) private(q) schedule(static)
    do k = 1, n
      q = list(k)
      call point_piola(f(:, q), tau(:, q), p(:, q))
    end do
    !$omp end parallel do
  end subroutine piola_stress_list

  !> P (5) of one point from F (5) and tau (4).
  pure subroutine point_piola(f, tau, p)
    real(wp), intent(in) :: f(5), tau(4)
    real(wp), intent(out) :: p(5)
    real(wp) :: det, i11, i12, i21, i22
    det = f(1)*f(4) - f(2)*f(3)
    i11 = f(4)/det
    i12 = -f(2)/det
    i21 = -f(3)/det
    i22 = f(1)/det
    ! P_iJ = tau_i1 Finv_J1 + tau_i2 Finv_J2
    p(1) = tau(1)*i11 + tau(4)*i12
    p(2) = tau(1)*i21 + tau(4)*i22
    p(3) = tau(4)*i11 + tau(2)*i12
    p(4) = tau(4)*i21 + tau(2)*i22
    p(5) = tau(3)/f(5)
  end subroutine point_piola

  !> f_int (2, np) = sum_L W_L P_L : grad N_I (eq. 72), gathered per particle (no races);
  !! with s given (stabilization stresses from deformation_gradient) their forces are added
  !! in the same pass.
  subroutine internal_force(t, p, fint, s, awake)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: fint(:, :)
    real(wp), intent(in), optional :: s(:, :)
    !> only the nodes marked here gather; the others get 0 (no active point touches them)
    logical, intent(in), optional :: awake(:)
    integer :: i
    logical :: with_stab, masked
    if (t%dims%ndim == 3) then
      call internal_force_3d(t, p, fint, s, awake)
      return
    end if
    with_stab = present(s)
    masked = present(awake)
    !$omp parallel do default(none) shared(t, p, fint, s, with_stab, masked, awake) &
    !$omp schedule(static)
    do i = 1, t%np
      if (masked) then
        if (.not. awake(i)) then
          fint(:, i) = 0.0_wp
          cycle
        end if
      end if
      call node_force(t, p, i, with_stab, fint(:, i), s)
    end do
    !$omp end parallel do
  end subroutine internal_force

  !> internal_force at the nodes list(1:n) only; the other nodes keep their values.
  subroutine internal_force_list(t, p, fint, list, n, s)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(inout) :: fint(:, :)
    integer, intent(in) :: list(:), n
    real(wp), intent(in), optional :: s(:, :)   !< stabilization stresses, as internal_force
    integer :: i, j
    logical :: with_stab
    if (t%dims%ndim == 3) then
      call internal_force_list_3d(t, p, fint, list, n, s)
      return
    end if
    with_stab = present(s)
    !$omp parallel do default(none) shared(t, p, fint, list, n, s, with_stab) &
    !$omp private(i) schedule(static)
    do j = 1, n
      i = list(j)
      call node_force(t, p, i, with_stab, fint(:, i), s)
    end do
    !$omp end parallel do
  end subroutine internal_force_list

  !> The internal force (2) at node i, eq. (72), over its points in the transpose's order
  !! (tg, th, tgs: g, h, gs of entry tent(k), stored in this loop's order), with the
  !! stabilization stresses s when with_stab.
  pure subroutine node_force(t, p, i, with_stab, fi, s)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    integer, intent(in) :: i
    logical, intent(in) :: with_stab
    real(wp), intent(out) :: fi(2)
    real(wp), intent(in), optional :: s(:, :)
    integer :: k, q
    real(wp) :: f1, f2, w
    f1 = 0.0_wp
    f2 = 0.0_wp
    do k = t%tptr(i), t%tptr(i + 1) - 1
      q = t%tq(k)
      w = t%wgt(q)
      f1 = f1 + w*(p(1, q)*t%tg(1, k) + p(2, q)*t%tg(2, k) + p(5, q)*t%th(k))
      f2 = f2 + w*(p(3, q)*t%tg(3, k) + p(4, q)*t%tg(4, k))
      if (with_stab) then
        f1 = f1 + s(1, q)*t%tgs(1, k) + s(3, q)*t%tgs(3, k)
        f2 = f2 + s(2, q)*t%tgs(2, k) + s(4, q)*t%tgs(4, k)
      end if
    end do
    fi = [f1, f2]
  end subroutine node_force

  !> SCNI sub-cell stabilization (after Puso, Chen, Zywicz, Elmer, IJNME 74 (2008)): the
  !! half-cell smoothed gradients differ from the cell's by dH (zero for linear fields, so
  !! the patch test is untouched); an elastic energy 1/2 sum W_h dH : c : dH with
  !! c = alpha (lambda + 2 mu) for the normal and alpha mu for the shear components penalises
  !! the modes the cell average cannot see (the saw-tooth of a uniform lattice). Adds its
  !! forces to fint and returns its energy (J, J/m in plane strain); s (4, nq) is work space.
  subroutine stabilization_force(t, d, c_normal, c_shear, s, fint, energy)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :), c_normal, c_shear
    real(wp), intent(inout) :: s(:, :), fint(:, :)
    real(wp), intent(out) :: energy
    integer :: q, e, i, k
    real(wp) :: dh(4), f1, f2
    if (t%dims%ndim == 3) then
      call stabilization_force_3d(t, d, c_normal, c_shear, s, fint, energy)
      return
    end if
    energy = 0.0_wp
    !$omp parallel do default(none) shared(t, d, c_normal, c_shear, s) private(e, i, dh) &
    !$omp reduction(+: energy) schedule(static)
    do q = 1, t%nq
      dh = 0.0_wp
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        dh(1) = dh(1) + d(1, i)*t%gs(1, e)
        dh(2) = dh(2) + d(2, i)*t%gs(2, e)
        dh(3) = dh(3) + d(1, i)*t%gs(3, e)
        dh(4) = dh(4) + d(2, i)*t%gs(4, e)
      end do
      s(:, q) = [t%ws(1, q)*c_normal*dh(1), t%ws(1, q)*c_shear*dh(2), &
        t%ws(2, q)*c_shear*dh(3), t%ws(2, q)*c_normal*dh(4)]
      energy = energy + 0.5_wp*sum(s(:, q)*dh)
    end do
    !$omp end parallel do
    !$omp parallel do default(none) shared(t, s, fint) private(k, e, q, f1, f2) schedule(static)
    do i = 1, t%np
      f1 = 0.0_wp
      f2 = 0.0_wp
      do k = t%tptr(i), t%tptr(i + 1) - 1
        e = t%tent(k)
        q = t%tq(k)
        f1 = f1 + s(1, q)*t%gs(1, e) + s(3, q)*t%gs(3, e)
        f2 = f2 + s(2, q)*t%gs(2, e) + s(4, q)*t%gs(4, e)
      end do
      fint(1, i) = fint(1, i) + f1
      fint(2, i) = fint(2, i) + f2
    end do
    !$omp end parallel do
  end subroutine stabilization_force

  !> Physical positions x (2, np) of the particles from reference X and coefficients d
  !! (for interpolating tables, finite-element nodes, simply X + d).
  subroutine physical_positions(t, x0, d, x)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: x0(:, :), d(:, :)
    real(wp), intent(out) :: x(:, :)
    integer :: j, e, i
    real(wp) :: u1, u2
    if (t%dims%ndim == 3) then
      call physical_positions_3d(t, x0, d, x)
      return
    end if
    if (t%interpolating) then
      !$omp parallel do default(none) shared(t, x0, d, x) schedule(static)
      do j = 1, t%np
        x(:, j) = x0(:, j) + d(:, j)
      end do
      !$omp end parallel do
      return
    end if
    !$omp parallel do default(none) shared(t, x0, d, x) private(e, i, u1, u2) schedule(static)
    do j = 1, t%np
      u1 = 0.0_wp
      u2 = 0.0_wp
      do e = t%pptr(j), t%pptr(j + 1) - 1
        i = t%pnbr(e)
        u1 = u1 + t%pn(1, e)*d(1, i)
        u2 = u2 + t%pn(2, e)*d(2, i)
      end do
      x(1, j) = x0(1, j) + u1
      x(2, j) = x0(2, j) + u2
    end do
    !$omp end parallel do
  end subroutine physical_positions
end module tl_kinematics_m
