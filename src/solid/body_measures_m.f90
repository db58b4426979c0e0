!> Measures of a deformed body for the log, the history and the summary, for any solid
!! whatever its discretization: its extents along the axes, the length (the extent along the
!! last axis: x2 in the plane, z = x3 in 3D), the width (the extent along x1), the foot
!! radius (the largest distance from the last axis, x1 in the plane and sqrt(x1^2 + x2^2)
!! in 3D, within one nominal spacing of the lowest point along it: a Taylor bar's foot on
!! the surface below it), and the largest effective plastic strain. All lengths are taken
!! at the physical positions of the nodes.
!!
!! In 3D the foot radius is, as in the plane, the largest distance from the axis of the
!! nodes within one spacing of the lowest z, taken in each direction of the body's
!! reference rim (its particles at the largest reference distance from the axis, in the
!! lowest reference layer: a node counts for the rim direction nearest its reference
!! angle) and averaged over the directions: a body of revolution on particles is not round
!! at the spacing's scale, and the single largest distance stood 4-7% beyond the
!! axisymmetric solid's foot radius at the same spacing (a Taylor bar at 1, 0.5 and 1/3
!! mm), the directions' mean within 1.4%, 0.3% and 1.1%. Maxima and counts only, so a
!! rank's parts give the serial value to the bit.
module body_measures_m
  use kinds_m, only: wp, i64
  use dims_m, only: max_dim
  use solid_m, only: solid_t, solid_positions, solid_point_position, at_prediction
  use rank_comm_m, only: rank_comm_t, single_rank_t
  implicit none
  private
  public :: measures_t, body_measures, body_measures_part, measure_names, measure_units

  type :: measures_t
    real(wp) :: length = 0.0_wp       !< extent along the last axis (m)
    real(wp) :: width = 0.0_wp        !< extent in x1 (m)
    real(wp) :: foot_radius = 0.0_wp  !< largest distance from the last axis near its lowest (m)
    real(wp) :: max_epsbar = 0.0_wp   !< largest effective plastic strain (1)
    real(wp) :: extent(max_dim) = 0.0_wp   !< extents along x1, x2 (, x3) (m)
  end type measures_t

  character(len=*), parameter :: measure_names(4) = [character(len=11) :: &
    'length', 'width', 'foot_radius', 'max_epsbar']
  character(len=*), parameter :: measure_units(4) = [character(len=1) :: 'm', 'm', 'm', '1']

  !> the most rim directions of the 3D foot radius (a ring of 2 pi R/h particles: R/h up to
  !! about 650)
  integer, parameter :: max_dirs = 4096

contains

  !> The distance of x (nd) from the last axis: |x1| in the plane (r in axisymmetry),
  !! sqrt(x1^2 + x2^2) in 3D.
  pure real(wp) function axis_distance(x, nd) result(r)
    real(wp), intent(in) :: x(:)
    integer, intent(in) :: nd
    if (nd == 3) then
      r = sqrt(x(1)**2 + x(2)**2)
    else
      r = x(1)
    end if
  end function axis_distance

  !> The 3D foot radius of s over its nodes list (all when absent; a rank's owned nodes),
  !! reduced over the ranks by comm: the rim directions from the reference rim (the nodes
  !! at the largest reference distance rmax from the z axis in the lowest reference layer:
  !! their count n and their angles' span give the angular step), then in each direction
  !! the largest distance from the axis of the nodes within one spacing of the lowest z,
  !! zmin (current), whose reference angle is nearest it; the mean over the directions.
  function foot_radius_3d(s, zmin, comm, list) result(r)
    type(solid_t), intent(in) :: s
    real(wp), intent(in) :: zmin
    class(rank_comm_t), intent(inout) :: comm
    integer, intent(in), optional :: list(:)
    real(wp) :: r
    real(wp) :: v(4), x(3), t, tol, step, w(max_dirs), twopi
    integer(i64) :: cnt(1)
    integer :: k, i, n, nd_, ndir
    logical :: full
    twopi = 2.0_wp*acos(-1.0_wp)
    n = s%np
    if (present(list)) n = size(list)
    ! the reference rim: the largest distance, the lowest layer, its angles' extremes
    v = -huge(1.0_wp)
    do k = 1, n
      i = node(k)
      v(1) = max(v(1), axis_distance(s%x0(:, i), 3))
      v(2) = max(v(2), -s%x0(3, i))
    end do
    call comm%max_real(v(1:2))
    tol = 1.0e-9_wp*s%spacing
    cnt = 0
    v(3:4) = -huge(1.0_wp)
    do k = 1, n
      i = node(k)
      if (.not. rim(i)) cycle
      cnt = cnt + 1
      t = angle(s%x0(:, i))
      v(3:4) = max(v(3:4), [-t, t])
    end do
    call comm%sum_i8(cnt)
    call comm%max_real(v(3:4))
    ndir = int(min(max(cnt(1), 1_i64), int(max_dirs, i64)))
    ! a whole ring spans 2 pi less one step; a sector its span with both ends; no rim (no
    ! node both at the largest distance and in the lowest layer: a sphere) one direction,
    ! the lowest nodes' largest distance (the angles' extremes are then -huge: their sum
    ! would overflow)
    full = .false.
    step = 0.0_wp
    if (cnt(1) > 0) then
      full = v(4) + v(3) > twopi*(1.0_wp - 1.5_wp/real(ndir, wp))
      if (full) then
        step = twopi/real(ndir, wp)
      else
        step = (v(4) + v(3))/real(max(ndir - 1, 1), wp)
      end if
    end if
    w = -huge(1.0_wp)
    do k = 1, n
      i = node(k)
      call solid_point_position(s, i, x)
      if (x(3) > zmin + s%spacing) cycle
      if (step > 0.0_wp) then
        nd_ = nint((angle(s%x0(:, i)) + v(3))/step)
      else
        nd_ = 0
      end if
      if (full) nd_ = modulo(nd_, ndir)
      nd_ = min(max(nd_, 0), ndir - 1) + 1
      w(nd_) = max(w(nd_), axis_distance(x, 3))
    end do
    call comm%max_real(w(1:ndir))
    r = sum(w(1:ndir), mask=w(1:ndir) > -huge(1.0_wp))/ &
      real(max(count(w(1:ndir) > -huge(1.0_wp)), 1), wp)
  contains
    pure integer function node(kk)
      integer, intent(in) :: kk
      node = kk
      if (present(list)) node = list(kk)
    end function node
    pure logical function rim(ii)
      integer, intent(in) :: ii
      rim = axis_distance(s%x0(:, ii), 3) >= v(1) - tol .and. s%x0(3, ii) <= -v(2) + tol
    end function rim
    pure real(wp) function angle(y)
      real(wp), intent(in) :: y(:)
      angle = modulo(atan2(y(2), y(1)), twopi)
      ! (a point on the positive x axis at angle 0, not 2 pi, for rounding)
      if (angle > twopi - 1.0e-12_wp) angle = 0.0_wp
    end function angle
  end function foot_radius_3d

  !> The measures of solid s at its current coefficients; s%x is used as work space.
  function body_measures(s) result(m)
    type(solid_t), intent(inout) :: s
    type(measures_t) :: m
    real(wp) :: zmin
    integer :: nd, c, i
    type(single_rank_t) :: one
    call solid_positions(s, at_prediction, s%x)
    nd = size(s%x, 1)
    do c = 1, nd
      m%extent(c) = maxval(s%x(c, :)) - minval(s%x(c, :))
    end do
    zmin = minval(s%x(nd, :))
    m%length = m%extent(nd)
    m%width = m%extent(1)
    m%foot_radius = -huge(1.0_wp)
    if (nd == 3) then
      one%nranks = 1
      m%foot_radius = foot_radius_3d(s, zmin, one)
    else
      do i = 1, s%np
        if (s%x(nd, i) <= zmin + s%spacing) m%foot_radius = max(m%foot_radius, &
          axis_distance(s%x(:, i), nd))
      end do
    end if
    m%max_epsbar = maxval(s%state%st%epsbar)
  end function body_measures

  !> Distributed memory: the measures of the whole solid whose rank's part s is (its own
  !! nodes and points, solid_set_owned), by two maxima over the ranks (collective). The
  !! extremes are those of the whole solid's nodes, so the measures are body_measures' to
  !! the bit, without gathering the solid.
  function body_measures_part(s, comm) result(m)
    type(solid_t), intent(in) :: s
    class(rank_comm_t), intent(inout) :: comm
    type(measures_t) :: m
    real(wp) :: v(2*max_dim + 1), w(1), x(max_dim), zmin
    integer :: k, nd, c
    nd = size(s%x0, 1)
    v = -huge(1.0_wp)
    do k = 1, size(s%part%own_n)
      call solid_point_position(s, s%part%own_n(k), x(:nd))
      do c = 1, nd
        v(2*c - 1:2*c) = max(v(2*c - 1:2*c), [-x(c), x(c)])
      end do
    end do
    do k = 1, size(s%part%own_q)
      v(2*max_dim + 1) = max(v(2*max_dim + 1), s%state%st%epsbar(s%part%own_q(k)))
    end do
    call comm%max_real(v)
    zmin = -v(2*nd - 1)
    w = -huge(1.0_wp)
    if (nd /= 3) then
      do k = 1, size(s%part%own_n)
        call solid_point_position(s, s%part%own_n(k), x(:nd))
        if (x(nd) <= zmin + s%spacing) w(1) = max(w(1), axis_distance(x(:nd), nd))
      end do
      call comm%max_real(w)
    end if
    do c = 1, nd
      m%extent(c) = v(2*c) - (-v(2*c - 1))
    end do
    m%length = m%extent(nd)
    m%width = m%extent(1)
    m%foot_radius = w(1)
    if (nd == 3) m%foot_radius = foot_radius_3d(s, zmin, comm, s%part%own_n)
    m%max_epsbar = v(2*max_dim + 1)
  end function body_measures_part
end module body_measures_m
