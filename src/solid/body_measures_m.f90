!> Measures of a deformed body for the log, the history and the summary, for any solid
!! whatever its discretization: its extents along the axes, the length (the extent along the
!! last axis: x2 in the plane, z = x3 in 3D), the width (the extent along x1), the foot
!! radius (the largest distance from the last axis, x1 in the plane and sqrt(x1^2 + x2^2)
!! in 3D, within one nominal spacing of the lowest point along it: a Taylor bar's foot on
!! the surface below it), and the largest effective plastic strain. All lengths are taken
!! at the physical positions of the nodes.
!!
!! In 3D the foot radius is the mean distance from the z axis of the particles of the
!! body's reference rim (at the largest reference distance from the axis, in the lowest
!! reference layer): a body of revolution on particles is not round at the spacing's scale
!! (the disk's rings, the planes of a quarter), and its single outermost particle stood
!! 4-6% beyond the axisymmetric solid's foot radius at the same spacing (a Taylor bar at
!! 0.5 mm and 1 mm), the rim's mean within 0.3-1.4%. The mean is summed in fixed point
!! (integer multiples of 1e-12 m), so a rank's parts add up to the serial value to the bit.
module body_measures_m
  use kinds_m, only: wp, i64
  use dims_m, only: max_dim
  use solid_m, only: solid_t, solid_positions, solid_point_position, at_prediction
  use rank_comm_m, only: rank_comm_t
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

  !> the fixed-point unit of the 3D foot radius's sum (m): exact integer sums, far below
  !! any spacing, and 9e18 units hold distances to 9e6 m
  real(wp), parameter :: fixed_unit = 1.0e-12_wp

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

  !> Is node i on the reference rim of s (3D): at the largest reference distance rmax from
  !! the z axis and in the lowest reference layer z0min (within tol)?
  pure logical function on_rim(s, i, rmax, z0min, tol)
    type(solid_t), intent(in) :: s
    integer, intent(in) :: i
    real(wp), intent(in) :: rmax, z0min, tol
    on_rim = axis_distance(s%x0(:, i), 3) >= rmax - tol .and. s%x0(3, i) <= z0min + tol
  end function on_rim

  !> The measures of solid s at its current coefficients; s%x is used as work space.
  function body_measures(s) result(m)
    type(solid_t), intent(inout) :: s
    type(measures_t) :: m
    real(wp) :: zmin, rmax, z0min, tol
    integer :: nd, c, i
    integer(i64) :: rsum(2)
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
      ! the reference rim's mean distance from the axis, summed in fixed point
      rmax = 0.0_wp
      do i = 1, s%np
        rmax = max(rmax, axis_distance(s%x0(:, i), 3))
      end do
      z0min = minval(s%x0(3, :))
      tol = 1.0e-9_wp*s%spacing
      rsum = 0
      do i = 1, s%np
        if (.not. on_rim(s, i, rmax, z0min, tol)) cycle
        rsum = rsum + [nint(axis_distance(s%x(:, i), 3)/fixed_unit, i64), 1_i64]
      end do
      m%foot_radius = real(rsum(1), wp)*fixed_unit/real(max(rsum(2), 1_i64), wp)
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
    real(wp) :: v(2*max_dim + 3), w(1), x(max_dim), zmin, tol
    integer :: k, nd, c
    integer(i64) :: rsum(2)
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
    ! (3D: the reference rim's largest distance from the axis and lowest layer)
    if (nd == 3) then
      do k = 1, size(s%part%own_n)
        v(2*max_dim + 2) = max(v(2*max_dim + 2), axis_distance(s%x0(:, s%part%own_n(k)), 3))
        v(2*max_dim + 3) = max(v(2*max_dim + 3), -s%x0(3, s%part%own_n(k)))
      end do
    end if
    call comm%max_real(v)
    zmin = -v(2*nd - 1)
    w = -huge(1.0_wp)
    rsum = 0
    tol = 1.0e-9_wp*s%spacing
    do k = 1, size(s%part%own_n)
      call solid_point_position(s, s%part%own_n(k), x(:nd))
      if (nd == 3) then
        if (on_rim(s, s%part%own_n(k), v(2*max_dim + 2), -v(2*max_dim + 3), tol)) &
          rsum = rsum + [nint(axis_distance(x(:nd), 3)/fixed_unit, i64), 1_i64]
      else if (x(nd) <= zmin + s%spacing) then
        w(1) = max(w(1), axis_distance(x(:nd), nd))
      end if
    end do
    if (nd == 3) then
      call comm%sum_i8(rsum)
    else
      call comm%max_real(w)
    end if
    do c = 1, nd
      m%extent(c) = v(2*c) - (-v(2*c - 1))
    end do
    m%length = m%extent(nd)
    m%width = m%extent(1)
    m%foot_radius = w(1)
    if (nd == 3) m%foot_radius = real(rsum(1), wp)*fixed_unit/real(max(rsum(2), 1_i64), wp)
    m%max_epsbar = v(2*max_dim + 1)
  end function body_measures_part
end module body_measures_m
