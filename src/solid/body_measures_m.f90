!> Measures of a deformed body for the log, the history and the summary, for any solid
!! whatever its discretization: its extents along the axes, the length (the extent along the
!! last axis: x2 in the plane, z = x3 in 3D), the width (the extent along x1), the foot
!! radius (the largest distance from the last axis, x1 in the plane and sqrt(x1^2 + x2^2)
!! in 3D, within one nominal spacing of the lowest point along it: a Taylor bar's foot on
!! the surface below it), and the largest effective plastic strain. All lengths are taken
!! at the physical positions of the nodes.
module body_measures_m
  use kinds_m, only: wp
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

  !> The measures of solid s at its current coefficients; s%x is used as work space.
  function body_measures(s) result(m)
    type(solid_t), intent(inout) :: s
    type(measures_t) :: m
    real(wp) :: zmin
    integer :: nd, c, i
    call solid_positions(s, at_prediction, s%x)
    nd = size(s%x, 1)
    do c = 1, nd
      m%extent(c) = maxval(s%x(c, :)) - minval(s%x(c, :))
    end do
    zmin = minval(s%x(nd, :))
    m%length = m%extent(nd)
    m%width = m%extent(1)
    m%foot_radius = -huge(1.0_wp)
    do i = 1, s%np
      if (s%x(nd, i) <= zmin + s%spacing) m%foot_radius = max(m%foot_radius, &
        axis_distance(s%x(:, i), nd))
    end do
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
    do k = 1, size(s%part%own_n)
      call solid_point_position(s, s%part%own_n(k), x(:nd))
      if (x(nd) <= zmin + s%spacing) w(1) = max(w(1), axis_distance(x(:nd), nd))
    end do
    call comm%max_real(w)
    do c = 1, nd
      m%extent(c) = v(2*c) - (-v(2*c - 1))
    end do
    m%length = m%extent(nd)
    m%width = m%extent(1)
    m%foot_radius = w(1)
    m%max_epsbar = v(2*max_dim + 1)
  end function body_measures_part
end module body_measures_m
