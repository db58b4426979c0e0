!> Meshfree contact (Sections 2 and 5): detection by det(M) of the master at the slave
!! particles (eqs. 25-28), gap and normal from the master's surface polylines (eqs. 89-92,
!! with the tangential velocity corrected to v_t = (v.t) t), the impenetrability force of
!! the central-difference scheme (eq. 93) and Coulomb friction (eqs. 94-96).
!!
!! Conventions. Master polylines run counter-clockwise around the master (material on the
!! left), so the outward normal is n = (t_y, -t_x) (the paper's e3 x t for its clockwise
!! walk). Penetration means g < 0; only then is a force applied (detection is a screen, the
!! gap decides). Forces are computed at the slave particles' physical positions; the caller
!! spreads them onto the nodal coefficients (eq. 98, or eq. 99 for element nodes).
!!
!! Integrator factors (doc/contact.md): the step is u_{n+1} = u_n + dt v_n + dt^2/2 a_n, so adding
!! f/M to a_n moves the particle by dt^2/2 f/M: the normal force 2 M |g| / dt^2 puts a
!! predicted penetration g back on the surface exactly (eq. 93). Stick is treated the same
!! way: the tangential force -2 M s_t / dt^2 cancels the predicted tangential slip s_t of
!! the step relative to the master (s_t = dt v_t with v_t the step's mean relative
!! tangential velocity, eq. 90 corrected), so a sticking particle ends the step with no
!! relative tangential motion; slip applies mu |f_n| against the slip; the smaller force is
!! applied (eq. 96). mu = 0 skips all tangential work.
module contact_m
  use kinds_m, only: wp, i64
  use exact_sum_m, only: exact_sum_t
  use errors_m, only: error_t
  use neighbour_bins_m, only: bins_t, bins_build, bins_candidates, bins_cell_block, &
    bins_block_runs, bins_block_run
  use geometry_m, only: segment_distance
  implicit none
  private
  public :: master_surface_t, surface_build, surface_gap, contact_point_force, surface_update
  public :: contact_counters_t, closest_segment_update, surface_projection, surface_tie_tol
  public :: surface_subset, contact_point_force_3d

  !> The master's surface: segments a -> b (counter-clockwise around the master) and bins
  !! over their midpoints.
  type :: master_surface_t
    integer :: nseg = 0
    real(wp), allocatable :: a(:, :), b(:, :)    !< end points (2, nseg) (m)
    real(wp), allocatable :: n(:, :), t(:, :)    !< outward normal, unit tangent (2, nseg)
    real(wp), allocatable :: mid(:, :)           !< midpoints (2, nseg) (m)
    integer, allocatable :: i0(:), i1(:)         !< particles at the segment ends
    real(wp) :: reach(2) = 0.0_wp                !< half the largest segment extent (m)
    type(bins_t) :: bins
  end type master_surface_t

  !> Work counters, cumulative over a run. evaluated and detected count the pair's detector:
  !! det(M_master) (eqs. 25-28) or the node-to-segment search (contact_nts_m).
  type :: contact_counters_t
    integer(i64) :: screened = 0    !< slave particles tested against the master's box
    integer(i64) :: evaluated = 0   !< detector evaluations (inside the grown box)
    integer(i64) :: detected = 0    !< flagged (det(M_master) > threshold, or g < 0 for NTS)
    integer(i64) :: contacts = 0    !< flagged with g < 0: force applied
    !> screened particles skipped because they cannot have reached the master's box since
    !! they were last found outside it (&contact skip_far); their positions are not computed
    integer(i64) :: skipped = 0
    integer(i64) :: detected_max = 0  !< most particles flagged in one step (all passes)
    !> Both detectors side by side (&contact compare_detectors), over the same particles:
    !! flagged by det(M) (det > threshold), flagged by the closest-segment gap (g < 0), the
    !! buffer zone (det(M) flags, g >= 0: no force) and det(M)'s misses (g < 0, det <=
    !! threshold), with the most of each detector in one step.
    integer(i64) :: cmp_det = 0, cmp_gap = 0, cmp_buffer = 0, cmp_missed = 0
    integer(i64) :: cmp_det_max = 0, cmp_gap_max = 0
    real(wp) :: buffer_gap_sum = 0.0_wp  !< sum of g over the buffer-zone flags (m)
    !> that sum exactly (exact_sum_m: the same bits for any threads and ranks)
    type(exact_sum_t) :: buffer_gap_exact
    real(wp) :: buffer_gap_max = 0.0_wp  !< largest such g: the buffer zone's depth (m)
    real(wp) :: t_detect = 0.0_wp        !< wall time in the pair's detector (s)
    !> wall time in the pair's whole correction (positions, re-binning, detection, forces,
    !! spreading; s): its cost against the rest of the step
    real(wp) :: t_pair = 0.0_wp
    !> the pair's friction work since t = 0 (J, J/m in plane strain; <= 0: dissipated):
    !! the exact sum of every step's particle terms (contact_stats_t's sums; this rank's
    !! particles on ranks), and its value (on ranks summed over them when read)
    type(exact_sum_t) :: w_friction_sum
    real(wp) :: w_friction = 0.0_wp
    !> 3D self-contact: flagged particles with g < 0 whose sign was not sure (the closest
    !! point's edge or vertex has a facet among the particle's reference neighbours): no
    !! contact is made for them (contact_pair_m detect_self_3d)
    integer(i64) :: self_unsure = 0
  end type contact_counters_t

  !> Two segments nearer a point than this fraction of the largest segment extent differ by
  !! round-off only: far above the 1e-16 relative error of a distance, far below any
  !! spacing (surface_tie_tol).
  real(wp), parameter :: tie_fraction = 1.0e-9_wp

contains

  !> Segments of the master's polylines (CSR ptr, idx over the points x), leaving out those
  !! on the symmetry axis x1 = 0 in axisymmetry (a symmetry line is no surface).
  subroutine surface_build(s, x, ptr, idx, closed, axisym, tol, err)
    type(master_surface_t), intent(out) :: s
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: ptr(:), idx(:)
    logical, intent(in) :: closed(:), axisym
    real(wp), intent(in) :: tol
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, j, i0, i1, m
    integer, allocatable :: e0(:), e1(:)
    allocate(e0(size(idx)), e1(size(idx)))
    m = 0
    do k = 1, size(ptr) - 1
      do j = ptr(k), ptr(k + 1) - 1
        i0 = idx(j)
        if (j < ptr(k + 1) - 1) then
          i1 = idx(j + 1)
        else if (closed(k)) then
          i1 = idx(ptr(k))
        else
          cycle
        end if
        if (axisym .and. abs(x(1, i0)) <= tol .and. abs(x(1, i1)) <= tol) cycle
        if (all(x(:, i0) == x(:, i1))) cycle
        m = m + 1
        e0(m) = i0
        e1(m) = i1
      end do
    end do
    s%nseg = m
    s%i0 = e0(1:m)
    s%i1 = e1(1:m)
    allocate(s%a(2, m), s%b(2, m), s%n(2, m), s%t(2, m), s%mid(2, m))
    call surface_update(s, x, err)
  end subroutine surface_build

  !> The segments of surface full whose two ends are both held, in full's order (distributed
  !! memory: the part of a contact master a rank holds). num0, num1 (full%nseg): each
  !! segment's ends' numbers in the subset's numbering (the rank's particles), 0 for an end
  !! not held. Their geometry comes with surface_update. Of full only its ends are read.
  subroutine surface_subset(full, num0, num1, s)
    type(master_surface_t), intent(in) :: full
    integer, intent(in) :: num0(:), num1(:)
    type(master_surface_t), intent(out) :: s
    logical :: both(full%nseg)
    both = num0 > 0 .and. num1 > 0
    s%nseg = count(both)
    s%i0 = pack(num0, both)
    s%i1 = pack(num1, both)
    allocate(s%a(2, s%nseg), s%b(2, s%nseg), s%n(2, s%nseg), s%t(2, s%nseg), &
      s%mid(2, s%nseg))
  end subroutine surface_subset

  !> Segment geometry and bins from the current positions x of the master's particles.
  !! With grid_lo, grid_hi and reach: the segments are part of a larger surface whose
  !! midpoints' extremes and reach these are; its bins' cells and reach are taken, so that
  !! a search finds the same segments in the same order (distributed memory).
  subroutine surface_update(s, x, err, grid_lo, grid_hi, reach)
    type(master_surface_t), intent(inout) :: s
    real(wp), intent(in) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: grid_lo(2), grid_hi(2), reach(2)
    integer :: j
    real(wp) :: e(2), l
    s%reach = 0.0_wp
    do j = 1, s%nseg
      s%a(:, j) = x(:, s%i0(j))
      s%b(:, j) = x(:, s%i1(j))
      e = s%b(:, j) - s%a(:, j)
      l = max(norm2(e), tiny(1.0_wp))
      s%t(:, j) = e/l
      s%n(:, j) = [s%t(2, j), -s%t(1, j)]
      s%mid(:, j) = 0.5_wp*(s%a(:, j) + s%b(:, j))
      s%reach = max(s%reach, 0.5_wp*abs(e))
    end do
    if (present(reach)) s%reach = reach
    call bins_build(s%bins, s%mid, max(2.0_wp*s%reach, tiny(1.0_wp)), err, grid_lo, grid_hi)
  end subroutine surface_update

  !> The master segment closest to p among those reaching within r (per direction) of p,
  !! and the signed gap g = (p - a) . n to it (eq. 89). found is false when none is near.
  !! Self-contact: with xr (the reference positions of the surface's particles), xc and rex,
  !! a segment is left out when either end lies within rex of xc in the reference
  !! configuration (the point's own and adjacent segments, and every other one among its
  !! reference neighbours), or within the end's own radius rexv (np) when given, the larger
  !! (the symmetric neighbour relation of det(M)'s, rk_cloud_m cloud_set_reference).
  pure subroutine surface_gap(s, p, r, found, g, nrm, tng, seg, xi, xr, xc, rex, rexv)
    type(master_surface_t), intent(in) :: s
    real(wp), intent(in) :: p(2), r(2)
    logical, intent(out) :: found
    real(wp), intent(out) :: g, nrm(2), tng(2)
    integer, intent(out), optional :: seg          !< the closest segment
    real(wp), intent(out), optional :: xi          !< where p projects on it, 0 at a, 1 at b
    real(wp), intent(in), optional :: xr(:, :), xc(2), rex
    real(wp), intent(in), optional :: rexv(:)
    integer :: clo(3), chi(3), k, q, qa, qb, jseg, jbest
    real(wp) :: gbest, dbest
    logical :: excl, empty
    excl = present(xr) .and. present(xc) .and. present(rex)
    jbest = 0
    dbest = huge(1.0_wp)
    gbest = -huge(1.0_wp)
    ! the segments of the bins' block around p, in bins_candidates' order (walked in place:
    ! a candidate list as long as the surface was an allocation at every call)
    call bins_cell_block(s%bins, p, r + s%reach, clo, chi, empty)
    if (.not. empty) then
      do k = 1, bins_block_runs(clo, chi)
        call bins_block_run(s%bins, clo, chi, k, qa, qb)
        do q = qa, qb
          jseg = s%bins%idx(q)
          if (excl) then
            if (near_end(s%i0(jseg)) .or. near_end(s%i1(jseg))) cycle
          end if
          call closest_segment_update(s, jseg, p, jbest, dbest, gbest)
        end do
      end do
    end if
    call surface_projection(s, p, jbest, found, g, nrm, tng, seg, xi)

  contains

    !> Is particle i within rex (or its own rexv, the larger) of xc in the reference
    !! configuration?
    pure logical function near_end(i)
      integer, intent(in) :: i
      real(wp) :: rr
      rr = rex
      if (present(rexv)) rr = max(rex, rexv(i))
      near_end = sum((xr(:, i) - xc)**2) < rr*rr
    end function near_end
  end subroutine surface_gap

  !> Closest-segment rule shared by every search over the master's segments (the det(M)
  !! path's bins above and the node-to-segment buckets of contact_nts_m), so that both
  !! detectors measure the same gap: candidate segment j replaces the best so far (jbest at
  !! distance dbest, gap gbest; start with 0, huge, -huge) when it is closer, or, at a
  !! corner where the two are equally close, when it puts p farther outside (otherwise a
  !! point beside a convex corner reads as inside it).
  pure subroutine closest_segment_update(s, j, p, jbest, dbest, gbest)
    type(master_surface_t), intent(in) :: s
    integer, intent(in) :: j
    real(wp), intent(in) :: p(2)
    integer, intent(inout) :: jbest
    real(wp), intent(inout) :: dbest, gbest
    real(wp) :: dist, gj
    logical :: tie
    dist = segment_distance(s%a(:, j), s%b(:, j), p)
    gj = dot_product(p - s%a(:, j), s%n(:, j))
    tie = abs(dist - dbest) <= surface_tie_tol(s)
    if ((dist < dbest .and. .not. tie) .or. (tie .and. gj > gbest)) then
      dbest = min(dist, dbest)
      gbest = gj
      jbest = j
    end if
  end subroutine closest_segment_update

  !> Two segments closer to a point than this differ by round-off only (m): 1e-9 of the
  !! largest segment extent, far above the 1e-16 relative error of a distance and far
  !! below any spacing.
  pure real(wp) function surface_tie_tol(s) result(tol)
    type(master_surface_t), intent(in) :: s
    tol = tie_fraction*maxval(s%reach)
  end function surface_tie_tol

  !> Gap, normal, tangent and projection of p on segment jbest (0: none found, found false).
  pure subroutine surface_projection(s, p, jbest, found, g, nrm, tng, seg, xi)
    type(master_surface_t), intent(in) :: s
    real(wp), intent(in) :: p(2)
    integer, intent(in) :: jbest
    logical, intent(out) :: found
    real(wp), intent(out) :: g, nrm(2), tng(2)
    integer, intent(out), optional :: seg
    real(wp), intent(out), optional :: xi
    real(wp) :: e(2)
    found = jbest > 0
    g = 0.0_wp
    nrm = 0.0_wp
    tng = 0.0_wp
    if (present(seg)) seg = jbest
    if (present(xi)) xi = 0.0_wp
    if (.not. found) return
    nrm = s%n(:, jbest)
    tng = s%t(:, jbest)
    g = dot_product(p - s%a(:, jbest), nrm)
    if (present(xi)) then
      e = s%b(:, jbest) - s%a(:, jbest)
      xi = max(0.0_wp, min(1.0_wp, dot_product(p - s%a(:, jbest), e)/dot_product(e, e)))
    end if
  end subroutine surface_projection

  !> Contact force on one slave particle of (effective) mass m with predicted gap g (< 0:
  !! penetration). Against a deformable master m is the reduced mass m_s m_m/(m_s + m_m),
  !! so that the step closes the gap between both moving surfaces.
  !! and predicted tangential slip s_t over the step relative to the master (m), for the
  !! step dt and friction coefficient mu: normal 2 m |g|/dt^2 along n (eq. 93), tangential
  !! the smaller of stick -2 m s_t/dt^2 and slip mu |f_n| against the slip (eqs. 94-96).
  !! stick is true when the stick force was applied.
  pure subroutine contact_point_force(g, nrm, tng, slip, m, dt, mu, f, stick)
    real(wp), intent(in) :: g, nrm(2), tng(2), slip, m, dt, mu
    real(wp), intent(out) :: f(2)
    logical, intent(out) :: stick
    real(wp) :: fn, fstick, fslip, ft
    f = 0.0_wp
    stick = .false.
    if (.not. (g < 0.0_wp)) return
    fn = 2.0_wp*m*(-g)/(dt*dt)
    f = fn*nrm
    if (mu <= 0.0_wp .or. slip == 0.0_wp) return
    fstick = 2.0_wp*m*abs(slip)/(dt*dt)
    fslip = mu*fn
    stick = fstick <= fslip
    ft = -sign(min(fstick, fslip), slip)
    f = f + ft*tng
  end subroutine contact_point_force

  !> contact_point_force in three dimensions: the same normal force 2 m |g|/dt^2 along the
  !! outward normal nrm (3) (eq. 93), and friction in the tangent plane (eqs. 94-96)
  !! against the predicted tangential slip vector slip (3) of the step relative to the
  !! master (m; in the tangent plane): the smaller of stick, -2 m slip/dt^2, and slip, mu
  !! |f_n| along -slip/|slip|. In the plane (slip = s_t t) it is contact_point_force.
  pure subroutine contact_point_force_3d(g, nrm, slip, m, dt, mu, f, stick)
    real(wp), intent(in) :: g, nrm(3), slip(3), m, dt, mu
    real(wp), intent(out) :: f(3)
    logical, intent(out) :: stick
    real(wp) :: fn, fstick, fslip, s
    f = 0.0_wp
    stick = .false.
    if (.not. (g < 0.0_wp)) return
    fn = 2.0_wp*m*(-g)/(dt*dt)
    f = fn*nrm
    s = norm2(slip)
    if (mu <= 0.0_wp .or. s == 0.0_wp) return
    fstick = 2.0_wp*m*s/(dt*dt)
    fslip = mu*fn
    stick = fstick <= fslip
    f = f - (min(fstick, fslip)/s)*slip
  end subroutine contact_point_force_3d
end module contact_m
