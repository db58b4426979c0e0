!> Contact detection by the moment matrix (Section 2): det(M) of a body at query points,
!! the interior plateau, and the inside/outside classification det(M) > threshold, with
!! the threshold either eps_cr (absolute, paper: 5e-10) or eps_rel x plateau (scale-free).
!! When the body has an exact geometry, each query also gets its signed distance so the
!! buffer zone of eq. (50), 0 < distance < rho, can be measured.
module detection_m
  use kinds_m, only: wp, i64
  use body_m, only: body_t
  use geometry_m, only: geom_none, signed_distance
  use errors_m, only: error_t
  use rk_cloud_m, only: rk_cloud_t, cloud_det, cloud_init
  use sorting_m, only: sort_index
  use neighbour_bins_m, only: bins_candidates
  use rank_comm_m, only: rank_comm_t, kth_smallest
  implicit none
  private
  public :: det_at_points, body_plateau, classify, buffer_stats, buffer_stats_t
  public :: detection_threshold, body_cloud, share_det_medians, deep_particles

  !> What the classification says about the buffer zone (all distances in m).
  type :: buffer_stats_t
    real(wp) :: rho_buffer = 0.0_wp         !< eq. (50): sqrt(sum rho_i^2)
    real(wp) :: max_outside_inside = 0.0_wp !< largest distance of a det > eps point outside
    real(wp) :: min_outside_outside = 0.0_wp !< smallest distance of a det <= eps point outside
    integer(i64) :: n_false_outside = 0     !< points inside the body with det <= eps
    integer(i64) :: n_beyond_buffer = 0     !< points outside with det > eps and distance >= rho
    integer(i64) :: n_points = 0
  end type buffer_stats_t

contains

  !> The packed cloud of a body (reference positions).
  subroutine body_cloud(b, c, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(out) :: c
    type(error_t), allocatable, intent(inout) :: err
    call cloud_init(c, b%x, b%rho, b%vol, b%kid, b%wshape, b%bid, b%h(1:b%ndim), err)
  end subroutine body_cloud

  !> det(M) of cloud c at every column of p(ndim, n). OpenMP over points.
  subroutine det_at_points(c, p, det)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: p(:, :)
    real(wp), intent(out) :: det(:)
    integer :: i
    !$omp parallel do default(none) shared(c, p, det) schedule(static, 256)
    do i = 1, size(p, 2)
      det(i) = cloud_det(c, p(:, i))
    end do
    !$omp end parallel do
  end subroutine det_at_points

  !> Interior plateau: the median of det(M) at the body's deep particles, those whose
  !! support holds no boundary particle (there det(M) is flat; near the boundary it drops).
  !! A body too thin to have deep particles falls back to the largest det(M) of any particle.
  function body_plateau(b, c) result(plateau)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    real(wp) :: plateau
    real(wp), allocatable :: det(:), deep_det(:)
    integer, allocatable :: order(:)
    logical, allocatable :: deep(:)
    allocate(det(b%np))
    call det_at_points(c, b%x, det)
    deep = deep_particles(c, b%boundary, b%x, b%rho)
    if (.not. any(deep)) then
      plateau = maxval(det)
      return
    end if
    deep_det = pack(det, deep)
    allocate(order(size(deep_det)))
    call sort_index(deep_det, order)
    plateau = deep_det(order((size(deep_det) + 1)/2))
  end function body_plateau

  !> Whether each particle at x (ndim, n) with support rho (ndim, n) is deep in cloud c:
  !! no boundary particle of the cloud (bnd: the flags of the particles c was made from,
  !! in their order) lies within its support.
  function deep_particles(c, bnd, x, rho) result(deep)
    type(rk_cloud_t), intent(in) :: c
    logical, intent(in) :: bnd(:)
    real(wp), intent(in) :: x(:, :), rho(:, :)
    logical, allocatable :: deep(:)
    integer, allocatable :: cand(:)
    integer :: i, k, nc
    allocate(deep(size(x, 2)), cand(c%np))
    do i = 1, size(x, 2)
      call bins_candidates(c%bins, x(:, i), rho(:, i), cand, nc)
      deep(i) = .true.
      do k = 1, nc
        if (.not. bnd(c%perm(cand(k)))) cycle
        if (all(abs(c%x(:, cand(k)) - x(:, i)) < rho(:, i))) then
          deep(i) = .false.
          exit
        end if
      end do
    end do
  end function deep_particles

  !> body_plateau's and the surface median's (contact_pair_m surface_det_median) values of
  !! a body no rank holds whole, over the ranks (comm), each the serial one to the bit,
  !! from det(M) at each rank's share of the particles (the shares partition the body:
  !! det, whether each is deep, deep_particles, and a boundary particle, bnd, in the whole
  !! body's cloud, or one that gives its bits): the medians are the k-th smallest over the
  !! ranks (rank_comm_m kth_smallest), the fallback the largest. Collective.
  subroutine share_det_medians(comm, det, deep, bnd, plateau, surface_det)
    class(rank_comm_t), intent(inout) :: comm
    real(wp), intent(in) :: det(:)
    logical, intent(in) :: deep(:), bnd(:)
    real(wp), intent(out) :: plateau, surface_det
    integer(i64) :: n(2)
    real(wp) :: top(1)
    n = [count(deep, kind=i64), count(bnd, kind=i64)]
    call comm%sum_i8(n)
    if (n(1) == 0) then
      ! (a body too thin to have deep particles: the largest det(M) of any)
      top = -huge(1.0_wp)
      if (size(det) > 0) top = maxval(det)
      call comm%max_real(top)
      plateau = top(1)
    else
      plateau = kth_smallest(comm, pack(det, deep), (n(1) + 1)/2)
    end if
    ! (surface_det_median's: 0 without boundary particles)
    surface_det = kth_smallest(comm, pack(det, bnd), (n(2) + 1)/2)
  end subroutine share_det_medians

  !> eps_rel x plateau when eps_rel > 0, else eps_cr.
  pure real(wp) function detection_threshold(eps_cr, eps_rel, plateau) result(t)
    real(wp), intent(in) :: eps_cr, eps_rel, plateau
    if (eps_rel > 0.0_wp) then
      t = eps_rel*plateau
    else
      t = eps_cr
    end if
  end function detection_threshold

  !> inside = 1 where det > threshold, else 0.
  pure subroutine classify(det, threshold, inside)
    real(wp), intent(in) :: det(:), threshold
    integer, intent(out) :: inside(:)
    inside = merge(1, 0, det > threshold)
  end subroutine classify

  !> Signed distances of the points and how the classification sits in the buffer zone.
  subroutine buffer_stats(b, p, inside, dist, st)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: p(:, :)
    integer, intent(in) :: inside(:)
    real(wp), intent(out) :: dist(:)
    type(buffer_stats_t), intent(out) :: st
    integer :: i
    st%rho_buffer = norm2(b%h(1:b%ndim))
    st%n_points = size(p, 2)
    if (b%geom%kind == geom_none) then
      dist = huge(1.0_wp)
      return
    end if
    st%min_outside_outside = huge(1.0_wp)
    do i = 1, size(p, 2)
      dist(i) = signed_distance(b%geom, p(:, i))
      if (dist(i) <= 0.0_wp) then
        if (inside(i) == 0) st%n_false_outside = st%n_false_outside + 1
      else if (inside(i) == 1) then
        st%max_outside_inside = max(st%max_outside_inside, dist(i))
        if (dist(i) >= st%rho_buffer) st%n_beyond_buffer = st%n_beyond_buffer + 1
      else
        st%min_outside_outside = min(st%min_outside_outside, dist(i))
      end if
    end do
  end subroutine buffer_stats
end module detection_m
