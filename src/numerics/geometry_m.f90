!> Exact geometry of generated bodies: signed distance (negative inside) for a segment, a
!! polygon (rectangles are polygons), an annulus sector, and in 3D a prism (a polygon in
!! x-y extruded along z; boxes are prisms). Used to classify query points
!! against the truth (buffer zone of eq. (50), detection accuracy) and never by the solver.
module geometry_m
  use kinds_m, only: wp, pi
  implicit none
  private
  public :: geometry_t, geom_none, geom_segment, geom_polygon, geom_annulus, geom_prism
  public :: geom_cylinder
  public :: signed_distance, polygon_area, clip_polygon_box, segment_distance
  public :: polygon_crossing, full_turn_tol, cross3, twice_area

  integer, parameter :: geom_none = 0, geom_segment = 1, geom_polygon = 2, geom_annulus = 3
  integer, parameter :: geom_prism = 4
  !> a circular cylinder about the z axis through center (x, y): radius r1, from z0 to z1
  integer, parameter :: geom_cylinder = 5

  !> An angular span within this of 2 pi (rad) is a full turn: the decks give whole
  !! degrees, converted with one rounding (about 1e-16 relative), and no sector an
  !! annulus generator makes is within 1e-12 rad of a full ring.
  real(wp), parameter :: full_turn_tol = 1.0e-12_wp

  type :: geometry_t
    integer :: kind = geom_none
    real(wp) :: a = 0.0_wp, b = 0.0_wp          !< segment [a, b] (m)
    real(wp), allocatable :: v(:, :)            !< polygon vertices (2, nv), counter-clockwise
    real(wp) :: center(2) = 0.0_wp              !< annulus centre (m)
    real(wp) :: r0 = 0.0_wp, r1 = 0.0_wp        !< inner, outer radius (m)
    real(wp) :: t0 = 0.0_wp, t1 = 0.0_wp        !< start, end angle (rad), t1 > t0
    real(wp) :: z0 = 0.0_wp, z1 = 0.0_wp        !< prism: the polygon v from z0 to z1 (m)
  end type geometry_t

contains

  !> Signed distance from p to the boundary: < 0 inside, > 0 outside (m).
  pure real(wp) function signed_distance(g, p) result(sd)
    type(geometry_t), intent(in) :: g
    real(wp), intent(in) :: p(:)
    select case (g%kind)
    case (geom_segment)
      sd = max(g%a - p(1), p(1) - g%b)
    case (geom_polygon)
      sd = polygon_sd(g%v, p(1:2))
    case (geom_annulus)
      sd = annulus_sd(g, p(1:2))
    case (geom_prism)
      sd = prism_sd(g, p(1:3))
    case (geom_cylinder)
      sd = cylinder_sd(g, p(1:3))
    case default
      sd = huge(1.0_wp)
    end select
  end function signed_distance

  !> Distance from p to the segment [a, b] in the plane.
  pure real(wp) function segment_distance(a, b, p) result(d)
    real(wp), intent(in) :: a(2), b(2), p(2)
    real(wp) :: e(2), t, l2
    e = b - a
    l2 = dot_product(e, e)
    t = 0.0_wp
    if (l2 > 0.0_wp) t = max(0.0_wp, min(1.0_wp, dot_product(p - a, e)/l2))
    d = norm2(p - a - t*e)
  end function segment_distance

  pure real(wp) function polygon_sd(v, p) result(sd)
    real(wp), intent(in) :: v(:, :), p(2)
    integer :: i, j, nv
    logical :: inside
    nv = size(v, 2)
    sd = huge(1.0_wp)
    inside = .false.
    j = nv
    do i = 1, nv
      sd = min(sd, segment_distance(v(:, j), v(:, i), p))
      if ((v(2, i) > p(2)) .neqv. (v(2, j) > p(2))) then
        if (p(1) < (v(1, j) - v(1, i))*(p(2) - v(2, i))/(v(2, j) - v(2, i)) + v(1, i)) &
          inside = .not. inside
      end if
      j = i
    end do
    if (inside) sd = -sd
  end function polygon_sd

  !> A prism's signed distance: the polygon's in x-y (s) and the slab's along z (t) are
  !! orthogonal, so outside it is sqrt(max(s, 0)^2 + max(t, 0)^2) and inside the nearer
  !! face's, max(s, t).
  pure real(wp) function prism_sd(g, p) result(sd)
    type(geometry_t), intent(in) :: g
    real(wp), intent(in) :: p(3)
    sd = extruded_sd(polygon_sd(g%v, p(1:2)), g, p(3))
  end function prism_sd

  !> A cylinder's signed distance: the disk's (r - R) and the slab's combined as a prism's.
  pure real(wp) function cylinder_sd(g, p) result(sd)
    type(geometry_t), intent(in) :: g
    real(wp), intent(in) :: p(3)
    if (g%t1 - g%t0 >= 2.0_wp*pi - full_turn_tol) then
      sd = extruded_sd(norm2(p(1:2) - g%center) - g%r1, g, p(3))
    else
      ! a sector of the cylinder (symmetry planes along its straight sides)
      sd = extruded_sd(annulus_sd(g, p(1:2)), g, p(3))
    end if
  end function cylinder_sd

  !> The signed distance of a section's extrusion from z0 to z1: s the section's in x-y, t
  !! the slab's along z; outside sqrt(max(s, 0)^2 + max(t, 0)^2), inside max(s, t).
  pure real(wp) function extruded_sd(s, g, z) result(sd)
    real(wp), intent(in) :: s, z
    type(geometry_t), intent(in) :: g
    real(wp) :: t
    t = max(g%z0 - z, z - g%z1)
    if (s <= 0.0_wp .and. t <= 0.0_wp) then
      sd = max(s, t)
    else
      sd = sqrt(max(s, 0.0_wp)**2 + max(t, 0.0_wp)**2)
    end if
  end function extruded_sd

  pure real(wp) function annulus_sd(g, p) result(sd)
    type(geometry_t), intent(in) :: g
    real(wp), intent(in) :: p(2)
    real(wp) :: q(2), r, t, d, e0(2), e1(2)
    logical :: full, in_angle
    q = p - g%center
    r = norm2(q)
    t = atan2(q(2), q(1))
    full = g%t1 - g%t0 >= 2.0_wp*pi - full_turn_tol
    in_angle = full .or. angle_in(t, g%t0, g%t1)
    e0 = [cos(g%t0), sin(g%t0)]
    e1 = [cos(g%t1), sin(g%t1)]
    d = huge(1.0_wp)
    ! distance to the two arcs
    if (in_angle) then
      d = abs(r - g%r1)
      ! (a solid disk, r0 = 0, has no inner arc)
      if (g%r0 > 0.0_wp) d = min(d, abs(r - g%r0))
    else
      d = min(norm2(q - g%r0*e0), norm2(q - g%r1*e0), norm2(q - g%r0*e1), norm2(q - g%r1*e1))
    end if
    if (.not. full) then
      d = min(d, segment_distance(g%r0*e0, g%r1*e0, q), segment_distance(g%r0*e1, g%r1*e1, q))
    end if
    sd = d
    if (in_angle .and. r >= g%r0 .and. r <= g%r1) sd = -d
  end function annulus_sd

  pure logical function angle_in(t, t0, t1)
    real(wp), intent(in) :: t, t0, t1
    real(wp) :: u
    u = modulo(t - t0, 2.0_wp*pi)
    angle_in = u <= t1 - t0
  end function angle_in

  !> The first pair of edges of the closed polygon v(2, nv) that cross, touch or overlap
  !! (e1 < e2; edge i joins vertex i to vertex i + 1, edge nv closes the loop), or an edge of
  !! zero length (e1 = e2); e1 = e2 = 0 when the polygon is simple. Neighbouring edges meet
  !! at their shared vertex and count only when they fold back onto each other. O(nv^2):
  !! for the few vertices of a deck.
  pure subroutine polygon_crossing(v, nv, e1, e2)
    real(wp), intent(in) :: v(:, :)
    integer, intent(in) :: nv
    integer, intent(out) :: e1, e2
    real(wp) :: tol, a(2), b(2), c(2), d(2)
    integer :: i, j
    e1 = 0
    e2 = 0
    ! orientations below tol (m^2) count as collinear: round-off of the vertex coordinates
    tol = 64.0_wp*epsilon(1.0_wp)*sum((maxval(v(:, 1:nv), dim=2) - &
      minval(v(:, 1:nv), dim=2))**2)
    do i = 1, nv
      if (sum((v(:, next(i)) - v(:, i))**2) <= tol) then
        e1 = i
        e2 = i
        return
      end if
    end do
    do i = 1, nv - 1
      a = v(:, i)
      b = v(:, next(i))
      do j = i + 1, nv
        c = v(:, j)
        d = v(:, next(j))
        if (j == i + 1) then
          if (abs(orient(a, b, d)) <= tol .and. dot_product(b - a, d - c) < 0.0_wp) exit
          cycle
        else if (i == 1 .and. j == nv) then
          if (abs(orient(c, d, b)) <= tol .and. dot_product(d - c, b - a) < 0.0_wp) exit
          cycle
        end if
        if (segments_meet(a, b, c, d, tol)) exit
      end do
      if (j <= nv) then
        e1 = i
        e2 = j
        return
      end if
    end do
  contains
    pure integer function next(k)
      integer, intent(in) :: k
      next = merge(1, k + 1, k == nv)
    end function next
  end subroutine polygon_crossing

  !> Twice the signed area of the triangle (a, b, c): > 0 when c is left of a -> b.
  pure real(wp) function orient(a, b, c)
    real(wp), intent(in) :: a(2), b(2), c(2)
    orient = (b(1) - a(1))*(c(2) - a(2)) - (b(2) - a(2))*(c(1) - a(1))
  end function orient

  !> Segments [a, b] and [c, d] cross or touch (orientations within tol count as zero).
  pure logical function segments_meet(a, b, c, d, tol) result(meet)
    real(wp), intent(in) :: a(2), b(2), c(2), d(2), tol
    real(wp) :: o(4)
    o = [orient(c, d, a), orient(c, d, b), orient(a, b, c), orient(a, b, d)]
    where (abs(o) <= tol) o = 0.0_wp
    meet = o(1)*o(2) < 0.0_wp .and. o(3)*o(4) < 0.0_wp
    if (meet) return
    meet = (o(1) == 0.0_wp .and. in_box(c, d, a)) .or. (o(2) == 0.0_wp .and. in_box(c, d, b)) &
      .or. (o(3) == 0.0_wp .and. in_box(a, b, c)) .or. (o(4) == 0.0_wp .and. in_box(a, b, d))
  contains
    pure logical function in_box(p, q, r)
      real(wp), intent(in) :: p(2), q(2), r(2)
      in_box = all(r >= min(p, q)) .and. all(r <= max(p, q))
    end function in_box
  end function segments_meet

  !> Shoelace area of a polygon (positive when counter-clockwise).
  pure real(wp) function polygon_area(v, nv) result(a)
    real(wp), intent(in) :: v(:, :)
    integer, intent(in) :: nv
    integer :: i, j
    a = 0.0_wp
    j = nv
    do i = 1, nv
      a = a + (v(1, j)*v(2, i) - v(1, i)*v(2, j))
      j = i
    end do
    a = 0.5_wp*a
  end function polygon_area

  !> Clip polygon v (any shape) by the box [lo, hi] (Sutherland-Hodgman); result w(2, nw).
  pure subroutine clip_polygon_box(v, lo, hi, w, nw)
    real(wp), intent(in) :: v(:, :), lo(2), hi(2)
    real(wp), intent(out) :: w(:, :)
    integer, intent(out) :: nw
    real(wp) :: a(2, size(w, 2)), b(2, size(w, 2))
    integer :: na, edge
    na = size(v, 2)
    a(:, 1:na) = v
    do edge = 1, 4
      call clip_half(a, na, edge, lo, hi, b, nw)
      na = nw
      a(:, 1:na) = b(:, 1:nw)
      if (na == 0) exit
    end do
    nw = na
    w(:, 1:nw) = a(:, 1:nw)
    call remove_spikes(w, nw)
  end subroutine clip_polygon_box

  !> Removes the zero-width spikes Sutherland-Hodgman leaves when a concave polygon is
  !! clipped: where an intermediate clip splits the polygon, the pieces stay joined by
  !! edges along the clip line, out and back, and a later clip can cut those to a spike
  !! (C-shape: the strip of a box below the notch keeps an edge up into the notch and back).
  !! A spike encloses no area but reaches out of the polygon, where the RK shape functions
  !! of an integration point may not be defined. Removed: vertices repeating the previous
  !! one (to the round-off of the cut points) and vertices where the outline turns back on
  !! itself along a line. Zero-width bridges between separate pieces of the same box (a
  !! thin notch across it) are not spikes and stay; fewer than 3 vertices left: empty.
  pure subroutine remove_spikes(w, nw)
    real(wp), intent(inout) :: w(:, :)
    integer, intent(inout) :: nw
    real(wp) :: a(2), b(2), tol
    integer :: k
    logical :: found
    if (nw < 3) return
    ! the round-off of a cut point: a few eps of the coordinates
    tol = 64.0_wp*epsilon(1.0_wp)*maxval(abs(w(:, 1:nw)))
    do
      if (nw < 3) exit
      found = .false.
      do k = 1, nw
        a = w(:, k) - w(:, merge(nw, k - 1, k == 1))
        b = w(:, merge(1, k + 1, k == nw)) - w(:, k)
        if (norm2(a) <= tol) then
          found = .true.
        else if (dot_product(a, b) < 0.0_wp .and. &
          abs(a(1)*b(2) - a(2)*b(1)) <= tol*(norm2(a) + norm2(b))) then
          found = .true.
        end if
        if (found) exit
      end do
      if (.not. found) exit
      w(:, k:nw - 1) = w(:, k + 1:nw)
      nw = nw - 1
    end do
    if (nw < 3) nw = 0
  end subroutine remove_spikes

  pure subroutine clip_half(a, na, edge, lo, hi, b, nb)
    real(wp), intent(in) :: a(:, :), lo(2), hi(2)
    integer, intent(in) :: na, edge
    real(wp), intent(out) :: b(:, :)
    integer, intent(out) :: nb
    integer :: i, j
    logical :: ini, inj
    real(wp) :: t
    nb = 0
    if (na == 0) return
    j = na
    do i = 1, na
      ini = inside(a(:, i))
      inj = inside(a(:, j))
      if (ini .neqv. inj) then
        t = cross_t(a(:, j), a(:, i))
        nb = nb + 1
        b(:, nb) = a(:, j) + t*(a(:, i) - a(:, j))
      end if
      if (ini) then
        nb = nb + 1
        b(:, nb) = a(:, i)
      end if
      j = i
    end do
  contains
    pure logical function inside(p)
      real(wp), intent(in) :: p(2)
      select case (edge)
      case (1)
        inside = p(1) >= lo(1)
      case (2)
        inside = p(1) <= hi(1)
      case (3)
        inside = p(2) >= lo(2)
      case default
        inside = p(2) <= hi(2)
      end select
    end function inside
    pure real(wp) function cross_t(p, q)
      real(wp), intent(in) :: p(2), q(2)
      select case (edge)
      case (1)
        cross_t = (lo(1) - p(1))/(q(1) - p(1))
      case (2)
        cross_t = (hi(1) - p(1))/(q(1) - p(1))
      case (3)
        cross_t = (lo(2) - p(2))/(q(2) - p(2))
      case default
        cross_t = (hi(2) - p(2))/(q(2) - p(2))
      end select
    end function cross_t
  end subroutine clip_half

  !> The cross product a x b of two 3-vectors.
  pure function cross3(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)
    real(wp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross3

  !> Twice the area of the triangle xt(2, 3), positive when counter-clockwise (m^2): one
  !! function for cst4_m's element areas and the nodes' lumped areas made per rank
  !! (generators_m lattice_node), so that both are the same bits.
  pure real(wp) function twice_area(xt) result(a2)
    real(wp), intent(in) :: xt(2, 3)
    a2 = (xt(1, 2) - xt(1, 1))*(xt(2, 3) - xt(2, 1)) &
      - (xt(1, 3) - xt(1, 1))*(xt(2, 2) - xt(2, 1))
  end function twice_area
end module geometry_m
