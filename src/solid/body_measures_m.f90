!> Measures of a deformed body for the log, the history and the summary, for any solid
!! whatever its discretization: extent along x2 (length) and x1 (width), the largest x1
!! within one nominal spacing of the lowest x2 (the foot radius of a body standing on, or
!! striking, a surface below it), and the largest effective plastic strain. All lengths are
!! taken at the physical positions of the nodes.
module body_measures_m
  use kinds_m, only: wp
  use solid_m, only: solid_t, solid_positions, solid_point_position, at_prediction
  use rank_comm_m, only: rank_comm_t
  implicit none
  private
  public :: measures_t, body_measures, body_measures_part, measure_names, measure_units

  type :: measures_t
    real(wp) :: length = 0.0_wp       !< extent in x2 (m)
    real(wp) :: width = 0.0_wp        !< extent in x1 (m)
    real(wp) :: foot_radius = 0.0_wp  !< largest x1 within one spacing of the lowest x2 (m)
    real(wp) :: max_epsbar = 0.0_wp   !< largest effective plastic strain (1)
  end type measures_t

  character(len=*), parameter :: measure_names(4) = [character(len=11) :: &
    'length', 'width', 'foot_radius', 'max_epsbar']
  character(len=*), parameter :: measure_units(4) = [character(len=1) :: 'm', 'm', 'm', '1']

contains

  !> The measures of solid s at its current coefficients; s%x is used as work space.
  function body_measures(s) result(m)
    type(solid_t), intent(inout) :: s
    type(measures_t) :: m
    real(wp) :: zmin
    call solid_positions(s, at_prediction, s%x)
    zmin = minval(s%x(2, :))
    m%length = maxval(s%x(2, :)) - zmin
    m%width = maxval(s%x(1, :)) - minval(s%x(1, :))
    m%foot_radius = maxval(s%x(1, :), mask=s%x(2, :) <= zmin + s%spacing)
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
    real(wp) :: v(5), w(1), x(2), zmin
    integer :: k
    v = -huge(1.0_wp)
    do k = 1, size(s%part%own_n)
      call solid_point_position(s, s%part%own_n(k), x)
      v(1:4) = max(v(1:4), [-x(2), x(2), -x(1), x(1)])
    end do
    do k = 1, size(s%part%own_q)
      v(5) = max(v(5), s%state%st%epsbar(s%part%own_q(k)))
    end do
    call comm%max_real(v)
    zmin = -v(1)
    w = -huge(1.0_wp)
    do k = 1, size(s%part%own_n)
      call solid_point_position(s, s%part%own_n(k), x)
      if (x(2) <= zmin + s%spacing) w(1) = max(w(1), x(1))
    end do
    call comm%max_real(w)
    m%length = v(2) - zmin
    m%width = v(4) - (-v(3))
    m%foot_radius = w(1)
    m%max_epsbar = v(5)
  end function body_measures_part
end module body_measures_m
