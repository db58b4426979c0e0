!> Hot kernels of the total-Lagrangian solver in three dimensions (dims_3d of dims_m; issue
!! 23), the counterparts of tl_kinematics_m's plane kernels on the tables of rkpm_tl3d_m:
!! deformation gradients at the integration points, the rate of deformation and spin between
!! two configurations (the midpoint Cayley form, so a rigid rotation gives D = 0 exactly), the
!! first Piola-Kirchhoff stress from the Kirchhoff stress, the internal force (eq. 72)
!! gathered per particle, and the physical positions x_J = X_J + sum_I N_I(X_J) d_I.
!!
!! Layouts (dims_3d): F(9, nq), P(9, nq) row by row, F_cj at 3 (c - 1) + j; symmetric tensors
!! (6, nq) 11, 22, 33, 23, 13, 12; spin W (3, nq) as W23, W13, W12; d(3, np) coefficients (m).
!! The tables are compact: the three components share one shape function, so g (3, nnz)
!! holds dN/dX_j once, gs (3, nnz) the half-cell differences along X_j, pn (1, nnzp) N;
!! or, folded across symmetry planes (dims_3d_folded: ngrad = 9), per component: g and gs
!! (9, nnz) with component c's at 3 (c - 1) + 1..3, pn (3, nnzp).
!! The stabilization stresses s (9, nq) are indexed (c, j) row by row like F: component c's
!! half-cell gradient along X_j.
!! The plane kernels of tl_kinematics_m hand tables of dims_3d to these, so callers
!! (solid_m, stable_step_m) see one interface.
module tl_kinematics3d_m
  use kinds_m, only: wp
  use solid_tables_m, only: solid_tables_t
  implicit none
  private
  public :: deformation_gradient_3d, jacobian_3d, rate_of_deformation_3d, piola_stress_3d
  public :: internal_force_3d, physical_positions_3d, f_identity_3d, inverse_3x3
  public :: deformation_gradient_list_3d, rate_of_deformation_list_3d, piola_stress_list_3d, &
    internal_force_list_3d, stabilization_force_3d, linear_elastic_piola_3d, stretch2_min_3d

  !> F = I in the 3D layout.
  real(wp), parameter :: f_identity_3d(9) = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp]
  !> the stabilization stress (c, j) is normal (1) when c = j, shear (2) otherwise
  integer, parameter :: stab_kind(9) = [1, 2, 2, 2, 1, 2, 2, 2, 1]

contains

  !> P of the linear elastic law at the displacement gradient F - I (small strain, Lame
  !! constants lam, mu; Pa): the operator K of the critical-step power iteration.
  pure subroutine linear_elastic_piola_3d(lam, mu, f, p)
    real(wp), intent(in) :: lam, mu, f(9)
    real(wp), intent(out) :: p(9)
    real(wp) :: tr, s12, s13, s23
    tr = f(1) + f(5) + f(9) - 3.0_wp
    s12 = mu*(f(2) + f(4))
    s13 = mu*(f(3) + f(7))
    s23 = mu*(f(6) + f(8))
    p = [lam*tr + 2.0_wp*mu*(f(1) - 1.0_wp), s12, s13, s12, lam*tr + 2.0_wp*mu*(f(5) - 1.0_wp), &
      s23, s13, s23, lam*tr + 2.0_wp*mu*(f(9) - 1.0_wp)]
  end subroutine linear_elastic_piola_3d

  !> F (9, nq) at every integration point from the coefficients d (3, np):
  !! F_cj = delta_cj + sum_I d_cI dN_I/dX_j. With stab = [c_normal, c_shear] given, the
  !! same pass forms the SCNI stabilization stresses s (9, nq) and their energy (see
  !! stabilization_force_3d); with active given, only the marked points (quiet points keep
  !! F = I and s = 0); with energy_q (nq) each point's share of the energy.
  subroutine deformation_gradient_3d(t, d, f, stab, s, energy, active, energy_q)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :)
    real(wp), intent(inout) :: f(:, :)
    real(wp), intent(in), optional :: stab(2)
    real(wp), intent(inout), optional :: s(:, :)
    real(wp), intent(out), optional :: energy
    logical, intent(in), optional :: active(:)
    real(wp), intent(inout), optional :: energy_q(:)
    integer :: q
    real(wp) :: en, eq
    logical :: with_stab, masked, each
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
        call point_f_stab(t, d, q, stab, f(:, q), s(:, q), eq)
        en = en + eq
        if (each) energy_q(q) = eq
      else
        call point_f(t, d, q, f(:, q))
      end if
    end do
    !$omp end parallel do
    if (present(energy)) energy = en
  end subroutine deformation_gradient_3d

  !> F (and with stab the stabilization stresses) at the points list(1:n) only.
  subroutine deformation_gradient_list_3d(t, d, f, list, n, stab, s, energy, energy_q)
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
    with_stab = present(stab)
    each = present(energy_q)
    en = 0.0_wp
    !$omp parallel do default(none) shared(t, d, f, list, n, stab, s, with_stab, each, &
    !$omp energy_q) private(eq) reduction(+: en) schedule(static)
    do k = 1, n
      if (with_stab) then
        call point_f_stab(t, d, list(k), stab, f(:, list(k)), s(:, list(k)), eq)
        en = en + eq
        if (each) energy_q(list(k)) = eq
      else
        call point_f(t, d, list(k), f(:, list(k)))
      end if
    end do
    !$omp end parallel do
    if (present(energy)) energy = en
  end subroutine deformation_gradient_list_3d

  !> F (9) at point q.
  pure subroutine point_f(t, d, q, f)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :)
    integer, intent(in) :: q
    real(wp), intent(out) :: f(9)
    integer :: e, i
    real(wp) :: a(9)
    a = 0.0_wp
    if (t%dims%ngrad == 3) then
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        a(1:3) = a(1:3) + d(1, i)*t%g(1:3, e)
        a(4:6) = a(4:6) + d(2, i)*t%g(1:3, e)
        a(7:9) = a(7:9) + d(3, i)*t%g(1:3, e)
      end do
    else
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        a(1:3) = a(1:3) + d(1, i)*t%g(1:3, e)
        a(4:6) = a(4:6) + d(2, i)*t%g(4:6, e)
        a(7:9) = a(7:9) + d(3, i)*t%g(7:9, e)
      end do
    end if
    f = f_identity_3d + a
  end subroutine point_f

  !> F (9), the stabilization stresses s (9) and their energy at point q, one pass.
  pure subroutine point_f_stab(t, d, q, stab, f, s, energy)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :), stab(2)
    integer, intent(in) :: q
    real(wp), intent(out) :: f(9), s(9), energy
    integer :: e, i
    real(wp) :: a(9), dh(9)
    a = 0.0_wp
    dh = 0.0_wp
    if (t%dims%ngrad == 3) then
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        a(1:3) = a(1:3) + d(1, i)*t%g(1:3, e)
        a(4:6) = a(4:6) + d(2, i)*t%g(1:3, e)
        a(7:9) = a(7:9) + d(3, i)*t%g(1:3, e)
        dh(1:3) = dh(1:3) + d(1, i)*t%gs(1:3, e)
        dh(4:6) = dh(4:6) + d(2, i)*t%gs(1:3, e)
        dh(7:9) = dh(7:9) + d(3, i)*t%gs(1:3, e)
      end do
    else
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        a(1:3) = a(1:3) + d(1, i)*t%g(1:3, e)
        a(4:6) = a(4:6) + d(2, i)*t%g(4:6, e)
        a(7:9) = a(7:9) + d(3, i)*t%g(7:9, e)
        dh(1:3) = dh(1:3) + d(1, i)*t%gs(1:3, e)
        dh(4:6) = dh(4:6) + d(2, i)*t%gs(4:6, e)
        dh(7:9) = dh(7:9) + d(3, i)*t%gs(7:9, e)
      end do
    end if
    call stab_stress(t%ws(:, q), stab, dh, s)
    energy = 0.5_wp*sum(s*dh)
    f = f_identity_3d + a
  end subroutine point_f_stab

  !> s_cj = W_j c_kind dh_cj: the half cell along X_j's weight, c_normal for c = j and
  !! c_shear otherwise.
  pure subroutine stab_stress(ws, stab, dh, s)
    real(wp), intent(in) :: ws(3), stab(2), dh(9)
    real(wp), intent(out) :: s(9)
    integer :: c, j
    do c = 1, 3
      do j = 1, 3
        s(3*(c - 1) + j) = ws(j)*stab(stab_kind(3*(c - 1) + j))*dh(3*(c - 1) + j)
      end do
    end do
  end subroutine stab_stress

  !> J = det F (F row by row).
  pure real(wp) function jacobian_3d(f) result(j)
    real(wp), intent(in) :: f(9)
    j = f(1)*(f(5)*f(9) - f(6)*f(8)) - f(2)*(f(4)*f(9) - f(6)*f(7)) &
      + f(3)*(f(4)*f(8) - f(5)*f(7))
  end function jacobian_3d

  !> The inverse of a 3 x 3 matrix stored row by row (its cofactors over the determinant).
  pure function inverse_3x3(f) result(fi)
    real(wp), intent(in) :: f(9)
    real(wp) :: fi(9), det
    det = jacobian_3d(f)
    fi(1) = f(5)*f(9) - f(6)*f(8)
    fi(2) = f(3)*f(8) - f(2)*f(9)
    fi(3) = f(2)*f(6) - f(3)*f(5)
    fi(4) = f(6)*f(7) - f(4)*f(9)
    fi(5) = f(1)*f(9) - f(3)*f(7)
    fi(6) = f(3)*f(4) - f(1)*f(6)
    fi(7) = f(4)*f(8) - f(5)*f(7)
    fi(8) = f(2)*f(7) - f(1)*f(8)
    fi(9) = f(1)*f(5) - f(2)*f(4)
    fi = fi/det
  end function inverse_3x3

  !> The square of the smallest principal stretch of F (9): the smallest eigenvalue of
  !! C = F^T F, by the trigonometric closed form of a symmetric 3 x 3 matrix's eigenvalues
  !! (Smith, CACM 4 (1961)), clipped at 0 against round-off.
  pure real(wp) function stretch2_min_3d(f) result(s2)
    real(wp), intent(in) :: f(9)
    real(wp) :: c(3, 3), fm(3, 3), q, p1, p2, p, r, phi, b(3, 3)
    integer :: k
    real(wp), parameter :: pi = acos(-1.0_wp)
    fm = transpose(reshape(f, [3, 3]))
    c = matmul(transpose(fm), fm)
    p1 = c(1, 2)**2 + c(1, 3)**2 + c(2, 3)**2
    q = (c(1, 1) + c(2, 2) + c(3, 3))/3.0_wp
    if (p1 <= epsilon(1.0_wp)**2*q*q) then
      s2 = max(min(c(1, 1), c(2, 2), c(3, 3)), 0.0_wp)
      return
    end if
    p2 = (c(1, 1) - q)**2 + (c(2, 2) - q)**2 + (c(3, 3) - q)**2 + 2.0_wp*p1
    p = sqrt(p2/6.0_wp)
    b = c
    do k = 1, 3
      b(k, k) = b(k, k) - q
    end do
    b = b/p
    r = 0.5_wp*(b(1, 1)*(b(2, 2)*b(3, 3) - b(2, 3)*b(3, 2)) &
      - b(1, 2)*(b(2, 1)*b(3, 3) - b(2, 3)*b(3, 1)) + b(1, 3)*(b(2, 1)*b(3, 2) - b(2, 2)*b(3, 1)))
    r = max(-1.0_wp, min(1.0_wp, r))
    phi = acos(r)/3.0_wp
    ! the eigenvalues are q + 2 p cos(phi + 2 pi k/3); the smallest is k = 1
    s2 = max(q + 2.0_wp*p*cos(phi + 2.0_wp*pi/3.0_wp), 0.0_wp)
  end function stretch2_min_3d

  !> D (6, nq) and W (3, nq) between F0 and F1 a step dt apart: L dt = (F1 - F0) Fm^-1 with
  !! the midpoint Fm = (F0 + F1)/2 (a rigid rotation gives D = 0 exactly).
  subroutine rate_of_deformation_3d(nq, dt, f0, f1, d, w)
    integer, intent(in) :: nq
    real(wp), intent(in) :: dt, f0(:, :), f1(:, :)
    real(wp), intent(out) :: d(:, :), w(:, :)
    integer :: q
    real(wp) :: rdt
    rdt = 1.0_wp/dt
    !$omp parallel do default(none) shared(nq, f0, f1, d, w, rdt) schedule(static)
    do q = 1, nq
      call point_rate(rdt, f0(:, q), f1(:, q), d(:, q), w(:, q))
    end do
    !$omp end parallel do
  end subroutine rate_of_deformation_3d

  !> rate_of_deformation_3d at the points list(1:n) only.
  subroutine rate_of_deformation_list_3d(dt, f0, f1, d, w, list, n)
    real(wp), intent(in) :: dt, f0(:, :), f1(:, :)
    real(wp), intent(inout) :: d(:, :), w(:, :)
    integer, intent(in) :: list(:), n
    integer :: k, q
    real(wp) :: rdt
    rdt = 1.0_wp/dt
    !$omp parallel do default(none) shared(f0, f1, d, w, rdt, list, n) private(q) &
    !$omp schedule(static)
    do k = 1, n
      q = list(k)
      call point_rate(rdt, f0(:, q), f1(:, q), d(:, q), w(:, q))
    end do
    !$omp end parallel do
  end subroutine rate_of_deformation_list_3d

  !> D (6) and W (3) of one point (rate_of_deformation_3d), rdt = 1/dt.
  pure subroutine point_rate(rdt, f0, f1, d, w)
    real(wp), intent(in) :: rdt, f0(9), f1(9)
    real(wp), intent(out) :: d(6), w(3)
    real(wp) :: fmi(9), df(9), l(3, 3)
    integer :: r, c
    fmi = inverse_3x3(0.5_wp*(f0 + f1))
    df = f1 - f0
    do r = 1, 3
      do c = 1, 3
        l(r, c) = (df(3*r - 2)*fmi(c) + df(3*r - 1)*fmi(3 + c) + df(3*r)*fmi(6 + c))*rdt
      end do
    end do
    d = [l(1, 1), l(2, 2), l(3, 3), 0.5_wp*(l(2, 3) + l(3, 2)), 0.5_wp*(l(1, 3) + l(3, 1)), &
      0.5_wp*(l(1, 2) + l(2, 1))]
    w = [0.5_wp*(l(2, 3) - l(3, 2)), 0.5_wp*(l(1, 3) - l(3, 1)), 0.5_wp*(l(1, 2) - l(2, 1))]
  end subroutine point_rate

  !> P = tau F^-T: P_iJ = tau_ik (F^-1)_Jk, tau (6, nq) in Voigt's order.
  subroutine piola_stress_3d(nq, f, tau, p)
    integer, intent(in) :: nq
    real(wp), intent(in) :: f(:, :), tau(:, :)
    real(wp), intent(out) :: p(:, :)
    integer :: q
    !$omp parallel do default(none) shared(nq, f, tau, p) schedule(static)
    do q = 1, nq
      call point_piola(f(:, q), tau(:, q), p(:, q))
    end do
    !$omp end parallel do
  end subroutine piola_stress_3d

  !> piola_stress_3d at the points list(1:n) only.
  subroutine piola_stress_list_3d(f, tau, p, list, n)
    real(wp), intent(in) :: f(:, :), tau(:, :)
    real(wp), intent(inout) :: p(:, :)
    integer, intent(in) :: list(:), n
    integer :: k, q
    !$omp parallel do default(none) shared(f, tau, p, list, n) private(q) schedule(static)
    do k = 1, n
      q = list(k)
      call point_piola(f(:, q), tau(:, q), p(:, q))
    end do
    !$omp end parallel do
  end subroutine piola_stress_list_3d

  !> P (9) of one point from F (9) and tau (6).
  pure subroutine point_piola(f, tau, p)
    real(wp), intent(in) :: f(9), tau(6)
    real(wp), intent(out) :: p(9)
    real(wp) :: fi(9), s(3, 3)
    integer :: i, jj
    fi = inverse_3x3(f)
    s = reshape([tau(1), tau(6), tau(5), tau(6), tau(2), tau(4), tau(5), tau(4), tau(3)], &
      [3, 3])
    do i = 1, 3
      do jj = 1, 3
        p(3*(i - 1) + jj) = s(i, 1)*fi(3*(jj - 1) + 1) + s(i, 2)*fi(3*(jj - 1) + 2) &
          + s(i, 3)*fi(3*(jj - 1) + 3)
      end do
    end do
  end subroutine point_piola

  !> f_int (3, np) = sum_L W_L P_L : grad N_I (eq. 72): f_cI = sum_L W_L sum_j P_cj
  !! dN_I/dX_j, gathered per particle over the transpose (no races); with s given the
  !! stabilization stresses' forces in the same pass; with awake given only the marked
  !! nodes gather (the others get 0).
  subroutine internal_force_3d(t, p, fint, s, awake)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: fint(:, :)
    real(wp), intent(in), optional :: s(:, :)
    logical, intent(in), optional :: awake(:)
    integer :: i
    logical :: with_stab, masked
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
  end subroutine internal_force_3d

  !> internal_force_3d at the nodes list(1:n) only; the other nodes keep their values.
  subroutine internal_force_list_3d(t, p, fint, list, n, s)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(inout) :: fint(:, :)
    integer, intent(in) :: list(:), n
    real(wp), intent(in), optional :: s(:, :)
    integer :: j
    logical :: with_stab
    with_stab = present(s)
    !$omp parallel do default(none) shared(t, p, fint, list, n, s, with_stab) &
    !$omp schedule(static)
    do j = 1, n
      call node_force(t, p, list(j), with_stab, fint(:, list(j)), s)
    end do
    !$omp end parallel do
  end subroutine internal_force_list_3d

  !> The internal force (3) at node i, eq. (72), over its points in the transpose's order.
  pure subroutine node_force(t, p, i, with_stab, fi, s)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    integer, intent(in) :: i
    logical, intent(in) :: with_stab
    real(wp), intent(out) :: fi(3)
    real(wp), intent(in), optional :: s(:, :)
    integer :: k, q
    real(wp) :: f(3), w, g(3)
    f = 0.0_wp
    if (t%dims%ngrad /= 3) then
      call node_force_folded(t, p, i, with_stab, fi, s)
      return
    end if
    do k = t%tptr(i), t%tptr(i + 1) - 1
      q = t%tq(k)
      w = t%wgt(q)
      g = w*t%tg(1:3, k)
      f(1) = f(1) + p(1, q)*g(1) + p(2, q)*g(2) + p(3, q)*g(3)
      f(2) = f(2) + p(4, q)*g(1) + p(5, q)*g(2) + p(6, q)*g(3)
      f(3) = f(3) + p(7, q)*g(1) + p(8, q)*g(2) + p(9, q)*g(3)
      if (with_stab) then
        g = t%tgs(1:3, k)
        f(1) = f(1) + s(1, q)*g(1) + s(2, q)*g(2) + s(3, q)*g(3)
        f(2) = f(2) + s(4, q)*g(1) + s(5, q)*g(2) + s(6, q)*g(3)
        f(3) = f(3) + s(7, q)*g(1) + s(8, q)*g(2) + s(9, q)*g(3)
      end if
    end do
    fi = f
  end subroutine node_force

  !> node_force on folded tables (dims_3d_folded): component c's gradients at 3 (c - 1) + 1..3.
  pure subroutine node_force_folded(t, p, i, with_stab, fi, s)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    integer, intent(in) :: i
    logical, intent(in) :: with_stab
    real(wp), intent(out) :: fi(3)
    real(wp), intent(in), optional :: s(:, :)
    integer :: k, q, c
    real(wp) :: w
    fi = 0.0_wp
    do k = t%tptr(i), t%tptr(i + 1) - 1
      q = t%tq(k)
      w = t%wgt(q)
      do c = 1, 3
        fi(c) = fi(c) + w*dot_product(p(3*c - 2:3*c, q), t%tg(3*c - 2:3*c, k))
        if (with_stab) fi(c) = fi(c) + dot_product(s(3*c - 2:3*c, q), t%tgs(3*c - 2:3*c, k))
      end do
    end do
  end subroutine node_force_folded

  !> The SCNI sub-cell stabilization's forces added to fint and its energy (J), for the
  !! power iteration (tl_kinematics_m's stabilization_force in 3D): s (9, nq) work space.
  subroutine stabilization_force_3d(t, d, c_normal, c_shear, s, fint, energy)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :), c_normal, c_shear
    real(wp), intent(inout) :: s(:, :), fint(:, :)
    real(wp), intent(out) :: energy
    real(wp), allocatable :: f(:, :), p0(:, :), fs(:, :)
    allocate(f(9, t%nq), p0(9, t%nq), fs(3, t%np))
    call deformation_gradient_3d(t, d, f, [c_normal, c_shear], s, energy)
    p0 = 0.0_wp
    call internal_force_3d(t, p0, fs, s)
    fint = fint + fs
  end subroutine stabilization_force_3d

  !> Physical positions x (3, np) from reference x0 and coefficients d (for interpolating
  !! tables, element nodes, simply X + d).
  subroutine physical_positions_3d(t, x0, d, x)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: x0(:, :), d(:, :)
    real(wp), intent(out) :: x(:, :)
    integer :: j, e
    real(wp) :: u(3)
    if (t%interpolating) then
      !$omp parallel do default(none) shared(t, x0, d, x) schedule(static)
      do j = 1, t%np
        x(:, j) = x0(:, j) + d(:, j)
      end do
      !$omp end parallel do
      return
    end if
    if (t%dims%npos == 1) then
      !$omp parallel do default(none) shared(t, x0, d, x) private(e, u) schedule(static)
      do j = 1, t%np
        u = 0.0_wp
        do e = t%pptr(j), t%pptr(j + 1) - 1
          u = u + t%pn(1, e)*d(:, t%pnbr(e))
        end do
        x(:, j) = x0(:, j) + u
      end do
      !$omp end parallel do
    else
      ! (folded: each component its own N^c)
      !$omp parallel do default(none) shared(t, x0, d, x) private(e, u) schedule(static)
      do j = 1, t%np
        u = 0.0_wp
        do e = t%pptr(j), t%pptr(j + 1) - 1
          u = u + t%pn(:, e)*d(:, t%pnbr(e))
        end do
        x(:, j) = x0(:, j) + u
      end do
      !$omp end parallel do
    end if
  end subroutine physical_positions_3d
end module tl_kinematics3d_m
