!> Critical time step of the central-difference scheme for a body, dt_crit = 2/omega_max,
!! with omega_max^2 the largest eigenvalue of M^-1 K (lumped M, small-strain elastic K built
!! from the solver's own tables) found by power iteration. Also the simple estimate
!! h_min/c_d (smallest spacing over the dilatational wave speed) for the log.
module stable_step_m
  use kinds_m, only: wp
  use solid_m, only: solid_t
  use tl_kinematics_m, only: deformation_gradient, internal_force, stabilization_force
  implicit none
  private
  public :: critical_step, spacing_step

contains

  !> h_min / c_d (s).
  pure real(wp) function spacing_step(tb) result(dt)
    type(solid_t), intent(in) :: tb
    dt = tb%t%hmin/tb%mat%dilatational_speed()
  end function spacing_step

  !> 2/omega_max by power iteration on M^-1 K (60 iterations from a saw-tooth start, which
  !! is close to the highest mode of a lattice); prescribed components are held at zero.
  !! The Rayleigh quotient converges from below, so the step is padded by 2% (the result
  !! of 60 iterations is within 1% of a converged value on lattice bodies).
  function critical_step(tb) result(dt)
    type(solid_t), intent(in) :: tb
    real(wp) :: dt
    real(wp), allocatable :: x(:, :), y(:, :), f(:, :), p(:, :), sw(:, :)
    real(wp) :: lam, mu, eps(4), tr, omega2, nrm, es
    integer :: it, q, i
    allocate(x(2, tb%np), y(2, tb%np), f(5, tb%nq), p(5, tb%nq), sw(4, tb%nq))
    lam = tb%mat%lambda
    mu = tb%mat%g
    do i = 1, tb%np
      x(:, i) = real(1 - 2*mod(i, 2), wp)*[1.0_wp, -1.0_wp] + 0.1_wp*real(mod(i, 7), wp)
    end do
    where (tb%pres) x = 0.0_wp
    omega2 = 0.0_wp
    do it = 1, 60
      nrm = sqrt(sum(spread(tb%t%mass, 1, 2)*x*x))
      x = x/nrm
      call deformation_gradient(tb%t, x, f)
      do q = 1, tb%nq
        eps = [f(1, q) - 1.0_wp, f(4, q) - 1.0_wp, f(5, q) - 1.0_wp, 0.5_wp*(f(2, q) + f(3, q))]
        tr = eps(1) + eps(2) + eps(3)
        p(:, q) = [lam*tr + 2.0_wp*mu*eps(1), 2.0_wp*mu*eps(4), 2.0_wp*mu*eps(4), &
          lam*tr + 2.0_wp*mu*eps(2), lam*tr + 2.0_wp*mu*eps(3)]
      end do
      call internal_force(tb%t, p, y)
      if (tb%stab_normal > 0.0_wp) call stabilization_force(tb%t, x, tb%stab_normal, &
        tb%stab_shear, sw, y, es)
      where (tb%pres) y = 0.0_wp
      omega2 = sum(x*y)
      x(1, :) = y(1, :)/tb%t%mass
      x(2, :) = y(2, :)/tb%t%mass
    end do
    dt = 2.0_wp/sqrt(1.02_wp*omega2)
  end function critical_step
end module stable_step_m
