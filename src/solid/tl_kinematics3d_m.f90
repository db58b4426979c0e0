!> Hot kernels of the total-Lagrangian solver in three dimensions (dims_3d of dims_m; issue
!! 23), the counterparts of tl_kinematics_m's plane kernels on the tables of rkpm_tl3d_m:
!! deformation gradients at the integration points, the rate of deformation and spin between
!! two configurations (the midpoint Cayley form, so a rigid rotation gives D = 0 exactly), the
!! first Piola-Kirchhoff stress from the Kirchhoff stress, the internal force (eq. 72)
!! gathered per particle, and the physical positions x_J = X_J + sum_I N_I(X_J) d_I.
!!
!! Layouts (dims_3d): F(9, nq), P(9, nq) row by row, F_cj at 3 (c - 1) + j; symmetric tensors
!! (6, nq) 11, 22, 33, 23, 13, 12; spin W (3, nq) as W23, W13, W12; d(3, np) coefficients (m).
module tl_kinematics3d_m
  use kinds_m, only: wp
  use solid_tables_m, only: solid_tables_t
  implicit none
  private
  public :: deformation_gradient_3d, jacobian_3d, rate_of_deformation_3d, piola_stress_3d
  public :: internal_force_3d, physical_positions_3d, f_identity_3d, inverse_3x3

  !> F = I in the 3D layout.
  real(wp), parameter :: f_identity_3d(9) = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp]

contains

  !> F (9, nq) at every integration point from the coefficients d (3, np):
  !! F_cj = delta_cj + sum_I d_cI dN^c_I/dX_j.
  subroutine deformation_gradient_3d(t, d, f)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: d(:, :)
    real(wp), intent(out) :: f(:, :)
    integer :: q, e, i
    real(wp) :: a(9)
    !$omp parallel do default(none) shared(t, d, f) private(e, i, a) schedule(static)
    do q = 1, t%nq
      a = 0.0_wp
      do e = t%ptr(q), t%ptr(q + 1) - 1
        i = t%nbr(e)
        a(1:3) = a(1:3) + d(1, i)*t%g(1:3, e)
        a(4:6) = a(4:6) + d(2, i)*t%g(4:6, e)
        a(7:9) = a(7:9) + d(3, i)*t%g(7:9, e)
      end do
      f(:, q) = f_identity_3d + a
    end do
    !$omp end parallel do
  end subroutine deformation_gradient_3d

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

  !> D (6, nq) and W (3, nq) between F0 and F1 a step dt apart: L dt = (F1 - F0) Fm^-1 with
  !! the midpoint Fm = (F0 + F1)/2 (a rigid rotation gives D = 0 exactly).
  subroutine rate_of_deformation_3d(nq, dt, f0, f1, d, w)
    integer, intent(in) :: nq
    real(wp), intent(in) :: dt, f0(:, :), f1(:, :)
    real(wp), intent(out) :: d(:, :), w(:, :)
    integer :: q, r, c
    real(wp) :: fmi(9), df(9), l(3, 3), rdt
    rdt = 1.0_wp/dt
    !$omp parallel do default(none) shared(nq, f0, f1, d, w, rdt) private(fmi, df, l, r, c) &
    !$omp schedule(static)
    do q = 1, nq
      fmi = inverse_3x3(0.5_wp*(f0(:, q) + f1(:, q)))
      df = f1(:, q) - f0(:, q)
      do r = 1, 3
        do c = 1, 3
          l(r, c) = (df(3*r - 2)*fmi(c) + df(3*r - 1)*fmi(3 + c) + df(3*r)*fmi(6 + c))*rdt
        end do
      end do
      d(:, q) = [l(1, 1), l(2, 2), l(3, 3), 0.5_wp*(l(2, 3) + l(3, 2)), &
        0.5_wp*(l(1, 3) + l(3, 1)), 0.5_wp*(l(1, 2) + l(2, 1))]
      w(:, q) = [0.5_wp*(l(2, 3) - l(3, 2)), 0.5_wp*(l(1, 3) - l(3, 1)), &
        0.5_wp*(l(1, 2) - l(2, 1))]
    end do
    !$omp end parallel do
  end subroutine rate_of_deformation_3d

  !> P = tau F^-T: P_iJ = tau_ik (F^-1)_Jk, tau (6, nq) in Voigt's order.
  subroutine piola_stress_3d(nq, f, tau, p)
    integer, intent(in) :: nq
    real(wp), intent(in) :: f(:, :), tau(:, :)
    real(wp), intent(out) :: p(:, :)
    integer :: q, i, jj
    real(wp) :: fi(9), s(3, 3)
    !$omp parallel do default(none) shared(nq, f, tau, p) private(fi, s, i, jj) &
    !$omp schedule(static)
    do q = 1, nq
      fi = inverse_3x3(f(:, q))
      s = reshape([tau(1, q), tau(6, q), tau(5, q), tau(6, q), tau(2, q), tau(4, q), &
        tau(5, q), tau(4, q), tau(3, q)], [3, 3])
      do i = 1, 3
        do jj = 1, 3
          p(3*(i - 1) + jj, q) = s(i, 1)*fi(3*(jj - 1) + 1) + s(i, 2)*fi(3*(jj - 1) + 2) &
            + s(i, 3)*fi(3*(jj - 1) + 3)
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine piola_stress_3d

  !> f_int (3, np) = sum_L W_L P_L : grad N_I (eq. 72): f_cI = sum_L W_L sum_j P_cj
  !! dN^c_I/dX_j, gathered per particle over the transpose (no races).
  subroutine internal_force_3d(t, p, fint)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: fint(:, :)
    integer :: i, k, q
    real(wp) :: f(3), w
    !$omp parallel do default(none) shared(t, p, fint) private(k, q, f, w) schedule(static)
    do i = 1, t%np
      f = 0.0_wp
      do k = t%tptr(i), t%tptr(i + 1) - 1
        q = t%tq(k)
        w = t%wgt(q)
        f(1) = f(1) + w*dot_product(p(1:3, q), t%tg(1:3, k))
        f(2) = f(2) + w*dot_product(p(4:6, q), t%tg(4:6, k))
        f(3) = f(3) + w*dot_product(p(7:9, q), t%tg(7:9, k))
      end do
      fint(:, i) = f
    end do
    !$omp end parallel do
  end subroutine internal_force_3d

  !> Physical positions x (3, np) from reference x0 and coefficients d.
  subroutine physical_positions_3d(t, x0, d, x)
    type(solid_tables_t), intent(in) :: t
    real(wp), intent(in) :: x0(:, :), d(:, :)
    real(wp), intent(out) :: x(:, :)
    integer :: j, e
    real(wp) :: u(3)
    !$omp parallel do default(none) shared(t, x0, d, x) private(e, u) schedule(static)
    do j = 1, t%np
      u = 0.0_wp
      do e = t%pptr(j), t%pptr(j + 1) - 1
        u = u + t%pn(:, e)*d(:, t%pnbr(e))
      end do
      x(:, j) = x0(:, j) + u
    end do
    !$omp end parallel do
  end subroutine physical_positions_3d
end module tl_kinematics3d_m
