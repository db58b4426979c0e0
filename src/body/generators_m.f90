!> Particle-body generators: segment (1D), rectangle and polygon (2D lattices, e.g. the L- or
!! C-shaped concave domain of Figs. 6-7), annulus sector (polar lattice), solid disk
!! (concentric rings with explicit cells), and bodies given as arrays (read from a particle
!! file). Each particle gets its volume (its lattice cell
!! clipped by the exact shape), its support rho = support_factor x spacing per direction,
!! a boundary flag, and the ordered, counter-clockwise boundary polylines.
module generators_m
  use kinds_m, only: wp, pi, i64
  use errors_m, only: error_t, set_error
  use body_m, only: body_t, max_cell_vertices, extrusion_t, lattice_t
  use geometry_m, only: geometry_t, geom_segment, geom_polygon, geom_annulus, geom_prism, &
    geom_cylinder, &
    signed_distance, polygon_area, clip_polygon_box, segment_distance, full_turn_tol, twice_area
  use sorting_m, only: sort_index
  use rank_comm_m, only: share_first
  use strings_m, only: itoa, rtoa
  implicit none
  private
  public :: make_segment, make_rectangle, make_polygon, make_annulus, make_from_arrays
  public :: make_disk, disk_ring_count, lattice_cells_explicit, extrude_body
  public :: set_supports, perturb_interior, max_perturbation, section_triangles
  public :: extrude_pick, extrude_count, extruded_particle, extruded_facet, extruded_nfacets
  public :: lattice_particle, lattice_pick, lattice_count, body_pick, body_count
  public :: lattice_node, lattice_nodes, lattice_loop, polygon_merges, lattice_corners
  public :: polar_boxes, annulus_supports, mean_spacing

  !> Relative tolerance for "on the boundary" and "cell is cut" decisions on lattices.
  real(wp), parameter :: geom_tol = 1.0e-9_wp
  !> Largest perturbation, as a fraction of the spacing: below 1/2 every moved particle stays
  !! strictly inside its own lattice cell, so the cells still hold one particle each.
  real(wp), parameter :: max_perturbation = 0.5_wp
  !> Marsaglia's xorshift64 example seed (Marsaglia, J. Stat. Softw. 8(14), 2003), mixed with
  !! the deck's seed; the state must not be 0.
  integer(i64), parameter :: xorshift_base = 88172645463325252_i64
  !> Draws discarded after seeding: nearby seeds differ in a few low bits, and xorshift64
  !! needs a few rounds to spread them over the whole word.
  integer, parameter :: xorshift_warmup = 16

contains

  !> n particles evenly on [a, b] (Example 2.1); end particles carry half a cell.
  subroutine make_segment(b, a, bb, n, err)
    type(body_t), intent(out) :: b
    real(wp), intent(in) :: a, bb
    integer, intent(in) :: n
    type(error_t), allocatable, intent(inout) :: err
    integer :: i
    real(wp) :: dx
    if (n < 2 .or. bb <= a) then
      call set_error(err, 'segment needs n >= 2 and hi > lo')
      return
    end if
    dx = (bb - a)/real(n - 1, wp)
    b%ndim = 1
    b%np = n
    allocate(b%x(1, n), b%vol(n), b%boundary(n))
    do i = 1, n
      b%x(1, i) = a + real(i - 1, wp)*dx
    end do
    b%vol = dx
    b%vol(1) = 0.5_wp*dx
    b%vol(n) = 0.5_wp*dx
    b%boundary = .false.
    b%boundary([1, n]) = .true.
    b%spacing = 0.0_wp
    b%spacing(1) = dx
    b%nloops = 0
    allocate(b%loop_ptr(1), b%loop_idx(0), b%loop_closed(0))
    b%loop_ptr = 1
    b%geom%kind = geom_segment
    b%geom%a = a
    b%geom%b = bb
  end subroutine make_segment

  !> n(1) x n(2) particles on [lo, hi] (Example 2.2).
  subroutine make_rectangle(b, lo, hi, n, err, share, cst4)
    type(body_t), intent(out) :: b
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: n(2)
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: only rank me's share of the particles (rank_comm_m share_first, as
    !! body_keep_share cuts it: b%held_share, b%row0), made from the recipe (b%lat), with
    !! the whole boundary loop (its ring's particles only)
    integer, intent(in), optional :: share(2)
    !> with share: the nodes of a CST4 rectangle on this lattice (lattice_t cst4: the
    !! lattice points, then the boxes' centres, their lumped volumes), its share of them
    logical, intent(in), optional :: cst4
    real(wp) :: v(2, 4), dx(2)
    logical :: ok
    if (any(n < 2) .or. any(hi <= lo)) then
      call set_error(err, 'rectangle needs n >= 2 in each direction and hi > lo')
      return
    end if
    dx = (hi - lo)/real(n - 1, wp)
    v(:, 1) = lo
    v(:, 2) = [hi(1), lo(2)]
    v(:, 3) = hi
    v(:, 4) = [lo(1), hi(2)]
    if (.not. present(share)) then
      call make_polygon(b, v, dx, lo, err)
      if (allocated(err)) return
    else if (int(n(1), i64)*n(2) > int(huge(1), i64)) then
      call set_error(err, 'rectangle: more than 2**31 - 1 lattice points; give fewer')
      return
    end if
    ! the recipe (a rank makes its share and region from it: lattice_particle)
    allocate(b%lat)
    b%lat%n = n
    b%lat%origin = lo
    b%lat%dx = dx
    b%lat%g%kind = geom_polygon
    b%lat%g%v = v
    if (.not. present(share)) return
    if (present(cst4)) b%lat%cst4 = cst4
    b%ndim = 2
    b%geom = b%lat%g
    b%np = lattice_nodes(b%lat)
    b%spacing = 0.0_wp
    b%spacing(1:2) = dx
    call lattice_share(b, share)
    call lattice_loop(b%lat, b, ok)
    if (.not. ok) call set_error(err, 'rectangle: its lattice is not the n(1) x n(2) '// &
      'points a rank makes its share of (an internal error of the generator; the serial '// &
      'run, mfcd, makes it whole)')
  end subroutine make_rectangle

  !> Rank share(1)'s share of the share(2) ranks of the particles (nodes) of b, a body of
  !! b%np made from its recipe b%lat (rank_comm_m share_first, as body_keep_share cuts it:
  !! b%held_share, b%row0, the share's arrays from 1), by lattice_node.
  subroutine lattice_share(b, share)
    type(body_t), intent(inout) :: b
    integer, intent(in) :: share(2)
    integer :: q, q0, q1
    q0 = share_first(b%np, share(1), share(2))
    q1 = share_first(b%np, share(1) + 1, share(2)) - 1
    b%held_share = .true.
    b%row0 = q0
    ! (particle q at q - q0 + 1: a share's arrays from 1, as body_keep_share leaves them)
    allocate(b%x(2, q1 - q0 + 1), b%vol(q1 - q0 + 1), b%boundary(q1 - q0 + 1))
    do q = q0, q1
      call lattice_node(b%lat, q, b%x(:, q - q0 + 1), b%vol(q - q0 + 1), &
        b%boundary(q - q0 + 1))
    end do
  end subroutine lattice_share

  !> Lattice point (i, j) of rectangle recipe lat (make_rectangle's; i, j from 0): its
  !! position, volume (its lattice cell clipped by the rectangle) and boundary flag by
  !! make_polygon's operations in its order, so the same bits, then moved by lat%shift as
  !! build_body's placement does (unless as_made).
  pure subroutine lattice_particle(lat, i, j, x, vol, bnd, as_made)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: i, j
    real(wp), intent(out) :: x(2), vol
    logical, intent(out) :: bnd
    logical, intent(in), optional :: as_made
    real(wp) :: p(2), sd, w(2, 64)
    integer :: nw
    logical :: moved
    call lattice_point(lat, i, j, p, sd, vol, nw, w)
    bnd = abs(sd) <= geom_tol*minval(lat%dx) .or. vol < (1.0_wp - geom_tol)* &
      (lat%dx(1)*lat%dx(2))
    moved = lat%shifted
    if (present(as_made)) moved = moved .and. .not. as_made
    x = p
    if (moved) x = x + lat%shift
  end subroutine lattice_particle

  !> Node q of the rectangle of recipe lat: lattice point q (i + 1 + j n(1): position,
  !! volume, boundary flag, lattice_particle's); or of a CST4 rectangle's (lat%cst4,
  !! cst4_m cst4_rectangle's operations in its order, so the same bits): a box's corner
  !! (q <= n(1) n(2)), its volume a third of a quarter box added once for each triangle
  !! at it, or a box's centre (the mean of its four corners as made), four such thirds.
  pure subroutine lattice_node(lat, q, x, vol, bnd, rho)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: q
    real(wp), intent(out) :: x(2), vol
    logical, intent(out) :: bnd
    !> its supports (an annulus's from its position as made, build_body's local spacing;
    !! else the recipe's, lat%rho)
    real(wp), intent(out), optional :: rho(2)
    real(wp) :: xc(2, 4), a3, v
    integer :: nc, i, j, m, ntri
    logical :: b
    if (present(rho)) rho = lat%rho
    if (lat%polar) then
      call polar_node(lat, q, x, vol, bnd)
      if (present(rho)) rho = lat%factor*max(lat%sdr, norm2(x - lat%center)*lat%sdt)
      if (lat%shifted) x = x + lat%shift
      return
    end if
    nc = lat%n(1)*lat%n(2)
    if (allocated(lat%run_ptr)) nc = lat%nq
    if (q <= nc) then
      call lattice_ij(lat, q, i, j)
      call lattice_particle(lat, i, j, x, vol, bnd)
      if (.not. lat%cst4) return
      ! (two triangles of each box at the corner)
      ntri = 2*(merge(1, 0, i > 0) + merge(1, 0, i < lat%n(1) - 1))* &
        (merge(1, 0, j > 0) + merge(1, 0, j < lat%n(2) - 1))
    else
      m = q - nc - 1
      i = mod(m, lat%n(1) - 1)
      j = m/(lat%n(1) - 1)
      call lattice_particle(lat, i, j, xc(:, 1), v, b, as_made=.true.)
      call lattice_particle(lat, i + 1, j, xc(:, 2), v, b, as_made=.true.)
      call lattice_particle(lat, i + 1, j + 1, xc(:, 3), v, b, as_made=.true.)
      call lattice_particle(lat, i, j + 1, xc(:, 4), v, b, as_made=.true.)
      x = 0.25_wp*sum(xc, dim=2)
      if (lat%shifted) x = x + lat%shift
      bnd = .false.
      ntri = 4
    end if
    a3 = 0.25_wp*lat%dx(1)*lat%dx(2)/3.0_wp
    vol = 0.0_wp
    do m = 1, ntri
      vol = vol + a3
    end do
  end subroutine lattice_node

  !> The number of nodes of the rectangle of recipe lat: its lattice points, and a CST4
  !! rectangle's box centres.
  pure integer function lattice_nodes(lat) result(n)
    type(lattice_t), intent(in) :: lat
    n = lattice_corners(lat)
    if (lat%cst4) n = n + (lat%n(1) - 1)*polar_boxes(lat)
  end function lattice_nodes

  !> The number of lattice points of recipe lat (a CST4 body's corners, numbered first)
  pure integer function lattice_corners(lat) result(n)
    type(lattice_t), intent(in) :: lat
    n = lat%n(1)*lat%n(2)
    if (allocated(lat%run_ptr)) n = lat%nq
  end function lattice_corners

  !> The rows of boxes of a CST4 lattice along its second index: n(2) - 1, or n(2) around
  !! a whole ring (its last boxes close onto the first)
  pure integer function polar_boxes(lat) result(n)
    type(lattice_t), intent(in) :: lat
    n = lat%n(2) - 1
    if (lat%polar .and. lat%full) n = lat%n(2)
  end function polar_boxes

  !> Corner (i, j) of the polar lattice of recipe lat (i, j from 1; j modulo n(2) around
  !! a ring), as made: make_annulus's operations, the same bits.
  pure function polar_corner(lat, i, j) result(x)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: i, j
    real(wp) :: x(2), r, t
    t = lat%t0 + real(modulo(j - 1, lat%n(2)), wp)*lat%dt
    r = lat%r0 + real(i - 1, wp)*lat%dr
    x = lat%center + [r*cos(t), r*sin(t)]
  end function polar_corner

  !> Node q of the CST4 annulus of recipe lat (polar), as made, by cst4_m cst4_annulus's
  !! operations in its order (the same bits): a corner (q <= n(1) n(2); make_annulus's
  !! boundary flag) or a box's centre (the mean of its corners; interior); its lumped area
  !! a third of each triangle at it, added in the triangles' order (four a box: bottom,
  !! right, top, left of its corners (ib, jb), (ib + 1, jb), (ib + 1, jb + 1), (ib, jb + 1)).
  pure subroutine polar_node(lat, q, x, vol, bnd)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: q
    real(wp), intent(out) :: x(2), vol
    logical, intent(out) :: bnd
    integer :: n1, nc, i, j, box, ib(4), jb(4), k(2, 4), e(8), order(8), ne, m, l, t
    real(wp) :: xc(2, 4), xt(2, 3)
    n1 = lat%n(1)
    nc = n1*lat%n(2)
    ne = 0
    if (q <= nc) then
      i = mod(q - 1, n1) + 1
      j = (q - 1)/n1 + 1
      x = polar_corner(lat, i, j)
      bnd = i == 1 .or. i == n1 .or. ((j == 1 .or. j == lat%n(2)) .and. .not. lat%full)
      ! (the boxes at the corner: it is their corner 1, 2, 3 or 4, in two triangles each)
      ib = [i, i - 1, i - 1, i]
      jb = [j, j, j - 1, j - 1]
      k = reshape([1, 4, 1, 2, 2, 3, 3, 4], [2, 4])
      do m = 1, 4
        if (jb(m) == 0 .and. lat%full) jb(m) = lat%n(2)
        if (ib(m) < 1 .or. ib(m) > n1 - 1 .or. jb(m) < 1 .or. jb(m) > polar_boxes(lat)) cycle
        box = ib(m) + (jb(m) - 1)*(n1 - 1)
        e(ne + 1:ne + 2) = 4*(box - 1) + k(:, m)
        ne = ne + 2
      end do
    else
      box = q - nc
      i = mod(box - 1, n1 - 1) + 1
      j = (box - 1)/(n1 - 1) + 1
      xc = box_corners(i, j)
      x = 0.25_wp*sum(xc, dim=2)
      bnd = .false.
      e(1:4) = 4*(box - 1) + [1, 2, 3, 4]
      ne = 4
    end if
    ! (the triangles in ascending numbers, as cst4_annulus adds them)
    do m = 1, ne
      order(m) = m
    end do
    do m = 2, ne
      t = order(m)
      l = m - 1
      do while (l >= 1)
        if (e(order(l)) <= e(t)) exit
        order(l + 1) = order(l)
        l = l - 1
      end do
      order(l + 1) = t
    end do
    vol = 0.0_wp
    do m = 1, ne
      box = (e(order(m)) - 1)/4 + 1
      l = mod(e(order(m)) - 1, 4) + 1
      xc = box_corners(mod(box - 1, n1 - 1) + 1, (box - 1)/(n1 - 1) + 1)
      xt(:, 1) = xc(:, l)
      xt(:, 2) = xc(:, mod(l, 4) + 1)
      xt(:, 3) = 0.25_wp*sum(xc, dim=2)
      vol = vol + 0.5_wp*twice_area(xt)/3.0_wp
    end do
  contains
    !> the corners of box (bi, bj) as made, counter-clockwise (cst4_annulus's order)
    pure function box_corners(bi, bj) result(c)
      integer, intent(in) :: bi, bj
      real(wp) :: c(2, 4)
      c(:, 1) = polar_corner(lat, bi, bj)
      c(:, 2) = polar_corner(lat, bi + 1, bj)
      c(:, 3) = polar_corner(lat, bi + 1, bj + 1)
      c(:, 4) = polar_corner(lat, bi, bj + 1)
    end function box_corners
  end subroutine polar_node

  !> The boundary loops of the annulus of recipe lat (polar) into b, make_annulus's: a ring's
  !! outer circle counter-clockwise and inner one clockwise, a sector's one loop.
  subroutine polar_loops(lat, b)
    type(lattice_t), intent(in) :: lat
    type(body_t), intent(inout) :: b
    integer :: i, j, nr, nt, nb
    nr = lat%n(1)
    nt = lat%n(2)
    if (lat%full) then
      b%nloops = 2
      b%loop_ptr = [1, nt + 1, 2*nt + 1]
      b%loop_idx = [([(idx(nr, j), j = 1, nt)]), ([(idx(1, j), j = nt, 1, -1)])]
      b%loop_closed = [.true., .true.]
    else
      nb = 2*(nr - 1) + 2*(nt - 1)
      b%nloops = 1
      b%loop_ptr = [1, nb + 1]
      b%loop_idx = [[(idx(i, 1), i = 1, nr - 1)], [(idx(nr, j), j = 1, nt - 1)], &
        [(idx(i, nt), i = nr, 2, -1)], [(idx(1, j), j = nt, 2, -1)]]
      b%loop_closed = [.true.]
    end if
  contains
    pure integer function idx(ir, jt)
      integer, intent(in) :: ir, jt
      idx = ir + (jt - 1)*nr
    end function idx
  end subroutine polar_loops

  !> The lattice indices (i, j) of particle q of recipe lat: a rectangle's (i + 1) + j n(1),
  !! a polygon's by its runs (the run holding q, by bisection over their first numbers).
  pure subroutine lattice_ij(lat, q, i, j)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: q
    integer, intent(out) :: i, j
    integer :: lo, hi, mid
    if (.not. allocated(lat%run_ptr)) then
      i = mod(q - 1, lat%n(1))
      j = (q - 1)/lat%n(1)
      return
    end if
    ! (the last run whose first particle is at most q)
    lo = 1
    hi = size(lat%run_q)
    do while (lo < hi)
      mid = (lo + hi + 1)/2
      if (lat%run_q(mid) < q) then
        lo = mid
      else
        hi = mid - 1
      end if
    end do
    j = lat%run_j(lo)
    i = lat%run_i(1, lo) + (q - lat%run_q(lo) - 1)
  end subroutine lattice_ij

  !> make_polygon's look at lattice point (i, j) of recipe lat: its position p, signed
  !! distance sd to the rectangle, and its clipped cell (w, nw) and area a.
  pure subroutine lattice_point(lat, i, j, p, sd, a, nw, w)
    type(lattice_t), intent(in) :: lat
    integer, intent(in) :: i, j
    real(wp), intent(out) :: p(2), sd, a, w(2, 64)
    integer, intent(out) :: nw
    p = lat%origin + [real(i, wp)*lat%dx(1), real(j, wp)*lat%dx(2)]
    sd = signed_distance(lat%g, p)
    call clip_polygon_box(lat%g%v, p - 0.5_wp*lat%dx, p + 0.5_wp*lat%dx, w, nw)
    a = 0.0_wp
    if (nw >= 3) a = polygon_area(w, nw)
  end subroutine lattice_point

  !> The boundary loop of the rectangle of recipe lat into b (make_polygon's: its boundary
  !! particles in ascending numbers, sorted by edge_key), made from the ring of the
  !! lattice's outermost points alone; ok: make_polygon keeps exactly the n(1) x n(2)
  !! points (every point of the ring within the rectangle and a boundary particle, every
  !! point of the ring around it outside with no piece of its cell inside, which
  !! make_polygon would merge), so that particle (i + 1) + j n(1) is lattice point (i, j)
  !! and the ring's particles are the boundary's (an inner cell is the whole lattice box).
  subroutine lattice_loop(lat, b, ok)
    type(lattice_t), intent(in) :: lat
    type(body_t), intent(inout) :: b
    logical, intent(out) :: ok
    integer, allocatable :: bl(:), order(:)
    real(wp), allocatable :: key(:)
    real(wp) :: x(2), vol, p(2), sd, a, w(2, 64), tol, reach
    integer :: i, j, k, nb, nw
    logical :: bnd
    tol = geom_tol*minval(lat%dx)
    reach = 0.5_wp*norm2(lat%dx)
    ok = .true.
    nb = 0
    allocate(bl(2*(lat%n(1) + lat%n(2))), key(2*(lat%n(1) + lat%n(2))))
    do j = -1, lat%n(2)
      do k = 1, lat%n(1) + 2
        ! (the rows of the two rings whole, of the others their two ends each side)
        i = k - 2
        if (j > 0 .and. j < lat%n(2) - 1) then
          if (k > 4) exit
          i = merge(k - 2, lat%n(1) + k - 4, k <= 2)
        end if
        if (i > -1 .and. i < lat%n(1) .and. j > -1 .and. j < lat%n(2)) then
          call lattice_particle(lat, i, j, x, vol, bnd, as_made=.true.)
          call lattice_point(lat, i, j, p, sd, a, nw, w)
          ok = ok .and. bnd .and. sd <= tol
          nb = nb + 1
          bl(nb) = i + 1 + j*lat%n(1)
          key(nb) = edge_key(lat%g%v, x)
        else
          ! (the ring around: outside, and no piece of its cell inside)
          call lattice_point(lat, i, j, p, sd, a, nw, w)
          ok = ok .and. sd > tol .and. (sd >= reach .or. .not. a > 0.0_wp)
        end if
      end do
    end do
    allocate(order(nb))
    call sort_index(key(1:nb), order)
    b%nloops = 1
    b%loop_ptr = [1, nb + 1]
    b%loop_idx = bl(order)
    b%loop_closed = [.true.]
  end subroutine lattice_loop

  !> Some particles of rectangle b (its recipe b%lat, make_rectangle's: the whole body is
  !! never made), as extrude_pick takes an extruded body's: those numbered g0 ... g1
  !! whose reference position, or one of its mirror images across the lines (nplanes of
  !! them: coordinate normal(m) = pos(m); and across both), lies within [lo, hi] (their
  !! first two entries); ends: of the lattice's outermost ring only (the whole cloud's
  !! extremes are theirs and their images'). As body r, in ascending numbers (r%glob, of
  !! r%np_whole = b%np): positions, volumes, boundary flags and supports (b%lat%rho) the
  !! whole body's bits; b's description copied (name, kernel, spacing, supports' factors,
  !! geometry, the recipe); no boundary loops. Only the lattice rows and columns that can
  !! hold such a particle are walked (a rank's region, not the whole body).
  subroutine lattice_pick(b, g0, g1, lo, hi, nplanes, normal, pos, r, ends)
    type(body_t), intent(in) :: b
    integer, intent(in) :: g0, g1, nplanes, normal(:)
    real(wp), intent(in) :: lo(:), hi(:), pos(:)
    type(body_t), intent(out) :: r
    logical, intent(in), optional :: ends
    integer :: n, pass, i, j, q, k(2, 2), m, ir(2)
    real(wp) :: x(2), vol, rh(2)
    logical :: bnd, only_ends
    logical, allocatable :: jm(:)
    only_ends = .false.
    if (present(ends)) only_ends = ends
    call copy_description(b, r)
    r%ndim = 2
    r%lat = b%lat
    r%np_whole = lattice_nodes(b%lat)
    if (b%lat%polar) then
      ! the radii and angles of the box (polar_span)
      allocate(jm(b%lat%n(2)))
      call polar_span(b%lat, lo(1:2), hi(1:2), nplanes, ir, jm)
    else
      ! the lattice indices each axis can take (a position or an image within the box)
      do i = 1, 2
        k(i, :) = index_span(i)
      end do
    end if
    associate (l => b%lat)
      do pass = 1, 2
        n = 0
        if (allocated(l%run_ptr)) then
          ! a polygon's: the runs of the rows in the span; its ends each run's first and
          ! last particles and each column's lowest (every row's and column's coordinate)
          do j = k(2, 1), k(2, 2)
            do m = l%run_ptr(j - l%j0 + 1), l%run_ptr(j - l%j0 + 2) - 1
              do i = max(k(1, 1), l%run_i(1, m)), min(k(1, 2), l%run_i(2, m))
                if (only_ends .and. i > l%run_i(1, m) .and. i < l%run_i(2, m) .and. &
                  j /= l%col_low(i - l%i0 + 1)) cycle
                q = l%run_q(m) + i - l%run_i(1, m) + 1
                if (q < g0 .or. q > g1) cycle
                call take(q)
              end do
            end do
          end do
        end if
        if (l%polar) then
          ! an annulus's: the corners of the radii and angles the box can hold, then the
          ! boxes' centres among them
          do j = 1, l%n(2)
            if (.not. jm(j)) cycle
            do i = ir(1), ir(2)
              if (only_ends .and. i > 1 .and. i < l%n(1)) cycle
              q = i + (j - 1)*l%n(1)
              if (q < g0 .or. q > g1) cycle
              call take(q)
            end do
          end do
          do j = 1, polar_boxes(l)
            if (only_ends) exit
            if (.not. (jm(j) .or. jm(modulo(j, l%n(2)) + 1))) cycle
            do i = max(1, ir(1) - 1), min(l%n(1) - 1, ir(2))
              q = l%n(1)*l%n(2) + i + (j - 1)*(l%n(1) - 1)
              if (q < g0 .or. q > g1) cycle
              call take(q)
            end do
          end do
        end if
        do j = k(2, 1), k(2, 2)
          if (allocated(l%run_ptr) .or. l%polar) exit
          do i = k(1, 1), k(1, 2)
            if (only_ends .and. i > 0 .and. i < l%n(1) - 1 .and. j > 0 .and. &
              j < l%n(2) - 1) cycle
            q = i + 1 + j*l%n(1)
            if (q < g0 .or. q > g1) cycle
            call take(q)
          end do
        end do
        ! (a CST4 rectangle's box centres, numbered after the corners: lattice_node)
        if (l%cst4 .and. .not. only_ends .and. .not. l%polar) then
          do j = max(0, k(2, 1) - 1), min(l%n(2) - 2, k(2, 2))
            do i = max(0, k(1, 1) - 1), min(l%n(1) - 2, k(1, 2))
              q = l%n(1)*l%n(2) + i + 1 + j*(l%n(1) - 1)
              if (q < g0 .or. q > g1) cycle
              call take(q)
            end do
          end do
        end if
        if (pass == 1) allocate(r%x(2, n), r%vol(n), r%boundary(n), r%rho(2, n), r%glob(n))
      end do
    end associate
    r%np = n

  contains

    !> The lattice indices along axis d (0 ... n(d) - 1) whose coordinate or its image
    !! across a line normal to d lies within [lo(d), hi(d)], widened by one for rounding
    !! (take tests each node exactly)
    function index_span(d) result(span)
      integer, intent(in) :: d
      integer :: span(2), m, ia, ic, k0
      real(wp) :: o, a, c
      ! (a polygon's lattice indices from i0, j0: k0 + 0 ... n(d) - 1)
      k0 = 0
      if (allocated(b%lat%run_ptr)) k0 = merge(b%lat%i0, b%lat%j0, d == 1)
      o = b%lat%origin(d) + real(k0, wp)*b%lat%dx(d)
      if (b%lat%shifted) o = o + b%lat%shift(d)
      span = [index_at(lo(d), o, b%lat%dx(d), b%lat%n(d), .false.), &
        index_at(hi(d), o, b%lat%dx(d), b%lat%n(d), .true.)]
      do m = 1, nplanes
        if (normal(m) /= d) cycle
        ! (the image of [lo, hi] across the line: [2 pos - hi, 2 pos - lo])
        a = 2.0_wp*pos(m) - hi(d)
        c = 2.0_wp*pos(m) - lo(d)
        ia = index_at(a, o, b%lat%dx(d), b%lat%n(d), .false.)
        ic = index_at(c, o, b%lat%dx(d), b%lat%n(d), .true.)
        if (ia <= ic) then
          span(1) = min(span(1), ia)
          span(2) = max(span(2), ic)
        end if
      end do
      if (span(1) > span(2)) span = [0, -1]
      span = span + k0
    end function index_span

    !> node q when it or one of its images lies within [lo, hi]: counted (pass 1) and
    !! stored (pass 2)
    subroutine take(q)
      integer, intent(in) :: q
      call lattice_node(b%lat, q, x, vol, bnd, rh)
      if (.not. near_images(x, lo(1:2), hi(1:2), nplanes, normal, pos)) return
      n = n + 1
      if (pass == 1) return
      r%x(:, n) = x
      r%vol(n) = vol
      r%boundary(n) = bnd
      r%rho(:, n) = rh
      r%glob(n) = q
    end subroutine take
  end subroutine lattice_pick

  !> The radii ir(1) ... ir(2) and the angles jm(j) of the polar lattice of recipe lat
  !! whose corners can lie within [lo, hi] (lattice_pick's box, in the positions as moved
  !! by lat%shift), widened by two spacings each way for the rounding (lattice_pick tests
  !! each node exactly): the radii between the box's least and greatest distance from the
  !! centre, the angles of the box as seen from it (all of them when the box holds the
  !! centre, or the pick takes mirror images: nplanes > 0).
  pure subroutine polar_span(lat, lo, hi, nplanes, ir, jm)
    type(lattice_t), intent(in) :: lat
    real(wp), intent(in) :: lo(2), hi(2)
    integer, intent(in) :: nplanes
    integer, intent(out) :: ir(2)
    logical, intent(out) :: jm(:)
    real(wp) :: c(2), p(2), dmin, dmax, phi, d, amin, amax, a, z, per, corner(2)
    integer :: m, j0, j1, n1, n2
    n1 = lat%n(1)
    n2 = lat%n(2)
    ir = [1, n1]
    jm = .true.
    if (nplanes > 0) return
    c = lat%center
    if (lat%shifted) c = c + lat%shift
    ! (a box of huge sides reaches everything)
    if (any(abs(lo) > 0.25_wp*huge(1.0_wp)) .or. any(abs(hi) > 0.25_wp*huge(1.0_wp))) return
    p = max(lo, min(hi, c))
    dmin = norm2(p - c)
    dmax = 0.0_wp
    do m = 1, 4
      corner = [merge(lo(1), hi(1), m == 1 .or. m == 4), merge(lo(2), hi(2), m <= 2)]
      dmax = max(dmax, norm2(corner - c))
    end do
    ir(1) = max(1, floor(max(-2.0_wp, min(real(n1 + 1, wp), (dmin - lat%r0)/lat%dr))) - 1)
    ir(2) = min(n1, ceiling(max(-2.0_wp, min(real(n1 + 1, wp), (dmax - lat%r0)/lat%dr))) + 3)
    if (dmin <= 0.0_wp) return
    ! the box's angles about c: within pi of the nearest point's
    phi = atan2(p(2) - c(2), p(1) - c(1))
    amin = 0.0_wp
    amax = 0.0_wp
    do m = 1, 4
      corner = [merge(lo(1), hi(1), m == 1 .or. m == 4), merge(lo(2), hi(2), m <= 2)]
      d = atan2(corner(2) - c(2), corner(1) - c(1)) - phi
      d = d - 2.0_wp*pi*anint(d/(2.0_wp*pi))
      amin = min(amin, d)
      amax = max(amax, d)
    end do
    jm = .false.
    per = 2.0_wp*pi/lat%dt
    do m = -2, 2
      a = (phi + amin - lat%t0)/lat%dt + real(m, wp)*per
      z = (phi + amax - lat%t0)/lat%dt + real(m, wp)*per
      j0 = max(1, floor(max(-3.0_wp, min(real(n2 + 2, wp), a))) - 1)
      j1 = min(n2, ceiling(max(-3.0_wp, min(real(n2 + 2, wp), z))) + 3)
      if (j0 <= j1) jm(j0:j1) = .true.
    end do
  end subroutine polar_span

  !> The first (upper: last) index i of the lattice coordinates o + i dx, i = 0 ... n - 1,
  !! at or beyond coordinate y, widened by one (lattice_pick's span)
  pure integer function index_at(y, o, dx, n, upper) result(i)
    real(wp), intent(in) :: y, o, dx
    integer, intent(in) :: n
    logical, intent(in) :: upper
    real(wp) :: t
    ! (a box's infinite sides: the lattice's ends, without overflowing)
    if (abs(y - o) > real(n + 2, wp)*dx) then
      t = sign(real(n + 2, wp), y - o)
    else
      t = (y - o)/dx
    end if
    t = max(-2.0_wp, min(real(n + 1, wp), t))
    if (upper) then
      i = min(n - 1, ceiling(t) + 1)
    else
      i = max(0, floor(t) - 1)
    end if
  end function index_at

  !> Whether any particle of rectangle b (its recipe, lattice_pick's) lies within [lo, hi]
  !! (their first two entries; 1, else 0), without making the body.
  integer function lattice_count(b, lo, hi) result(n)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(:), hi(:)
    type(body_t) :: r
    integer :: none(2)
    real(wp) :: nowhere(2)
    none = 0
    nowhere = 0.0_wp
    ! (every particle of the whole body: b may be some of them, b%np fewer)
    call lattice_pick(b, 1, huge(1), lo, hi, 0, none, nowhere, r)
    n = min(1, r%np)
  end function lattice_count

  !> Some particles of b, a body whose particles a rank makes from its recipe (a rectangle,
  !! lattice_pick; an extruded body, extrude_pick), by that recipe's pick.
  subroutine body_pick(b, g0, g1, lo, hi, nplanes, normal, pos, r, ends)
    type(body_t), intent(in) :: b
    integer, intent(in) :: g0, g1, nplanes, normal(:)
    real(wp), intent(in) :: lo(:), hi(:), pos(:)
    type(body_t), intent(out) :: r
    logical, intent(in), optional :: ends
    if (allocated(b%lat)) then
      call lattice_pick(b, g0, g1, lo, hi, nplanes, normal, pos, r, ends)
    else
      call extrude_pick(b, g0, g1, lo(1:3), hi(1:3), nplanes, normal, pos, r, ends)
    end if
  end subroutine body_pick

  !> Whether any particle of b (as body_pick) lies within [lo, hi] (1, else 0).
  integer function body_count(b, lo, hi) result(n)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(:), hi(:)
    if (allocated(b%lat)) then
      n = lattice_count(b, lo, hi)
    else
      n = extrude_count(b, lo(1:3), hi(1:3))
    end if
  end function body_count

  !> Lattice points origin + (i dx, j dy) inside or on the polygon v(2, nv).
  !! A particle's cell is its lattice cell clipped by the polygon. The lattice cells whose
  !! point lies outside the polygon but which still hold part of it (orphan pieces, along
  !! the outline) are merged into a particle's cell (b%merged_ptr, b%merged_centre): so the
  !! cells tile the polygon, and the volumes sum to its area to round-off. Each orphan piece
  !! goes to the neighbouring cell (left, right, below, above) with which it shares the
  !! longest stretch of lattice line inside the polygon, taken among the cells that already
  !! have a particle: first the cells of the particles themselves, then, in further rounds,
  !! the orphan pieces merged in the round before (a piece whose neighbours are all orphans,
  !! as near an acute vertex, reaches a particle through them). A piece with no such
  !! neighbour (none is known for a simple polygon) goes to the particle nearest its lattice
  !! point. The merged cell is a union of clipped lattice cells, each a polygon: SCNI and
  !! Gauss integration (rkpm_tl_m) integrate over each piece and add, so the lines the
  !! pieces share cancel and each cell's boundary integral is over its true boundary.
  !! Boundary flags and the boundary polyline come from the particle's own clipped cell.
  subroutine make_polygon(b, v_in, dx, origin, err, share)
    type(body_t), intent(out) :: b
    real(wp), intent(in) :: v_in(:, :), dx(2), origin(2)
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: only rank me's share of the particles (as make_rectangle's), made from
    !! the recipe b%lat (polygon_walk: the runs of the rows' particles, perimeter-sized),
    !! with the whole boundary loop; for a polygon whose lattice merges no cell
    !! (polygon_merges false), the whole body never made
    integer, intent(in), optional :: share(2)
    real(wp), allocatable :: v(:, :), xs(:, :), vols(:), key(:), oarea(:)
    logical, allocatable :: bnd(:)
    integer, allocatable :: order(:), bl(:), own(:, :), oij(:, :), oown(:), onew(:)
    real(wp) :: lo(2), hi(2), p(2), sd, tol, w(2, 64), cell, area, reach, a, dmin
    integer :: nv, i, j, i0, i1, j0, j1, np, cap, nw, k, nb, no, q, nleft
    logical :: merges
    nv = size(v_in, 2)
    if (nv < 3 .or. any(dx <= 0.0_wp)) then
      call set_error(err, 'polygon needs at least 3 vertices and a positive spacing')
      return
    end if
    area = polygon_area(v_in, nv)
    if (abs(area) <= 0.0_wp) then
      call set_error(err, 'polygon has zero area (check the vertex list)')
      return
    end if
    allocate(v(2, nv))
    if (area > 0.0_wp) then
      v = v_in
    else
      v = v_in(:, nv:1:-1)
    end if
    b%ndim = 2
    b%geom%kind = geom_polygon
    b%geom%v = v
    lo = minval(v, dim=2)
    hi = maxval(v, dim=2)
    tol = geom_tol*minval(dx)
    ! the lattice's index range and size in 64 bits: a tiny spacing must not wrap around
    if (any((hi - lo)/dx > 0.25_wp*real(huge(1), wp))) then
      call set_error(err, 'polygon: the spacing is too small for the outline (more than '// &
        '5e8 lattice points per direction)')
      return
    end if
    i0 = floor((lo(1) - origin(1))/dx(1) - geom_tol)
    i1 = ceiling((hi(1) - origin(1))/dx(1) + geom_tol)
    j0 = floor((lo(2) - origin(2))/dx(2) - geom_tol)
    j1 = ceiling((hi(2) - origin(2))/dx(2) + geom_tol)
    if (int(i1 - i0 + 1, i64)*(j1 - j0 + 1) > int(huge(1), i64)) then
      call set_error(err, 'polygon: more than 2**31 - 1 lattice points; give a coarser spacing')
      return
    end if
    if (present(share)) then
      ! the recipe: the lattice, its rows' runs of particles, the loop (one walk)
      allocate(b%lat)
      b%lat%g = b%geom
      b%lat%origin = origin
      b%lat%dx = dx
      b%lat%i0 = i0
      b%lat%j0 = j0
      b%lat%n = [i1 - i0 + 1, j1 - j0 + 1]
      call polygon_walk(v, dx, origin, i0, i1, j0, j1, merges, b%lat, b)
      if (merges) then
        call set_error(err, 'polygon: its lattice merges cells along the outline, so a '// &
          'rank cannot make its share alone (an internal error: such a polygon is made '// &
          'whole, dynamic_setup_m body_per_part)', 1)
        return
      end if
      b%np = lattice_nodes(b%lat)
      b%spacing = 0.0_wp
      b%spacing(1:2) = dx
      call lattice_share(b, share)
      return
    end if
    cap = (i1 - i0 + 1)*(j1 - j0 + 1)
    allocate(xs(2, cap), vols(cap), bnd(cap), own(i0:i1, j0:j1), oij(2, cap), oarea(cap))
    cell = dx(1)*dx(2)
    ! a cell lies within half its diagonal of its point: points farther out meet nothing
    reach = 0.5_wp*norm2(dx)
    ! own(i, j): the particle whose cell holds lattice cell (i, j); -1 an orphan piece not
    ! yet merged; 0 a cell outside the polygon
    own = 0
    np = 0
    no = 0
    do j = j0, j1
      do i = i0, i1
        p = origin + [real(i, wp)*dx(1), real(j, wp)*dx(2)]
        sd = signed_distance(b%geom, p)
        if (sd > tol .and. sd >= reach) cycle
        call clip_polygon_box(v, p - 0.5_wp*dx, p + 0.5_wp*dx, w, nw)
        a = 0.0_wp
        if (nw >= 3) a = polygon_area(w, nw)
        if (sd > tol) then
          if (a > 0.0_wp) then
            no = no + 1
            oij(:, no) = [i, j]
            oarea(no) = a
            own(i, j) = -1
          end if
          cycle
        end if
        np = np + 1
        own(i, j) = np
        xs(:, np) = p
        vols(np) = a
        bnd(np) = abs(sd) <= tol .or. vols(np) < (1.0_wp - geom_tol)*cell
      end do
    end do
    ! merge the orphan pieces, in rounds: a round sees only the owners of the rounds before
    allocate(oown(no), onew(no))
    oown = 0
    nleft = no
    do while (nleft > 0)
      onew = 0
      do k = 1, no
        if (oown(k) == 0) onew(k) = neighbour_owner(v, dx, origin, i0, j0, own, oij(1, k), &
          oij(2, k))
      end do
      if (all(onew == 0)) exit
      do k = 1, no
        if (onew(k) == 0) cycle
        oown(k) = onew(k)
        own(oij(1, k), oij(2, k)) = onew(k)
        nleft = nleft - 1
      end do
    end do
    do k = 1, no
      if (oown(k) /= 0 .or. np == 0) cycle
      p = origin + real(oij(:, k), wp)*dx
      dmin = huge(1.0_wp)
      do q = 1, np
        if (norm2(xs(:, q) - p) < dmin) then
          dmin = norm2(xs(:, q) - p)
          oown(k) = q
        end if
      end do
    end do
    b%np = np
    b%x = xs(:, 1:np)
    b%vol = vols(1:np)
    b%boundary = bnd(1:np)
    ! the merged lattice cells by particle (CSR), and their areas added to the volumes
    allocate(b%merged_ptr(np + 1), b%merged_centre(2, count(oown > 0)))
    b%merged_ptr = 0
    do k = 1, no
      if (oown(k) > 0) b%merged_ptr(oown(k) + 1) = b%merged_ptr(oown(k) + 1) + 1
    end do
    b%merged_ptr(1) = 1
    do q = 1, np
      b%merged_ptr(q + 1) = b%merged_ptr(q + 1) + b%merged_ptr(q)
    end do
    allocate(bl(np))
    bl = b%merged_ptr(1:np)
    do k = 1, no
      q = oown(k)
      if (q == 0) cycle
      b%merged_centre(:, bl(q)) = origin + real(oij(:, k), wp)*dx
      bl(q) = bl(q) + 1
      b%vol(q) = b%vol(q) + oarea(k)
    end do
    deallocate(bl)
    b%spacing = 0.0_wp
    b%spacing(1:2) = dx
    ! One closed loop: boundary particles ordered by (nearest edge, position along it).
    nb = count(b%boundary)
    allocate(bl(nb), key(nb), order(nb))
    bl = pack([(k, k = 1, np)], b%boundary)
    do k = 1, nb
      key(k) = edge_key(v, b%x(:, bl(k)))
    end do
    call sort_index(key, order)
    b%nloops = 1
    b%loop_ptr = [1, nb + 1]
    b%loop_idx = bl(order)
    b%loop_closed = [.true.]
  end subroutine make_polygon

  !> Whether make_polygon merges a lattice cell into a particle's for the polygon v_in
  !! (spacing dx from origin): an orphan piece along the outline (then a rank cannot make
  !! its share alone, since a particle's cell depends on its neighbours'). Also true for
  !! what make_polygon refuses (it is then made whole, and says why). The lattice's walk
  !! alone (polygon_walk): the time of the whole lattice, no array.
  logical function polygon_merges(v_in, dx, origin) result(merges)
    real(wp), intent(in) :: v_in(:, :), dx(2), origin(2)
    real(wp), allocatable :: v(:, :)
    real(wp) :: area, lo(2), hi(2)
    integer :: nv
    merges = .true.
    nv = size(v_in, 2)
    if (nv < 3 .or. any(dx <= 0.0_wp)) return
    area = polygon_area(v_in, nv)
    if (abs(area) <= 0.0_wp) return
    if (area > 0.0_wp) then
      v = v_in
    else
      v = v_in(:, nv:1:-1)
    end if
    lo = minval(v, dim=2)
    hi = maxval(v, dim=2)
    if (any((hi - lo)/dx > 0.25_wp*real(huge(1), wp))) return
    ! (make_polygon's index range)
    call polygon_walk(v, dx, origin, floor((lo(1) - origin(1))/dx(1) - geom_tol), &
      ceiling((hi(1) - origin(1))/dx(1) + geom_tol), &
      floor((lo(2) - origin(2))/dx(2) - geom_tol), &
      ceiling((hi(2) - origin(2))/dx(2) + geom_tol), merges)
  end function polygon_merges

  !> make_polygon's walk of the lattice points origin + (i dx, j dy), i0 <= i <= i1,
  !! j0 <= j <= j1, over the counter-clockwise polygon v, by its tests in its order;
  !! merges: it finds a lattice cell that make_polygon would merge into a particle's (an
  !! orphan piece; the walk stops there). With lat and b, it keeps what a rank needs to
  !! make any particle without the whole body: the runs of each row's particles and each
  !! column's lowest particle (into lat: its n, i0, j0 and the rest set by the caller),
  !! and the boundary loop (into b: the boundary particles sorted by edge_key, as
  !! make_polygon sorts them, in the same order, so the same loop).
  subroutine polygon_walk(v, dx, origin, i0, i1, j0, j1, merges, lat, b)
    real(wp), intent(in) :: v(:, :), dx(2), origin(2)
    integer, intent(in) :: i0, i1, j0, j1
    logical, intent(out) :: merges
    type(lattice_t), intent(inout), optional :: lat
    type(body_t), intent(inout), optional :: b
    type(geometry_t) :: g
    integer, allocatable :: rj(:), ri(:, :), rq(:), bl(:), order(:)
    real(wp), allocatable :: key(:)
    real(wp) :: p(2), sd, tol, reach, a, w(2, 64), cell
    integer :: i, j, nw, np, nr, nb, last
    logical :: keep
    keep = present(lat) .and. present(b)
    g%kind = geom_polygon
    g%v = v
    tol = geom_tol*minval(dx)
    reach = 0.5_wp*norm2(dx)
    cell = dx(1)*dx(2)
    merges = .false.
    np = 0
    nr = 0
    nb = 0
    if (keep) then
      allocate(lat%run_ptr(j1 - j0 + 2), lat%col_low(i1 - i0 + 1))
      lat%col_low = j0 - 1
      allocate(rj(64), ri(2, 64), rq(64), bl(64), key(64))
    end if
    do j = j0, j1
      if (keep) lat%run_ptr(j - j0 + 1) = nr + 1
      last = i0 - 2
      do i = i0, i1
        p = origin + [real(i, wp)*dx(1), real(j, wp)*dx(2)]
        sd = signed_distance(g, p)
        if (sd > tol .and. sd >= reach) cycle
        call clip_polygon_box(v, p - 0.5_wp*dx, p + 0.5_wp*dx, w, nw)
        a = 0.0_wp
        if (nw >= 3) a = polygon_area(w, nw)
        if (sd > tol) then
          if (a > 0.0_wp) then
            merges = .true.
            return
          end if
          cycle
        end if
        np = np + 1
        if (.not. keep) cycle
        if (i /= last + 1) then
          ! (a new run: the arrays doubled when full)
          nr = nr + 1
          if (nr > size(rq)) then
            rj = [rj, rj]
            rq = [rq, rq]
            ri = reshape([ri, ri], [2, 2*size(ri, 2)])
          end if
          rj(nr) = j
          ri(:, nr) = i
          rq(nr) = np - 1
        end if
        ri(2, nr) = i
        last = i
        if (lat%col_low(i - i0 + 1) < j0) lat%col_low(i - i0 + 1) = j
        ! (make_polygon's boundary flag, its volume a: no cell merged)
        if (abs(sd) <= tol .or. a < (1.0_wp - geom_tol)*cell) then
          nb = nb + 1
          if (nb > size(bl)) then
            bl = [bl, bl]
            key = [key, key]
          end if
          bl(nb) = np
          key(nb) = edge_key(v, p)
        end if
      end do
    end do
    if (.not. keep) return
    lat%run_ptr(j1 - j0 + 2) = nr + 1
    lat%run_j = rj(1:nr)
    lat%run_i = ri(:, 1:nr)
    lat%run_q = rq(1:nr)
    lat%nq = np
    allocate(order(nb))
    call sort_index(key(1:nb), order)
    b%nloops = 1
    b%loop_ptr = [1, nb + 1]
    b%loop_idx = bl(order)
    b%loop_closed = [.true.]
  end subroutine polygon_walk

  !> make_polygon: the owner of the neighbour of orphan cell (ii, jj) of the lattice own
  !! (spacing dx from origin, the polygon v) that shares the longest stretch of lattice
  !! line with its piece, among the neighbours owned already; 0 if none. The
  !! piece is counter-clockwise, so its edges on its right side run up, on its top side
  !! left, and so on: the signed sums below cancel the zero-width bridges along the box
  !! that clipping a concave polygon leaves, and count only where the material meets.
  integer function neighbour_owner(v, dx, origin, i0, j0, own, ii, jj) result(best)
    real(wp), intent(in) :: v(:, :), dx(2), origin(2)
    integer, intent(in) :: i0, j0
    integer, intent(in) :: own(i0:, j0:)
    integer, intent(in) :: ii, jj
    integer :: i1, j1
    real(wp) :: pc(2), c(2), d(2), shared(4), etol(2), ww(2, 64)
    integer :: nww, m, side, nb_i(4), nb_j(4), mbest
    best = 0
    i1 = ubound(own, 1)
    j1 = ubound(own, 2)
    pc = origin + [real(ii, wp)*dx(1), real(jj, wp)*dx(2)]
    call clip_polygon_box(v, pc - 0.5_wp*dx, pc + 0.5_wp*dx, ww, nww)
    etol = geom_tol*dx
    shared = 0.0_wp
    do m = 1, nww
      c = ww(:, m)
      d = ww(:, modulo(m, nww) + 1) - c
      ! 1 left (x = lo), 2 right (x = hi), 3 below (y = lo), 4 above (y = hi)
      if (abs(c(1) - (pc(1) - 0.5_wp*dx(1))) <= etol(1) .and. abs(d(1)) <= etol(1)) &
        shared(1) = shared(1) - d(2)
      if (abs(c(1) - (pc(1) + 0.5_wp*dx(1))) <= etol(1) .and. abs(d(1)) <= etol(1)) &
        shared(2) = shared(2) + d(2)
      if (abs(c(2) - (pc(2) - 0.5_wp*dx(2))) <= etol(2) .and. abs(d(2)) <= etol(2)) &
        shared(3) = shared(3) + d(1)
      if (abs(c(2) - (pc(2) + 0.5_wp*dx(2))) <= etol(2) .and. abs(d(2)) <= etol(2)) &
        shared(4) = shared(4) - d(1)
    end do
    nb_i = [ii - 1, ii + 1, ii, ii]
    nb_j = [jj, jj, jj - 1, jj + 1]
    ! a stretch must be longer than the "on the line" tolerance to count
    shared(1:2) = shared(1:2) - etol(2)
    shared(3:4) = shared(3:4) - etol(1)
    do side = 1, 4
      if (shared(side) <= 0.0_wp) cycle
      if (nb_i(side) < i0 .or. nb_i(side) > i1 .or. nb_j(side) < j0 .or. nb_j(side) > j1) &
        cycle
      if (own(nb_i(side), nb_j(side)) <= 0) cycle
      if (best > 0) then
        if (shared(side) <= shared(mbest)) cycle
      end if
      best = own(nb_i(side), nb_j(side))
      mbest = side
    end do
  end function neighbour_owner

  !> Position along the polygon boundary: edge index - 1 + fraction along the edge.
  pure real(wp) function edge_key(v, p) result(key)
    real(wp), intent(in) :: v(:, :), p(2)
    integer :: i, j, nv
    real(wp) :: d, dmin, e(2), t
    nv = size(v, 2)
    dmin = huge(1.0_wp)
    key = 0.0_wp
    do i = 1, nv
      j = merge(1, i + 1, i == nv)
      d = segment_distance(v(:, i), v(:, j), p)
      e = v(:, j) - v(:, i)
      t = max(0.0_wp, min(1.0_wp, dot_product(p - v(:, i), e)/dot_product(e, e)))
      ! prefer the edge where p sits nearer the start (a vertex belongs to the next edge)
      if (d < dmin - geom_tol*norm2(e) .or. (abs(d - dmin) <= geom_tol*norm2(e) &
        .and. t < 0.5_wp)) then
        dmin = d
        key = real(i - 1, wp) + t
      end if
    end do
    if (key >= real(nv, wp) - geom_tol) key = 0.0_wp
  end function edge_key

  !> Polar lattice: nr radii on [r0, r1], nt angles on [t0, t1] (radians) about center.
  !! A full ring (t1 - t0 = 2 pi) does not repeat the seam.
  subroutine make_annulus(b, center, r0, r1, t0, t1, nr, nt, err, share)
    type(body_t), intent(out) :: b
    real(wp), intent(in) :: center(2), r0, r1, t0, t1
    integer, intent(in) :: nr, nt
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: the nodes of the CST4 annulus on this lattice (cst4_m cst4_annulus:
    !! the corners, then the boxes' centres, their lumped areas), rank me's share of them
    !! only, made from the recipe b%lat (polar), with the whole boundary loops
    integer, intent(in), optional :: share(2)
    real(wp) :: dr, dt, r, t, ra, rb, ta, tb
    logical :: full
    integer :: i, j, k, np, nb
    if (nr < 2 .or. nt < 2 .or. r1 <= r0 .or. r0 < 0.0_wp .or. t1 <= t0 &
      .or. t1 - t0 > 2.0_wp*pi + full_turn_tol) then
      call set_error(err, 'annulus sector needs n >= 2, 0 <= r_inner < r_outer and '// &
        '0 < theta_end - theta_start <= 360 degrees')
      return
    end if
    if (int(nr, i64)*nt > int(huge(1), i64)) then
      call set_error(err, 'annulus sector: n_radial x n_angular is more than 2**31 - 1 '// &
        'particles; give fewer')
      return
    end if
    full = t1 - t0 >= 2.0_wp*pi - full_turn_tol
    dr = (r1 - r0)/real(nr - 1, wp)
    if (full) then
      dt = (t1 - t0)/real(nt, wp)
    else
      dt = (t1 - t0)/real(nt - 1, wp)
    end if
    if (present(share)) then
      ! the recipe (a rank makes its share and region from it: lattice_node)
      allocate(b%lat)
      b%lat%polar = .true.
      b%lat%cst4 = .true.
      b%lat%full = full
      b%lat%n = [nr, nt]
      b%lat%center = center
      b%lat%r0 = r0
      b%lat%dr = dr
      b%lat%t0 = t0
      b%lat%dt = dt
      b%ndim = 2
      b%np = lattice_nodes(b%lat)
      b%spacing = 0.0_wp
      b%spacing(1:2) = max(dr, 0.5_wp*(r0 + r1)*dt)
      b%geom%kind = geom_annulus
      b%geom%center = center
      b%geom%r0 = r0
      b%geom%r1 = r1
      b%geom%t0 = t0
      b%geom%t1 = t1
      b%lat%g = b%geom
      call lattice_share(b, share)
      call polar_loops(b%lat, b)
      return
    end if
    np = nr*nt
    b%ndim = 2
    b%np = np
    allocate(b%x(2, np), b%vol(np), b%boundary(np))
    k = 0
    do j = 1, nt
      t = t0 + real(j - 1, wp)*dt
      ta = t - 0.5_wp*dt
      tb = t + 0.5_wp*dt
      if (.not. full) then
        ta = max(ta, t0)
        tb = min(tb, t1)
      end if
      do i = 1, nr
        r = r0 + real(i - 1, wp)*dr
        ra = max(r - 0.5_wp*dr, r0)
        rb = min(r + 0.5_wp*dr, r1)
        k = k + 1
        b%x(:, k) = center + r*[cos(t), sin(t)]
        b%vol(k) = 0.5_wp*(rb*rb - ra*ra)*(tb - ta)
        b%boundary(k) = i == 1 .or. i == nr .or. ((j == 1 .or. j == nt) .and. .not. full)
      end do
    end do
    b%spacing = 0.0_wp
    b%spacing(1:2) = max(dr, 0.5_wp*(r0 + r1)*dt)
    b%geom%kind = geom_annulus
    b%geom%center = center
    b%geom%r0 = r0
    b%geom%r1 = r1
    b%geom%t0 = t0
    b%geom%t1 = t1
    if (full) then
      ! two closed rings: outer counter-clockwise, inner clockwise (material on the left)
      b%nloops = 2
      b%loop_ptr = [1, nt + 1, 2*nt + 1]
      b%loop_idx = [([(idx(nr, j), j = 1, nt)]), ([(idx(1, j), j = nt, 1, -1)])]
      b%loop_closed = [.true., .true.]
    else
      nb = 2*(nr - 1) + 2*(nt - 1)
      b%nloops = 1
      b%loop_ptr = [1, nb + 1]
      b%loop_idx = [[(idx(i, 1), i = 1, nr - 1)], [(idx(nr, j), j = 1, nt - 1)], &
        [(idx(i, nt), i = nr, 2, -1)], [(idx(1, j), j = nt, 2, -1)]]
      b%loop_closed = [.true.]
    end if
  contains
    pure integer function idx(ir, jt)
      integer, intent(in) :: ir, jt
      idx = ir + (jt - 1)*nr
    end function idx
  end subroutine make_annulus

  !> Particles of ring k (k >= 1) of a disk: the nearest whole number to its circumference
  !! over the spacing, 2 pi k, so that neighbours on a ring are about one spacing apart.
  pure integer function disk_ring_count(k) result(n)
    integer, intent(in) :: k
    n = max(6, nint(2.0_wp*pi*real(k, wp)))
  end function disk_ring_count

  !> A solid disk of the given radius about center: a particle at the centre and nr =
  !! max(2, nint(radius/dx)) concentric rings at radii k h (h = radius/nr), ring k holding
  !! disk_ring_count(k) particles evenly spaced (odd rings turned by half a step, so that
  !! neighbouring rings do not line up), the last ring on the circle itself: the surface is
  !! smooth (its polyline is inscribed in the circle, its particles on it), unlike a lattice
  !! polygon's staircase.
  !!
  !! Integration cells, explicit (cell_ptr, cell_xy): ring k's particle j owns the annular
  !! sector between the circles of radii (k - 1/2) h and (k + 1/2) h (R for the last ring)
  !! and the angles half a step either side of it; the centre particle the disk of radius h/2.
  !! Each circle is drawn as one polygon through every break point of the rings on either
  !! side of it (and through the last ring's particles on the outer circle), and every cell
  !! takes its arcs from that polygon, vertex for vertex, so the cells tile the body with
  !! shared edges (what SCNI's divergence consistency needs) and their areas are the
  !! volumes. The same construction gives a sphere (shells of cells) and a cylinder (a disk
  !! in layers) in 3D.
  !!
  !! sector (rad, optional): a half (pi) or a quarter (pi/2) of the disk from angle 0, for
  !! symmetry planes along its straight sides: the rings hold a multiple of 4 (2) particles
  !! and are not turned, so every ring has particles on both sides; the disk's cells are
  !! clipped at the sides (the particles on them keep half cells) and the particles beyond
  !! dropped (disk_sector). The straight sides are boundary.
  subroutine make_disk(b, center, radius, dx, err, sector)
    type(body_t), intent(out) :: b
    real(wp), intent(in) :: center(2), radius, dx
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: sector
    !> two break angles closer than this (rad) are one vertex: far below any spacing of
    !! angles (2 pi / n_k, n_k < 1e9), far above the rounding of 2 pi (j + c)/n
    real(wp), parameter :: angle_tol = 1.0e-12_wp
    integer :: nr, k, j, np, c, nv, i0, i1, m, p, nvmax, nw, nxy
    integer(i64) :: ntot
    real(wp) :: h, rc, a
    integer, allocatable :: nk(:), first(:), cptr(:), idx_in(:, :), idx_out(:, :)
    real(wp), allocatable :: ang(:), ca(:, :), work(:), poly(:, :)
    integer, allocatable :: cnt(:)
    integer :: mult
    real(wp) :: turn
    if (.not. (radius > 0.0_wp .and. dx > 0.0_wp)) then
      call set_error(err, 'a disk needs radius > 0 and spacing > 0')
      return
    end if
    ! a sector: ring counts a multiple of mult, rings not turned (turn = 0)
    mult = 1
    turn = 0.5_wp
    if (present(sector)) then
      if (abs(sector - 0.5_wp*pi) < angle_tol) then
        mult = 4
      else if (abs(sector - pi) < angle_tol) then
        mult = 2
      else if (.not. abs(sector - 2.0_wp*pi) < angle_tol) then
        call set_error(err, 'a disk sector spans a quarter, a half or the whole turn')
        return
      end if
      if (mult > 1) turn = 0.0_wp
    end if
    if (radius/dx > 2.0e4_wp) then
      call set_error(err, 'a disk of radius '//rtoa(radius)//' m at spacing '// &
        rtoa(dx)//' m would have more than about 1.3e9 particles; give a coarser spacing')
      return
    end if
    nr = max(2, nint(radius/dx))
    h = radius/real(nr, wp)
    allocate(nk(0:nr), first(0:nr))
    nk(0) = 1
    first(0) = 1
    do k = 1, nr
      nk(k) = disk_ring_count(k)
      if (mult > 1) nk(k) = mult*max(8/mult, nint(real(nk(k), wp)/real(mult, wp)))
      first(k) = first(k - 1) + nk(k - 1)
    end do
    ntot = sum(int(nk, i64))
    np = int(ntot)
    b%ndim = 2
    b%np = np
    allocate(b%x(2, np), b%vol(np), b%boundary(np))
    b%x(:, 1) = center
    do k = 1, nr
      do j = 1, nk(k)
        a = ring_angle(k, j, 0.0_wp)
        b%x(:, first(k) + j - 1) = center + real(k, wp)*h*[cos(a), sin(a)]
      end do
    end do
    b%boundary = .false.
    b%boundary(first(nr):np) = .true.
    ! circle c (1 .. nr) is the inner side of ring c, at (c - 1/2) h; circle nr + 1 is R.
    ! cptr(c) .. cptr(c+1)-1 index its vertices (angles ang, ascending in [0, 2 pi)); the
    ! break angles of ring k are idx_in(:, k) on circle k and idx_out(:, k) on circle k+1
    allocate(cnt(nr + 1), cptr(nr + 2), idx_in(maxval(nk), nr), idx_out(maxval(nk), nr))
    ! (at most the break angles of the two rings beside each circle, and the last ring's
    ! particles)
    allocate(ang(2*np + nk(nr)), ca(2, 2*np + nk(nr)), work(2*maxval(nk)))
    cptr(1) = 1
    do c = 1, nr + 1
      ! this circle's break angles: ring c - 1's outer side, ring c's inner side, and on the
      ! outer circle ring nr's particles (relative to the centre)
      nw = 0
      if (c >= 2) call add_angles(c - 1, -0.5_wp)
      if (c <= nr) call add_angles(c, -0.5_wp)
      if (c == nr + 1) call add_angles(nr, 0.0_wp)
      call sort_unique(work(1:nw), angle_tol, m)
      rc = (real(c, wp) - 0.5_wp)*h
      if (c == nr + 1) rc = radius
      do j = 1, m
        ang(cptr(c) + j - 1) = work(j)
        ca(:, cptr(c) + j - 1) = rc*[cos(work(j)), sin(work(j))]
      end do
      cptr(c + 1) = cptr(c) + m
      cnt(c) = m
    end do
    do k = 1, nr
      do j = 1, nk(k)
        idx_in(j, k) = find_angle(k, ring_angle(k, j, -0.5_wp))
        idx_out(j, k) = find_angle(k + 1, ring_angle(k, j, -0.5_wp))
      end do
    end do
    ! the cells, counter-clockwise (a circle's vertex is a corner of at most two cells on
    ! either side of it)
    nvmax = 2*maxval(cnt) + 4
    allocate(poly(2, nvmax), b%cell_ptr(np + 1), b%cell_xy(2, 4*(cptr(nr + 2) - 1)))
    nxy = 0
    b%cell_ptr(1) = 1
    ! the centre: circle 1 whole
    nv = cnt(1)
    poly(:, 1:nv) = ca(:, cptr(1):cptr(2) - 1)
    call add_cell(1)
    do k = 1, nr
      do j = 1, nk(k)
        nv = 0
        ! outer arc from this cell's first break angle to the next (ascending, cyclic),
        ! then the inner arc back (descending): counter-clockwise
        i0 = idx_out(j, k)
        i1 = idx_out(merge(1, j + 1, j == nk(k)), k)
        p = i0
        do
          nv = nv + 1
          poly(:, nv) = ca(:, cptr(k + 1) + p - 1)
          if (p == i1) exit
          p = merge(1, p + 1, p == cnt(k + 1))
        end do
        i0 = idx_in(merge(1, j + 1, j == nk(k)), k)
        i1 = idx_in(j, k)
        p = i0
        do
          nv = nv + 1
          poly(:, nv) = ca(:, cptr(k) + p - 1)
          if (p == i1) exit
          p = merge(cnt(k), p - 1, p == 1)
        end do
        call add_cell(first(k) + j - 1)
      end do
    end do
    b%cell_xy = b%cell_xy(:, 1:nxy)
    if (maxval(b%cell_ptr(2:) - b%cell_ptr(:np)) > max_cell_vertices) then
      call set_error(err, 'a disk cell has more than '//itoa(max_cell_vertices)//' vertices')
      return
    end if
    b%spacing = 0.0_wp
    b%spacing(1:2) = h
    b%geom%kind = geom_annulus
    b%geom%center = center
    b%geom%r0 = 0.0_wp
    b%geom%r1 = radius
    b%geom%t0 = 0.0_wp
    b%geom%t1 = 2.0_wp*pi
    b%nloops = 1
    b%loop_ptr = [1, nk(nr) + 1]
    b%loop_idx = [(first(nr) + j - 1, j = 1, nk(nr))]
    b%loop_closed = [.true.]
    if (mult > 1) call disk_sector(b, 2.0_wp*pi/real(mult, wp), nr, err)
  contains
    !> The angle of ring k's particle j shifted by off steps, in [0, 2 pi).
    pure real(wp) function ring_angle(kk, jj, off) result(t)
      integer, intent(in) :: kk, jj
      real(wp), intent(in) :: off
      t = modulo(2.0_wp*pi*(real(jj - 1, wp) + turn*real(mod(kk, 2), wp) + off)/ &
        real(nk(kk), wp), 2.0_wp*pi)
    end function ring_angle

    !> The vertex of circle cc at angle t (within angle_tol, cyclic).
    integer function find_angle(cc, t) result(i)
      integer, intent(in) :: cc
      real(wp), intent(in) :: t
      real(wp) :: d, best
      integer :: q
      best = huge(1.0_wp)
      i = 1
      do q = 1, cnt(cc)
        d = abs(ang(cptr(cc) + q - 1) - t)
        d = min(d, 2.0_wp*pi - d)
        if (d < best) then
          best = d
          i = q
        end if
      end do
    end function find_angle

    !> Ring kk's break angles (off = -1/2) or particle angles (off = 0) onto work.
    subroutine add_angles(kk, off)
      integer, intent(in) :: kk
      real(wp), intent(in) :: off
      integer :: q
      do q = 1, nk(kk)
        nw = nw + 1
        work(nw) = ring_angle(kk, q, off)
      end do
    end subroutine add_angles

    !> Cell i is poly(:, 1:nv) (relative to the centre): its area, its vertices placed.
    subroutine add_cell(i)
      integer, intent(in) :: i
      integer :: q
      b%vol(i) = polygon_area(poly, nv)
      do q = 1, nv
        b%cell_xy(:, nxy + q) = center + poly(:, q)
      end do
      nxy = nxy + nv
      b%cell_ptr(i + 1) = b%cell_ptr(i) + nv
    end subroutine add_cell
  end subroutine make_disk

  !> The sector of angles [0, span] (pi/2 or pi) of the disk b (make_disk, rings not turned,
  !! so that each has particles at both angles): each cell clipped by the half-planes of the
  !! sector's straight sides (a convex region: the clipped cells tile the sector), the
  !! particles outside the sector dropped (the order kept: the centre, then each ring by
  !! angle from 0), their volumes the clipped areas; the particles on the sides are boundary;
  !! the boundary loop runs along the arc from angle 0 to span, in along the side at span to
  !! the centre, and out along the side at 0.
  subroutine disk_sector(b, span, nr, err)
    type(body_t), intent(inout) :: b
    real(wp), intent(in) :: span
    integer, intent(in) :: nr
    type(error_t), allocatable, intent(inout) :: err
    real(wp), parameter :: big = huge(1.0_wp)/4.0_wp
    real(wp) :: lo(2), hi(2), q(2), t, tol, cv(2, max_cell_vertices)
    real(wp), allocatable :: x(:, :), vol(:), cxy(:, :)
    integer, allocatable :: keep(:), cptr(:), loop(:)
    logical, allocatable :: bnd(:)
    integer :: i, n, nc, ncv, nv, m
    real(wp) :: h, r
    tol = 1.0e-9_wp*b%geom%r1
    h = b%geom%r1/real(nr, wp)
    lo = [b%geom%center(1), b%geom%center(2)]
    hi = lo + big
    if (span > 0.75_wp*pi) lo(1) = -big
    allocate(keep(b%np))
    n = 0
    do i = 1, b%np
      q = b%x(1:2, i) - b%geom%center
      t = atan2(q(2), q(1))
      if (abs(q(2)) <= tol) then
        t = merge(0.0_wp, pi, q(1) > 0.0_wp)
      else if (t < 0.0_wp) then
        t = t + 2.0_wp*pi
      end if
      if (norm2(q) <= tol .or. t <= span + 1.0e-9_wp) then
        n = n + 1
        keep(n) = i
      end if
    end do
    allocate(x(2, n), vol(n), bnd(n), cptr(n + 1), cxy(2, size(b%cell_xy, 2)))
    nc = 0
    cptr(1) = 1
    do m = 1, n
      i = keep(m)
      x(:, m) = b%x(1:2, i)
      nv = b%cell_ptr(i + 1) - b%cell_ptr(i)
      call clip_polygon_box(b%cell_xy(:, b%cell_ptr(i):b%cell_ptr(i + 1) - 1), lo, hi, cv, ncv)
      if (ncv < 3 .or. ncv > max_cell_vertices) then
        call set_error(err, 'a disk sector''s cell of particle '//itoa(m)//' is empty '// &
          'after the clip or has too many vertices')
        return
      end if
      cxy(:, nc + 1:nc + ncv) = cv(:, 1:ncv)
      nc = nc + ncv
      cptr(m + 1) = cptr(m) + ncv
      vol(m) = polygon_area(cv, ncv)
      q = x(:, m) - b%geom%center
      r = norm2(q)
      bnd(m) = b%boundary(i) .or. abs(q(2)) <= tol .or. &
        (span < 0.75_wp*pi .and. abs(q(1)) <= tol) .or. &
        (span > 0.75_wp*pi .and. abs(q(2)) <= tol)
    end do
    ! the loop: the arc (the last ring, by angle), the side at span inwards, the side at 0
    ! outwards (rings kk = nr - 1 .. 1 on the side, and the centre)
    allocate(loop(0))
    do m = 1, n
      r = norm2(x(:, m) - b%geom%center)
      if (abs(r - b%geom%r1) <= tol) loop = [loop, m]
    end do
    do i = nr - 1, 1, -1
      do m = 1, n
        q = x(:, m) - b%geom%center
        if (abs(norm2(q) - real(i, wp)*h) > tol) cycle
        if (abs(atan2(q(2), q(1)) - span) <= 1.0e-9_wp .or. (span > 0.75_wp*pi .and. &
          abs(q(2)) <= tol .and. q(1) < 0.0_wp)) loop = [loop, m]
      end do
    end do
    loop = [loop, 1]
    do i = 1, nr - 1
      do m = 1, n
        q = x(:, m) - b%geom%center
        if (abs(norm2(q) - real(i, wp)*h) > tol) cycle
        if (abs(q(2)) <= tol .and. q(1) > 0.0_wp) loop = [loop, m]
      end do
    end do
    b%np = n
    deallocate(b%x, b%vol, b%boundary)
    allocate(b%x(2, n))
    b%x = x
    call move_alloc(vol, b%vol)
    call move_alloc(bnd, b%boundary)
    call move_alloc(cptr, b%cell_ptr)
    b%cell_xy = cxy(:, 1:nc)
    b%geom%t0 = 0.0_wp
    b%geom%t1 = span
    b%loop_ptr = [1, size(loop) + 1]
    b%loop_idx = loop
  end subroutine disk_sector

  !> A 3D body from a 2D body b2 (a rectangle, a polygon or a disk) extruded along z: nz
  !! layers of its particles from z0 to z1 (spacing dz = (z1 - z0)/(nz - 1)), each with the
  !! volume of its 2D cell times its slab (dz, half at the two ends); a boundary particle is
  !! one on the 2D boundary or in an end layer. A box is an extruded rectangle, the 3D
  !! L-shaped or notched block an extruded polygon, a cylinder an extruded disk (its x-y
  !! cells, explicit polygons, kept for every layer). Layer by layer: particle (i, k) is
  !! i + (k - 1) np2. No boundary polylines (a 3D surface is facets).
  subroutine extrude_body(b2, z0, z1, nz, b, err, share)
    type(body_t), intent(in) :: b2
    real(wp), intent(in) :: z0, z1
    integer, intent(in) :: nz
    type(body_t), intent(out) :: b
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: only rank me's share of the particles (rank_comm_m share_first, as
    !! body_keep_share cuts it: b%held_share, b%row0)
    integer, intent(in), optional :: share(2)
    integer :: k, n2, i, q, n, q0, q1
    real(wp) :: dz, slab
    if (nz < 2 .or. .not. (z1 > z0)) then
      call set_error(err, 'an extruded body needs at least 2 layers and z1 > z0')
      return
    end if
    if (b2%geom%kind /= geom_polygon .and. .not. (b2%geom%kind == geom_annulus .and. &
      b2%geom%r0 == 0.0_wp .and. allocated(b2%cell_ptr))) then
      call set_error(err, 'only a rectangle, a polygon or a disk is extruded')
      return
    end if
    n2 = b2%np
    if (int(n2, i64)*nz > int(huge(1), i64)) then
      call set_error(err, 'the extruded body would have more than 2**31 - 1 particles')
      return
    end if
    dz = (z1 - z0)/real(nz - 1, wp)
    b%ndim = 3
    b%np = n2*nz
    q0 = 1
    q1 = b%np
    if (present(share)) then
      q0 = share_first(b%np, share(1), share(2))
      q1 = share_first(b%np, share(1) + 1, share(2)) - 1
      b%held_share = .true.
      b%row0 = q0
    end if
    ! (particle q at q - q0 + 1: a share's arrays from 1, as body_keep_share leaves them)
    allocate(b%x(3, q1 - q0 + 1), b%vol(q1 - q0 + 1), b%boundary(q1 - q0 + 1))
    do k = (q0 - 1)/n2 + 1, (q1 - 1)/n2 + 1
      slab = dz
      if (k == 1 .or. k == nz) slab = 0.5_wp*dz
      do i = 1, n2
        q = i + (k - 1)*n2
        if (q < q0 .or. q > q1) cycle
        q = q - q0 + 1
        b%x(1:2, q) = b2%x(1:2, i)
        b%x(3, q) = z0 + real(k - 1, wp)*dz
        if (k == nz) b%x(3, q) = z1
        b%vol(q) = b2%vol(i)*slab
        b%boundary(q) = b2%boundary(i) .or. k == 1 .or. k == nz
      end do
    end do
    b%spacing = 0.0_wp
    b%spacing(1:2) = b2%spacing(1:2)
    b%spacing(3) = dz
    b%nloops = 0
    allocate(b%loop_ptr(1), b%loop_idx(0), b%loop_closed(0))
    b%loop_ptr = 1
    if (b2%geom%kind == geom_polygon) then
      b%geom%kind = geom_prism
      b%geom%v = b2%geom%v
    else
      b%geom%kind = geom_cylinder
      b%geom%center = b2%geom%center
      b%geom%r1 = b2%geom%r1
      b%geom%t0 = b2%geom%t0
      b%geom%t1 = b2%geom%t1
    end if
    b%geom%z0 = z0
    b%geom%z1 = z1
    ! the recipe, for a rank that makes only its region's particles (extrude_pick)
    allocate(b%ext)
    b%ext%n2 = n2
    b%ext%nz = nz
    b%ext%x2 = b2%x(1:2, :)
    b%ext%vol2 = b2%vol
    b%ext%bnd2 = b2%boundary
    b%ext%z0 = z0
    b%ext%z1 = z1
    b%ext%dz = dz
    call extruded_facets(b2, nz, b, share)
    if (allocated(b2%cell_ptr)) then
      ! the x-y cells, the same polygon for each layer of a particle: held once, particle
      ! i + (k - 1) n2 takes cell i (body_cell; a copy a layer was some 90 B a particle)
      n = b2%cell_ptr(n2 + 1) - 1
      b%cell_ptr = b2%cell_ptr(1:n2 + 1)
      b%cell_xy = b2%cell_xy(:, 1:n)
      b%cell_period = n2
    end if
  end subroutine extrude_body

  !> Particle q = i + (k - 1) n2 of the extruded body of recipe e (extrude_body's position,
  !! volume and boundary flag, then moved by e%shift as build_body's placement does): the
  !! same operations in the same order, so the same bits. as_made: the position as
  !! extrude_body made it, before the placement (what its tetrahedra were ordered by).
  pure subroutine extruded_particle(e, i, k, x, vol, bnd, as_made)
    type(extrusion_t), intent(in) :: e
    integer, intent(in) :: i, k
    real(wp), intent(out) :: x(3), vol
    logical, intent(out) :: bnd
    logical, intent(in), optional :: as_made
    real(wp) :: slab
    logical :: moved
    moved = e%shifted
    if (present(as_made)) moved = moved .and. .not. as_made
    slab = e%dz
    if (k == 1 .or. k == e%nz) slab = 0.5_wp*e%dz
    x(1:2) = e%x2(1:2, i)
    x(3) = e%z0 + real(k - 1, wp)*e%dz
    if (k == e%nz) x(3) = e%z1
    if (moved) x = x + e%shift
    vol = e%vol2(i)*slab
    bnd = e%bnd2(i) .or. k == 1 .or. k == e%nz
  end subroutine extruded_particle

  !> Some particles of extruded body b (its recipe b%ext, extrude_body's: the whole body is
  !! never made): those numbered g0 ... g1 whose reference position, or one of its mirror
  !! images across the planes (nplanes of them: coordinate normal(m) = pos(m); and across
  !! both), lies within [lo, hi]; ends: of the first and last layers only. As body r, in
  !! ascending numbers (r%glob, of r%np_whole = b%np): positions, volumes, boundary flags
  !! and supports (b%ext%rho) the whole body's bits; b's description copied (name, kernel,
  !! spacing, supports' factors, geometry, the section's cells, the recipe, b's facets:
  !! the whole surface's over the whole body's numbers, or a rank's rows of it); no
  !! boundary loops.
  !! b may itself be such a body.
  subroutine extrude_pick(b, g0, g1, lo, hi, nplanes, normal, pos, r, ends)
    type(body_t), intent(in) :: b
    integer, intent(in) :: g0, g1, nplanes, normal(:)
    real(wp), intent(in) :: lo(3), hi(3), pos(:)
    type(body_t), intent(out) :: r
    logical, intent(in), optional :: ends
    integer :: n, pass, k, i, q
    real(wp) :: x(3), vol
    logical :: bnd, only_ends
    only_ends = .false.
    if (present(ends)) only_ends = ends
    call copy_description(b, r)
    r%ndim = 3
    if (allocated(b%cell_ptr)) then
      r%cell_ptr = b%cell_ptr
      r%cell_xy = b%cell_xy
      r%cell_period = b%cell_period
    end if
    r%ext = b%ext
    if (allocated(b%facets)) r%facets = b%facets
    r%facet0 = b%facet0
    r%nfacets = b%nfacets
    r%np_whole = b%ext%n2*b%ext%nz
    associate (e => b%ext)
      do pass = 1, 2
        n = 0
        do k = 1, e%nz
          if (only_ends .and. k > 1 .and. k < e%nz) cycle
          ! (a layer's z is every one of its particles' and their images': the planes are
          ! along z; so a region walks its layers' sections only)
          call extruded_particle(e, 1, k, x, vol, bnd)
          if ((x(3) < lo(3) .or. x(3) > hi(3)) .and. all(normal(1:nplanes) /= 3)) cycle
          if ((k - 1)*int(e%n2, i64) + 1 > g1 .or. k*int(e%n2, i64) < g0) cycle
          do i = 1, e%n2
            q = i + (k - 1)*e%n2
            if (q < g0 .or. q > g1) cycle
            call extruded_particle(e, i, k, x, vol, bnd)
            if (.not. near_images(x, lo, hi, nplanes, normal, pos)) cycle
            n = n + 1
            if (pass == 1) cycle
            r%x(:, n) = x
            r%vol(n) = vol
            r%boundary(n) = bnd
            r%rho(:, n) = e%rho
            r%glob(n) = q
          end do
        end do
        if (pass == 1) allocate(r%x(3, n), r%vol(n), r%boundary(n), r%rho(3, n), r%glob(n))
      end do
    end associate
    r%np = n

  end subroutine extrude_pick

  !> What a body made of some of b's particles (extrude_pick, lattice_pick) takes of b's
  !! description: name, shape, spacing, supports' factors and scale, kernel, window,
  !! basis, geometry; no boundary loops.
  subroutine copy_description(b, r)
    type(body_t), intent(in) :: b
    type(body_t), intent(inout) :: r
    r%name = b%name
    r%shape = b%shape
    r%spacing = b%spacing
    r%support_factor = b%support_factor
    r%h = b%h
    r%kid = b%kid
    r%wshape = b%wshape
    r%bid = b%bid
    r%geom = b%geom
    r%nloops = 0
    allocate(r%loop_ptr(1), r%loop_idx(0), r%loop_closed(0))
    r%loop_ptr = 1
  end subroutine copy_description

  !> Whether x or one of its mirror images across the planes (nplanes of them, 0-2:
  !! coordinate normal(m) = pos(m); and across both) lies within [lo, hi]: the regions of
  !! extrude_pick and lattice_pick, with their symmetry planes or axis.
  pure logical function near_images(x, lo, hi, nplanes, normal, pos) result(yes)
    real(wp), intent(in) :: x(:), lo(:), hi(:), pos(:)
    integer, intent(in) :: nplanes, normal(:)
    real(wp) :: y(size(x))
    integer :: m
    yes = all(x >= lo) .and. all(x <= hi)
    if (yes .or. nplanes == 0) return
    do m = 1, nplanes
      y = x
      y(normal(m)) = 2.0_wp*pos(m) - y(normal(m))
      if (all(y >= lo) .and. all(y <= hi)) yes = .true.
    end do
    if (nplanes == 2) then
      y = x
      y(normal(1:2)) = 2.0_wp*pos(1:2) - y(normal(1:2))
      if (all(y >= lo) .and. all(y <= hi)) yes = .true.
    end if
  end function near_images

  !> Whether any particle of extruded body b (its recipe, extrude_pick's) lies within [lo,
  !! hi] (1, else 0), without making them.
  integer function extrude_count(b, lo, hi) result(n)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: lo(3), hi(3)
    integer :: k, i
    real(wp) :: x(3), vol
    logical :: bnd
    n = 0
    do k = 1, b%ext%nz
      call extruded_particle(b%ext, 1, k, x, vol, bnd)
      if (x(3) < lo(3) .or. x(3) > hi(3)) cycle
      do i = 1, b%ext%n2
        call extruded_particle(b%ext, i, k, x, vol, bnd)
        if (all(x >= lo) .and. all(x <= hi)) then
          n = 1
          return
        end if
      end do
    end do
  end function extrude_count

  !> The closed boundary surface of b, b2 extruded in nz layers (extrude_body), as triangles
  !! over b's particles, counter-clockwise seen from outside: the section's triangulation
  !! (section_triangles) as the two end caps (turned over at the bottom) and each segment of
  !! the section's boundary loops times each layer as two side triangles (a CCW loop walks
  !! with the body on its left, so (a, b, c) of the quad a = (i0, k), b = (i1, k), c = (i1,
  !! k + 1), d = (i0, k + 1) faces out). Its recipe goes into b%ext (ctri, seg:
  !! extruded_facet makes any facet from it); with share ([me, nranks]) b holds rank me's
  !! share of the facets only (facet0 ... of nfacets, rank_comm_m share_first). Left
  !! unallocated when the section has no triangulation that closes it.
  subroutine extruded_facets(b2, nz, b, share)
    type(body_t), intent(in) :: b2
    integer, intent(in) :: nz
    type(body_t), intent(inout) :: b
    integer, intent(in), optional :: share(2)
    integer, allocatable :: tri(:, :)
    integer :: nside, l, q, j, f0, f1
    logical :: ok
    call section_triangles(b2, tri, ok)
    if (.not. ok) return
    nside = 0
    do l = 1, b2%nloops
      nside = nside + (b2%loop_ptr(l + 1) - b2%loop_ptr(l))
    end do
    allocate(b%ext%seg(2, nside))
    nside = 0
    do l = 1, b2%nloops
      do q = b2%loop_ptr(l), b2%loop_ptr(l + 1) - 1
        nside = nside + 1
        b%ext%seg(1, nside) = b2%loop_idx(q)
        b%ext%seg(2, nside) = b2%loop_idx(merge(b2%loop_ptr(l), q + 1, &
          q == b2%loop_ptr(l + 1) - 1))
      end do
    end do
    call move_alloc(tri, b%ext%ctri)
    b%nfacets = extruded_nfacets(b%ext)
    f0 = 1
    f1 = b%nfacets
    b%facet0 = 0
    if (present(share)) then
      f0 = share_first(b%nfacets, share(1), share(2))
      f1 = share_first(b%nfacets, share(1) + 1, share(2)) - 1
      b%facet0 = f0
    end if
    allocate(b%facets(3, f1 - f0 + 1))
    do j = f0, f1
      b%facets(:, j - f0 + 1) = extruded_facet(b%ext, j)
    end do
  end subroutine extruded_facets

  !> The number of facets of the closed surface of extruded body recipe e (extruded_facets:
  !! two a cap triangle, two a boundary segment and layer gap); 0 without one.
  pure integer function extruded_nfacets(e) result(nf)
    type(extrusion_t), intent(in) :: e
    nf = 0
    if (.not. allocated(e%ctri)) return
    nf = 2*size(e%ctri, 2) + 2*size(e%seg, 2)*(e%nz - 1)
  end function extruded_nfacets

  !> Facet j of the closed surface of extruded body recipe e, as extruded_facets numbers
  !! them: the caps' triangles in pairs (bottom turned over, then top), then each boundary
  !! segment's side triangles, two a layer gap, layer by layer. What a rank makes of the
  !! surface without the whole of it.
  pure function extruded_facet(e, j) result(t)
    type(extrusion_t), intent(in) :: e
    integer, intent(in) :: j
    integer :: t(3), nt, m, r, l, k, i0, i1
    nt = size(e%ctri, 2)
    if (j <= 2*nt) then
      m = (j + 1)/2
      if (mod(j, 2) == 1) then
        t = e%ctri([1, 3, 2], m)                  ! bottom, seen from below
      else
        t = e%ctri(:, m) + (e%nz - 1)*e%n2        ! top
      end if
      return
    end if
    r = j - 2*nt - 1
    l = r/(2*(e%nz - 1)) + 1
    r = r - 2*(e%nz - 1)*(l - 1)
    k = r/2 + 1
    i0 = e%seg(1, l)
    i1 = e%seg(2, l)
    if (mod(r, 2) == 0) then
      t = [i0, i1, i1 + e%n2] + (k - 1)*e%n2
    else
      t = [i0, i1 + e%n2, i0 + e%n2] + (k - 1)*e%n2
    end if
  end function extruded_facet

  !> A triangulation tri(3, nt) of a 2D body's section whose vertices are its particles,
  !! counter-clockwise, and whose outline is the body's boundary loops (ok), when the
  !! generator's layout gives one: a disk's centre fan and ring strips (consecutive rings
  !! merged by angle), a lattice polygon's squares of four particles cut along a diagonal
  !! (ok only if they cover the polygon: their areas sum to its area to round-off, as for a
  !! rectangle or a polygon with its vertices on lattice points).
  subroutine section_triangles(b2, tri, ok)
    type(body_t), intent(in) :: b2
    integer, allocatable, intent(out) :: tri(:, :)
    logical, intent(out) :: ok
    ok = .false.
    if (b2%geom%kind == geom_annulus .and. b2%geom%r0 == 0.0_wp .and. &
      allocated(b2%cell_ptr) .and. b2%geom%t1 - b2%geom%t0 > 1.5_wp*pi) then
      call disk_triangles(b2, tri)
      ok = .true.
    else if (b2%geom%kind == geom_annulus .and. b2%geom%r0 == 0.0_wp .and. &
      allocated(b2%cell_ptr)) then
      call sector_triangles(b2, tri)
      ok = abs(tri_area(b2%x, tri) - polygon_area(b2%x(1:2, b2%loop_idx), &
        size(b2%loop_idx))) <= 1.0e-9_wp*polygon_area(b2%x(1:2, b2%loop_idx), &
        size(b2%loop_idx))
    else if (b2%geom%kind == geom_polygon .and. .not. allocated(b2%cell_centre)) then
      call lattice_triangles(b2, tri)
      ok = abs(tri_area(b2%x, tri) - polygon_area(b2%geom%v, size(b2%geom%v, 2))) <= &
        1.0e-9_wp*polygon_area(b2%geom%v, size(b2%geom%v, 2))
    end if
    if (.not. ok .and. allocated(tri)) deallocate(tri)
  end subroutine section_triangles

  !> Sum of the signed areas of triangles tri over points x.
  pure real(wp) function tri_area(x, tri) result(a)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tri(:, :)
    integer :: m
    real(wp) :: e1(2), e2(2)
    a = 0.0_wp
    do m = 1, size(tri, 2)
      e1 = x(1:2, tri(2, m)) - x(1:2, tri(1, m))
      e2 = x(1:2, tri(3, m)) - x(1:2, tri(1, m))
      a = a + 0.5_wp*(e1(1)*e2(2) - e1(2)*e2(1))
    end do
  end function tri_area

  !> A lattice body's squares whose four corners are particles, each cut into two
  !! counter-clockwise triangles along the diagonal from its lower-left corner.
  subroutine lattice_triangles(b2, tri)
    type(body_t), intent(in) :: b2
    integer, allocatable, intent(out) :: tri(:, :)
    integer, allocatable :: at(:, :), ij(:, :)
    real(wp) :: lo(2)
    integer :: j, n(2), i, k, nt, c(4)
    lo = minval(b2%x(1:2, :), dim=2)
    allocate(ij(2, b2%np))
    do j = 1, b2%np
      ij(:, j) = nint((b2%x(1:2, j) - lo)/b2%spacing(1:2))
    end do
    n = maxval(ij, dim=2) + 1
    allocate(at(0:n(1), 0:n(2)))
    at = 0
    do j = 1, b2%np
      at(ij(1, j), ij(2, j)) = j
    end do
    allocate(tri(3, 2*b2%np))
    nt = 0
    do k = 0, n(2) - 2
      do i = 0, n(1) - 2
        c = [at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)]
        if (any(c == 0)) cycle
        tri(:, nt + 1) = [c(1), c(2), c(3)]
        tri(:, nt + 2) = [c(1), c(3), c(4)]
        nt = nt + 2
      end do
    end do
    tri = tri(:, 1:nt)
  end subroutine lattice_triangles

  !> A disk sector's triangulation (disk_sector's numbering: the centre, then each ring's
  !! particles by angle from 0 to the span, a ring the run of particles at one radius): the
  !! fan from the centre to ring 1, and between rings k and k + 1 the strip obtained by
  !! walking both rings by angle, as disk_triangles does without wrapping around.
  subroutine sector_triangles(b2, tri)
    type(body_t), intent(in) :: b2
    integer, allocatable, intent(out) :: tri(:, :)
    integer, allocatable :: first(:), nk(:)
    integer :: nr, k, np, nt, i, j, q
    real(wp) :: r, rprev, tol, ta, tb
    np = b2%np
    tol = 1.0e-9_wp*b2%geom%r1
    ! the rings: runs of particles at one radius after the centre
    allocate(first(np), nk(np))
    nr = 0
    rprev = -1.0_wp
    do q = 2, np
      r = norm2(b2%x(1:2, q) - b2%geom%center)
      if (abs(r - rprev) > tol) then
        nr = nr + 1
        first(nr) = q
        nk(nr) = 0
        rprev = r
      end if
      nk(nr) = nk(nr) + 1
    end do
    allocate(tri(3, 2*np))
    nt = 0
    do j = 1, nk(1) - 1
      nt = nt + 1
      tri(:, nt) = [1, first(1) + j - 1, first(1) + j]
    end do
    do k = 1, nr - 1
      i = 0
      j = 0
      do while (i < nk(k) - 1 .or. j < nk(k + 1) - 1)
        ta = huge(1.0_wp)
        tb = huge(1.0_wp)
        if (i < nk(k) - 1) ta = angle_of(first(k) + i + 1)
        if (j < nk(k + 1) - 1) tb = angle_of(first(k + 1) + j + 1)
        nt = nt + 1
        if (ta <= tb) then
          tri(:, nt) = [first(k) + i, first(k + 1) + j, first(k) + i + 1]
          i = i + 1
        else
          tri(:, nt) = [first(k) + i, first(k + 1) + j, first(k + 1) + j + 1]
          j = j + 1
        end if
      end do
    end do
    tri = tri(:, 1:nt)
  contains
    !> The angle of particle q about the centre in [0, 2 pi).
    real(wp) function angle_of(q) result(t)
      integer, intent(in) :: q
      real(wp) :: d(2)
      d = b2%x(1:2, q) - b2%geom%center
      t = atan2(d(2), d(1))
      if (abs(d(2)) <= tol) t = merge(0.0_wp, pi, d(1) > 0.0_wp)
      if (t < 0.0_wp) t = t + 2.0_wp*pi
    end function angle_of
  end subroutine sector_triangles

  !> A disk's triangulation (make_disk's numbering: the centre, then ring k's particles in
  !! increasing angle): the fan from the centre to ring 1, and between rings k and k + 1
  !! the strip obtained by walking both rings by angle, each step closing a triangle with
  !! the particle of the ring that comes next.
  subroutine disk_triangles(b2, tri)
    type(body_t), intent(in) :: b2
    integer, allocatable, intent(out) :: tri(:, :)
    integer, allocatable :: first(:), nk(:)
    integer :: nr, k, np, nt, i, j, a, bb, na, nb
    real(wp) :: ta, tb
    np = b2%np
    ! the rings from the particle count: 1 + sum_k disk_ring_count(k)
    nr = 0
    k = 1
    do while (k < np)
      nr = nr + 1
      k = k + disk_ring_count(nr)
    end do
    allocate(first(0:nr), nk(0:nr))
    first(0) = 1
    nk(0) = 1
    do k = 1, nr
      nk(k) = disk_ring_count(k)
      first(k) = first(k - 1) + nk(k - 1)
    end do
    allocate(tri(3, 2*np))
    nt = 0
    do j = 1, nk(1)
      tri(:, nt + 1) = [1, first(1) + j - 1, first(1) + modulo(j, nk(1))]
      nt = nt + 1
    end do
    do k = 1, nr - 1
      na = nk(k)
      nb = nk(k + 1)
      i = 0
      j = 0
      ! start both walks at the particles of smallest angle
      do while (i < na .or. j < nb)
        a = first(k) + modulo(i, na)
        bb = first(k + 1) + modulo(j, nb)
        ta = angle_of(first(k) + modulo(i + 1, na), i + 1 >= na)
        tb = angle_of(first(k + 1) + modulo(j + 1, nb), j + 1 >= nb)
        if (j >= nb .or. (i < na .and. ta <= tb)) then
          tri(:, nt + 1) = [a, first(k) + modulo(i + 1, na), bb]
          i = i + 1
        else
          tri(:, nt + 1) = [a, first(k + 1) + modulo(j + 1, nb), bb]
          j = j + 1
        end if
        ! counter-clockwise: (a, next, bb) as built is clockwise for the inner ring's step
        call ccw(tri(:, nt + 1))
        nt = nt + 1
      end do
    end do
    tri = tri(:, 1:nt)
  contains
    !> The angle of particle q about the disk's centre in [0, 2 pi), plus 2 pi past a wrap.
    real(wp) function angle_of(q, wrapped) result(t)
      integer, intent(in) :: q
      logical, intent(in) :: wrapped
      real(wp) :: d(2)
      d = b2%x(1:2, q) - b2%geom%center
      t = modulo(atan2(d(2), d(1)), 2.0_wp*pi)
      if (wrapped) t = t + 2.0_wp*pi
    end function angle_of

    subroutine ccw(t3)
      integer, intent(inout) :: t3(3)
      real(wp) :: e1(2), e2(2)
      e1 = b2%x(1:2, t3(2)) - b2%x(1:2, t3(1))
      e2 = b2%x(1:2, t3(3)) - b2%x(1:2, t3(1))
      if (e1(1)*e2(2) - e1(2)*e2(1) < 0.0_wp) t3(2:3) = t3([3, 2])
    end subroutine ccw
  end subroutine disk_triangles

  !> A lattice body's integration cells made explicit (cell_ptr, cell_xy): each particle's
  !! lattice cell (a box of the spacing about its lattice point) clipped by the body's
  !! polygon, the cell the SCNI and Gauss tables integrate over, so that the cells can turn
  !! with the body (&body rotate). ok is .false. (and nothing changes) when cells of lattice
  !! points outside a polygon were merged into particle cells (make_polygon): a particle's
  !! cell is then several pieces, which an explicit cell (one polygon) cannot hold.
  subroutine lattice_cells_explicit(b, ok)
    type(body_t), intent(inout) :: b
    logical, intent(out) :: ok
    real(wp) :: half(2), o(2), cv(2, max_cell_vertices)
    real(wp), allocatable :: xy(:, :)
    integer :: i, ncv, n
    ok = .false.
    if (b%geom%kind /= geom_polygon .or. allocated(b%cell_ptr)) return
    if (allocated(b%merged_ptr)) then
      if (b%merged_ptr(b%np + 1) > b%merged_ptr(1)) return
    end if
    half = 0.5_wp*b%spacing(1:2)
    allocate(b%cell_ptr(b%np + 1), xy(2, max_cell_vertices*b%np))
    b%cell_ptr(1) = 1
    n = 0
    do i = 1, b%np
      o = b%x(1:2, i)
      if (allocated(b%cell_centre)) o = b%cell_centre(1:2, i)
      call clip_polygon_box(b%geom%v, o - half, o + half, cv, ncv)
      xy(:, n + 1:n + ncv) = cv(:, 1:ncv)
      n = n + ncv
      b%cell_ptr(i + 1) = n + 1
    end do
    b%cell_xy = xy(:, 1:n)
    if (allocated(b%cell_centre)) deallocate(b%cell_centre)
    if (allocated(b%merged_ptr)) deallocate(b%merged_ptr)
    if (allocated(b%merged_centre)) deallocate(b%merged_centre)
    ok = .true.
  end subroutine lattice_cells_explicit

  !> Sort a ascending and drop values within tol of the previous one (cyclic over 2 pi at
  !! the end); the m distinct values are a(1:m).
  subroutine sort_unique(a, tol, m)
    real(wp), intent(inout) :: a(:)
    real(wp), intent(in) :: tol
    integer, intent(out) :: m
    integer, allocatable :: order(:)
    real(wp), allocatable :: s(:)
    integer :: i
    m = 0
    if (size(a) == 0) return
    allocate(order(size(a)))
    call sort_index(a, order)
    s = a(order)
    m = 1
    a(1) = s(1)
    do i = 2, size(s)
      if (s(i) - a(m) <= tol) cycle
      m = m + 1
      a(m) = s(i)
    end do
    if (m > 1 .and. a(1) + 2.0_wp*pi - a(m) <= tol) m = m - 1
  end subroutine sort_unique

  !> A body from arrays (particle file): x(ndim, np), vol(np), loop(np) (0 = interior,
  !! k > 0 = on boundary loop k) and order(np) (position along that loop).
  subroutine make_from_arrays(b, x, vol, loop, order, err)
    type(body_t), intent(out) :: b
    real(wp), intent(in) :: x(:, :), vol(:)
    integer, intent(in) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: np, nl, k, i, n, pos
    integer, allocatable :: members(:), srt(:)
    real(wp), allocatable :: key(:)
    np = size(x, 2)
    if (np < 1 .or. size(vol) /= np) then
      call set_error(err, 'particle file: no particles, or volume count differs from '// &
        'the number of positions')
      return
    end if
    if (any(vol <= 0.0_wp)) then
      call set_error(err, 'particle file: every particle volume must be positive')
      return
    end if
    b%ndim = size(x, 1)
    b%np = np
    b%x = x
    b%vol = vol
    b%boundary = loop > 0
    nl = 0
    if (np > 0) nl = maxval(loop)
    b%nloops = nl
    allocate(b%loop_ptr(nl + 1), b%loop_idx(count(loop > 0)), b%loop_closed(nl))
    b%loop_closed = .true.
    b%loop_ptr(1) = 1
    pos = 0
    do k = 1, nl
      members = pack([(i, i = 1, np)], loop == k)
      n = size(members)
      key = real(order(members), wp)
      if (allocated(srt)) deallocate(srt)
      allocate(srt(n))
      call sort_index(key, srt)
      b%loop_idx(pos + 1:pos + n) = members(srt)
      pos = pos + n
      b%loop_ptr(k + 1) = pos + 1
    end do
    b%spacing = 0.0_wp
    b%spacing(1:b%ndim) = mean_spacing(vol, b%ndim)
  end subroutine make_from_arrays

  !> A particle file's nominal spacing: the cube root (square root in 2D) of the mean
  !! volume (make_from_arrays; a plane mesh file read per part takes it from the rank that
  !! wrote the file, body_setup_m geo_mesh_file, the same expression: the same bits)
  pure real(wp) function mean_spacing(vol, ndim) result(h)
    real(wp), intent(in) :: vol(:)
    integer, intent(in) :: ndim
    h = (sum(vol)/real(size(vol), wp))**(1.0_wp/real(ndim, wp))
  end function mean_spacing

  !> Moves every interior particle of a lattice body (rectangle, polygon; b%boundary false)
  !! by a random offset, uniform in [-fraction, fraction) x the spacing in each direction
  !! (doc/stability.md). Boundary particles stay, so the surface polyline and the exact
  !! geometry stay valid. The volumes stay the lattice cells': for fraction < 1/2 each moved
  !! particle stays inside its own cell, the cells still tile the body and the volumes still
  !! sum to its area. b%cell_centre keeps the lattice points (and the merged cells of a
  !! polygon stay), so SCNI and Gauss integration use the same conforming cells as before
  !! the move. The offsets come from xorshift64
  !! (integer shifts and exclusive ors only) drawn in particle order, two per particle: one
  !! seed gives the same cloud with every compiler and on every machine.
  !! fraction: 0 <= fraction < max_perturbation; seed: any integer.
  subroutine perturb_interior(b, fraction, seed)
    type(body_t), intent(inout) :: b
    real(wp), intent(in) :: fraction
    integer, intent(in) :: seed
    integer(i64) :: state
    integer :: i, d, k
    real(wp) :: u
    if (allocated(b%cell_centre)) deallocate(b%cell_centre)
    allocate(b%cell_centre, source=b%x)
    if (fraction <= 0.0_wp) return
    state = ieor(xorshift_base, int(seed, i64))
    do k = 1, xorshift_warmup
      call xorshift64(state, u)
    end do
    do i = 1, b%np
      if (b%boundary(i)) cycle
      do d = 1, b%ndim
        call xorshift64(state, u)
        b%x(d, i) = b%x(d, i) + fraction*b%spacing(d)*(2.0_wp*u - 1.0_wp)
      end do
    end do
  end subroutine perturb_interior

  !> One step of Marsaglia's xorshift64 (shifts 13, 7, 17): the next state and u in [0, 1)
  !! from its top 53 bits. ishft is a logical shift on the bit pattern, so no arithmetic
  !! overflow is involved.
  pure subroutine xorshift64(state, u)
    integer(i64), intent(inout) :: state
    real(wp), intent(out) :: u
    state = ieor(state, ishft(state, 13))
    state = ieor(state, ishft(state, -7))
    state = ieor(state, ishft(state, 17))
    u = real(ishft(state, -11), wp)*2.0_wp**(-53)
  end subroutine xorshift64

  !> rho = factor x spacing per direction. For annuli the local spacing grows with radius,
  !! so each particle gets factor x max(dr, r dtheta); the basis scale h is the nominal rho.
  !> The supports of the particles (CST4 nodes) of annulus sector b as build_body gives
  !! them: factor x the local spacing max(dr, |x - center| dt) at each position as made
  !! (dr, dt the deck's radial and angular spacings); for a share made from b's polar
  !! recipe, the recipe's supports too (generators_m lattice_node) and the largest of them,
  !! at the outer circle's corners (the boxes' centres lie inside it).
  subroutine annulus_supports(b, center, dr, dt, factor)
    type(body_t), intent(inout) :: b
    real(wp), intent(in) :: center(2), dr, dt, factor(:)
    real(wp), allocatable :: local(:)
    real(wp) :: x(2), vol, rho(2)
    logical :: bnd
    integer :: i
    ! (a rank's share holds size(b%x, 2) of the np)
    allocate(local(size(b%x, 2)))
    do i = 1, size(b%x, 2)
      local(i) = max(dr, norm2(b%x(:, i) - center)*dt)
    end do
    call set_supports(b, factor, local)
    if (.not. allocated(b%lat)) return
    b%lat%sdr = dr
    b%lat%sdt = dt
    b%lat%factor = factor(1:2)
    b%lat%rho = 0.0_wp
    do i = 1, b%lat%n(2)
      call lattice_node(b%lat, b%lat%n(1)*i, x, vol, bnd, rho)
      b%lat%rho = max(b%lat%rho, rho)
    end do
  end subroutine annulus_supports

  subroutine set_supports(b, factor, local_spacing)
    type(body_t), intent(inout) :: b
    real(wp), intent(in) :: factor(:)
    real(wp), intent(in), optional :: local_spacing(:)
    integer :: i, nd
    nd = b%ndim
    b%support_factor = 0.0_wp
    b%support_factor(1:nd) = factor(1:nd)
    if (allocated(b%rho)) deallocate(b%rho)
    ! (a rank's share holds size(b%x, 2) of the np)
    allocate(b%rho(nd, size(b%x, 2)))
    do i = 1, size(b%x, 2)
      if (present(local_spacing)) then
        b%rho(:, i) = factor(1:nd)*local_spacing(i)
      else
        b%rho(:, i) = factor(1:nd)*b%spacing(1:nd)
      end if
    end do
    b%h = 1.0_wp
    b%h(1:nd) = factor(1:nd)*b%spacing(1:nd)
  end subroutine set_supports
end module generators_m
