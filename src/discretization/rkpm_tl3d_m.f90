!> Total-Lagrangian RKPM tables in three dimensions (Section 4 of the paper, stated for any
!! dimension; issue 23): stabilized conforming nodal integration (SCNI) over the particles'
!! lattice cells, computed once from the reference configuration.
!!
!! A 3D body extruded along z (generators_m extrude_body: a box, a polygon, a cylinder) gives
!! each particle a right prism over its x-y cell between two z levels (its layer's slab,
!! half at the ends): the x-y cell is the lattice square clipped by the polygon, or for a
!! cylinder the disk's explicit annular-sector cell. One integration point per particle, with
!!  - the weight W_L = V_L, the prism's volume;
!!  - the smoothed gradients b_Ij = (1/V_L) \oint N_I n_j dS (Chen, Wu, Yoon, You 2001): the
!!    two end faces (the x-y polygon, fan triangles of three points each, n = -e3 below,
!!    +e3 above) and the side faces (each polygon edge times the z interval, 2 x 2 Gauss
!!    points, the edge's outward normal in x-y). For linear fields b is exact (the RK shape
!!    functions of a linear basis reproduce them) and, because the cells tile the body with
!!    shared faces, the forces of a uniform stress on interior particles vanish: the patch
!!    test to round-off (test_rkpm_tl3d);
!!  - the lumped mass M_I = rho0 \int N_I dV (one point per fan triangle of the x-y cell,
!!    its centroid, x 2 Gauss points in z).
!!  - the sub-cell stabilization (after Puso, Chen, Zywicz, Elmer, IJNME 74 (2008); the 2D
!!    builder's right and upper halves, here in three directions): for each direction j
!!    the half prism on the positive side of the particle along X_j (the x-y polygon
!!    clipped at x = X1 or y = X2 times the z interval; the polygon times [X3, zb] along
!!    z) smooths dN/dX_j over its faces with n_j /= 0; gs_j = that minus the cell's, and
!!    the weight W_j = V_h (1 + V_h/(V_L - V_h)). A half that is (nearly) empty, as on the
!!    boundary, gets none. gs vanishes for linear fields (the patch test is untouched).
!! The three displacement components share one shape function (no symmetry axis to fold in
!! 3D), so the tables are compact (dims_3d): g and gs (3, nnz) hold dN/dX_j once, the
!! position table N once.
!!
!! Symmetry planes: a quarter or half cylinder (a disk sector extruded) is the part of a
!! symmetric body on one side of its straight sides. Its RK shape functions are folded as
!! the 2D builder folds them about the axis of revolution: each particle within its support
!! of a side gets a mirror image across it (and across both sides of a quarter, an image
!! of the image), carrying the mirrored displacement (its normal component negated); the
!! cloud with the images gives the shape functions, and each image's is added to its
!! twin's with the sign of the component: N^c_I = N_I + sum_images s_c N_I'. A particle on
!! a side is its own image: its normal component is held at 0 (solid set-up), and the
!! normal displacement vanishes on the side exactly. The components' shape functions then
!! differ near the sides: the tables are per component (dims_3d_folded: g, gs (9, nnz),
!! the position table N^c three times).
module rkpm_tl3d_m
  use kinds_m, only: wp, pi
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use body_m, only: body_t, max_cell_vertices
  use dims_m, only: dims_3d, dims_3d_folded
  use solid_tables_m, only: solid_tables_t, tables_transpose
  use geometry_m, only: geom_prism, geom_cylinder, clip_polygon_box, polygon_area
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_shape_values
  use neighbour_bins_m, only: bins_candidates
  use rkpm_tl_m, only: cell_area_points
  implicit none
  private
  public :: tl_build_3d, symmetry_planes_3d

  integer, parameter :: max_nb = 1024   !< particles covering one evaluation point (3D)
  integer, parameter :: max_cv = max_cell_vertices
  !> two Gauss points on [0, 1]
  real(wp), parameter :: gx(2) = [0.5_wp - 0.5_wp/sqrt(3.0_wp), 0.5_wp + 0.5_wp/sqrt(3.0_wp)]
  real(wp), parameter :: zero3(3) = 0.0_wp   !< no face: a volume point adds mass only
  !> A half cell holding less than this fraction of its cell's volume is empty (as in the
  !! 2D builder: clipping round-off, far below any genuine half).
  real(wp), parameter :: empty_half = 1.0e-9_wp

  !> The shape functions of a body with symmetry planes folded onto its particles: cloud
  !! particle k is particle twin(k) (k itself for k <= np), its displacement mirrored in
  !! the components with sgn(c, k) = -1; ncg the components whose shape functions are
  !! stored (1: compact, 3: folded, per component).
  type :: fold_t
    integer :: np = 0, ncg = 1
    integer, allocatable :: twin(:)
    real(wp), allocatable :: sgn(:, :)
  end type fold_t

contains

  !> The symmetry planes of body b: normal(k) = 1 or 2 (x or y), at position pos(k) (m),
  !! n of them (a quarter cylinder: y = cy and x = cx; a half: y = cy; else none).
  pure subroutine symmetry_planes_3d(b, normal, pos, n)
    type(body_t), intent(in) :: b
    integer, intent(out) :: normal(2), n
    real(wp), intent(out) :: pos(2)
    real(wp) :: span
    n = 0
    normal = 0
    pos = 0.0_wp
    if (b%geom%kind /= geom_cylinder) return
    span = b%geom%t1 - b%geom%t0
    if (span > 1.5_wp*pi) return
    n = 1
    normal(1) = 2
    pos(1) = b%geom%center(2)
    if (span < 0.75_wp*pi) then
      n = 2
      normal(2) = 1
      pos(2) = b%geom%center(1)
    end if
  end subroutine symmetry_planes_3d

  !> The cloud of body b with its mirror images across its symmetry planes (fold_t): the
  !! images of the particles whose supports reach across a plane (farther than tol from it).
  subroutine folded_cloud(b, c, f, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(out) :: c
    type(fold_t), intent(out) :: f
    type(error_t), allocatable, intent(inout) :: err
    integer :: normal(2), nplanes, i, m, k, ni, q
    real(wp) :: pos(2), tol, y(3), dist
    real(wp), allocatable :: xe(:, :), rhoe(:, :), vole(:)
    logical :: cross(2)
    call symmetry_planes_3d(b, normal, pos, nplanes)
    f%np = b%np
    f%ncg = merge(3, 1, nplanes > 0)
    ! at most 3 images per particle (two planes and the image of the image)
    allocate(xe(3, 4*b%np), rhoe(3, 4*b%np), vole(4*b%np), f%twin(4*b%np), f%sgn(3, 4*b%np))
    xe(:, 1:b%np) = b%x
    rhoe(:, 1:b%np) = b%rho
    vole(1:b%np) = b%vol
    f%twin(1:b%np) = [(i, i = 1, b%np)]
    f%sgn = 1.0_wp
    ni = b%np
    tol = 1.0e-9_wp*maxval(b%spacing(1:3))
    cross = .false.
    do i = 1, b%np
      do m = 1, nplanes
        dist = abs(b%x(normal(m), i) - pos(m))
        cross(m) = dist > tol .and. dist < b%rho(normal(m), i)
      end do
      ! the images across each plane it reaches, and across both (the quarter's corner)
      do q = 1, 3
        if (q > 1 .and. nplanes < 2) exit
        if (q <= 2) then
          if (.not. cross(min(q, 2))) cycle
        else
          if (.not. (cross(1) .and. cross(2))) cycle
        end if
        y = b%x(:, i)
        ni = ni + 1
        f%twin(ni) = i
        do k = 1, nplanes
          if (q == k .or. q == 3) then
            y(normal(k)) = 2.0_wp*pos(k) - y(normal(k))
            f%sgn(normal(k), ni) = -1.0_wp
          end if
        end do
        xe(:, ni) = y
        rhoe(:, ni) = b%rho(:, i)
        vole(ni) = b%vol(i)
      end do
    end do
    call cloud_init(c, xe(:, 1:ni), rhoe(:, 1:ni), vole(1:ni), b%kid, b%wshape, b%bid, &
      b%h(1:3), err)
    f%twin = f%twin(1:ni)
    f%sgn = f%sgn(:, 1:ni)
  end subroutine folded_cloud

  !> The SCNI tables of 3D lattice body b (reference configuration); rho0: density (kg/m^3).
  subroutine tl_build_3d(b, rho0, t, err)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(out) :: t
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: c
    type(fold_t) :: f
    real(wp), allocatable :: gl(:, :, :), ml(:, :), sl(:, :, :)
    integer, allocatable :: idl(:, :), nl(:), cand(:)
    integer :: np, maxk, i, n, bad, ng
    if (b%ndim /= 3 .or. (b%geom%kind /= geom_prism .and. b%geom%kind /= geom_cylinder)) then
      call set_error(err, "body '"//trim(b%name)//"': the 3D RKPM tables need a 3D body "// &
        "extruded along z (shape 'box', 'cylinder', or a 'polygon' with extrude)")
      return
    end if
    if (allocated(b%merged_ptr)) then
      if (b%merged_ptr(b%np + 1) > b%merged_ptr(1)) then
        call set_error(err, "body '"//trim(b%name)//"': its x-y cells hold merged lattice "// &
          "cells, which the 3D tables do not integrate yet; put the polygon's vertices on "// &
          "lattice points")
        return
      end if
    end if
    np = b%np
    t%np = np
    t%nq = np
    t%axisym = .false.
    t%scheme = 1
    call folded_cloud(b, c, f, err)
    if (allocated(err)) return
    t%dims = dims_3d
    if (f%ncg == 3) t%dims = dims_3d_folded
    ng = 3*f%ncg
    t%hmin = minval(b%spacing(1:3))
    ! the most particles one cell's points can touch: those within rmax + half a cell
    ! (the cloud holds the mirror images too)
    allocate(cand(c%np))
    maxk = 1
    do i = 1, np
      call bins_candidates(c%bins, b%x(:, i), c%rmax(1:3) + 0.5_wp*b%spacing(1:3), cand, n)
      maxk = max(maxk, n)
    end do
    allocate(gl(ng, maxk, np), ml(maxk, np), sl(ng, maxk, np), idl(maxk, np), nl(np))
    allocate(t%xq(3, np), t%owner(np), t%wgt(np), t%fix1(np), t%ws(3, np))
    t%fix1 = .false.
    bad = 0
    call cell_integrals(b, c, f, maxk, gl, ml, sl, idl, nl, t%wgt, t%ws, bad)
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined in the "// &
        "cell of particle "//itoa(bad)//" (too few particles cover a point of it; a larger "// &
        "support_factor mends it)")
      return
    end if
    t%xq = b%x
    t%owner = [(i, i = 1, np)]
    call compress_3d(t, gl, ml, sl, idl, nl, rho0)
    call positions_3d(b, c, f, t, err)
    if (allocated(err)) return
    call tables_transpose(t)
    t%total_mass = sum(t%mass)
    t%total_volume = sum(t%wgt)
  end subroutine tl_build_3d

  !> For each particle i: the volume of its cell (vol(i)), the unnormalised face integrals
  !! \oint N_I n dS (gl) and volume integrals \int N_I dV (ml) of the particles I touching
  !! it (idl, nl), then gl divided by the volume; the half cells' smoothed gradients minus
  !! the cell's (sl) and their weights (ws). bad: the largest particle whose cell has a
  !! point where the shape functions are undefined (0: none).
  subroutine cell_integrals(b, c, f, maxk, gl, ml, sl, idl, nl, vol, ws, bad)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    integer, intent(in) :: maxk
    real(wp), intent(out) :: gl(:, :, :), ml(:, :), sl(:, :, :), vol(:), ws(:, :)
    integer, intent(out) :: idl(:, :), nl(:)
    integer, intent(inout) :: bad
    real(wp) :: cv(2, max_cv), half(3), o(3), za, zb, zm, area, vh(3), hcs(2, max_cv, 2)
    real(wp) :: xg(2, 3*max_cv), wg(3*max_cv), lo(2), hi(2), xc(2, max_cv), wc(max_cv)
    integer :: ncv, ngp, i, q, r, np, dir, nhs(2), nc
    integer, allocatable :: slot(:)
    real(wp), parameter :: big = huge(1.0_wp)/4.0_wp
    np = b%np
    half = 0.5_wp*b%spacing(1:3)
    !$omp parallel default(none) shared(b, c, f, maxk, gl, ml, sl, idl, nl, vol, ws, half, np) &
    !$omp private(cv, o, za, zb, zm, area, vh, hcs, xg, wg, lo, hi, xc, wc, ncv, ngp, &
    !$omp q, r, dir, nhs, nc, slot) reduction(max: bad)
    allocate(slot(np))
    slot = 0
    !$omp do schedule(dynamic, 64)
    do i = 1, np
      nl(i) = 0
      o = b%x(:, i)
      if (allocated(b%cell_ptr)) then
        ncv = min(b%cell_ptr(i + 1) - b%cell_ptr(i), max_cv)
        cv(:, 1:ncv) = b%cell_xy(:, b%cell_ptr(i):b%cell_ptr(i) + ncv - 1)
      else
        call clip_polygon_box(b%geom%v, o(1:2) - half(1:2), o(1:2) + half(1:2), cv, ncv)
      end if
      za = max(b%geom%z0, o(3) - half(3))
      zb = min(b%geom%z1, o(3) + half(3))
      call cell_area_points(cv, ncv, xg, wg, ngp)
      area = sum(wg(1:ngp))
      vol(i) = area*(zb - za)
      zm = max(za, min(zb, o(3)))
      ! the half cells along X1 and X2 (the polygon clipped at x = X1, y = X2)
      do dir = 1, 2
        lo = -big
        hi = big
        lo(dir) = o(dir)
        call clip_polygon_box(cv(:, 1:ncv), lo, hi, hcs(:, :, dir), nhs(dir))
      end do
      ! volume integrals: one point per fan triangle (its centroid: exact for linear N; the
      ! masses are row sums, their total exact by the partition of unity) at two z levels
      call fan_centroids(cv, ncv, xc, wc, nc)
      do r = 1, 2
        do q = 1, nc
          call shape_at(c, f, [xc(:, q), za + gx(r)*(zb - za)], 0.5_wp*wc(q)*(zb - za), zero3, &
            zero3, i, slot, nl, idl, gl, ml, sl, bad)
        end do
      end do
      ! the end faces, n = -e3 at za and +e3 at zb (the top face is the X3 half cell's too)
      do q = 1, ngp
        call shape_at(c, f, [xg(:, q), za], 0.0_wp, [0.0_wp, 0.0_wp, -wg(q)], zero3, i, slot, &
          nl, idl, gl, ml, sl, bad)
        call shape_at(c, f, [xg(:, q), zb], 0.0_wp, [0.0_wp, 0.0_wp, wg(q)], &
          merge([0.0_wp, 0.0_wp, wg(q)], zero3, zb > zm), i, slot, nl, idl, gl, ml, sl, bad)
      end do
      ! the side faces; an edge that is whole in a half cell is that half cell's face too
      call side_faces(c, f, cv, ncv, za, zb, hcs, nhs, .true., i, slot, nl, idl, gl, ml, sl, &
        bad)
      ! the half cells' own faces: their edges that are not whole edges of the cell (the
      ! cut at x = X1 or y = X2, pieces of edges it splits)
      do dir = 1, 2
        vh(dir) = 0.0_wp
        if (nhs(dir) < 3) cycle
        ! (its volume only: the shoelace area, no quadrature points)
        vh(dir) = polygon_area(hcs(:, :, dir), nhs(dir))*(zb - za)
        call half_faces(c, f, hcs(:, :, dir), nhs(dir), cv, ncv, dir, za, zb, i, slot, nl, idl, &
          gl, ml, sl, bad)
      end do
      ! the half cell along X3: the polygon times [zm, zb]; its face at zm (-e3)
      vh(3) = area*(zb - zm)
      if (zb > zm) then
        do q = 1, ngp
          call shape_at(c, f, [xg(:, q), zm], 0.0_wp, zero3, [0.0_wp, 0.0_wp, -wg(q)], i, slot, &
            nl, idl, gl, ml, sl, bad)
        end do
      end if
      if (vol(i) > 0.0_wp) gl(:, 1:nl(i), i) = gl(:, 1:nl(i), i)/vol(i)
      do dir = 1, 3
        ! (rows dir, dir + 3, dir + 6 when the components are folded)
        if (vh(dir) > empty_half*vol(i) .and. vol(i) - vh(dir) > empty_half*vol(i)) then
          do q = dir, 3*f%ncg, 3
            sl(q, 1:nl(i), i) = sl(q, 1:nl(i), i)/vh(dir) - gl(q, 1:nl(i), i)
          end do
          ws(dir, i) = vh(dir)*(1.0_wp + vh(dir)/(vol(i) - vh(dir)))
        else
          do q = dir, 3*f%ncg, 3
            sl(q, 1:nl(i), i) = 0.0_wp
          end do
          ws(dir, i) = 0.0_wp
        end if
      end do
      do q = 1, nl(i)
        slot(idl(q, i)) = 0
      end do
    end do
    !$omp end do
    deallocate(slot)
    !$omp end parallel
  end subroutine cell_integrals

  !> The side faces of the prism polygon cv (ncv) x [za, zb], 2 x 2 Gauss points each:
  !! N_I n dS into gl (the cell), and N_I n_j dS into sl(j) where the edge is whole in the
  !! half cell j (hcs(:, :, j), nhs(j): an edge of it with the same two vertices).
  subroutine side_faces(c, f, cv, ncv, za, zb, hcs, nhs, whole, i, slot, nl, idl, gl, ml, &
    sl, bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: cv(:, :), za, zb, hcs(:, :, :)
    integer, intent(in) :: ncv, nhs(2), i
    logical, intent(in) :: whole
    integer, intent(inout) :: slot(:), nl(:), idl(:, :), bad
    real(wp), intent(inout) :: gl(:, :, :), ml(:, :), sl(:, :, :)
    real(wp) :: e(2), len_e, nrm(3), w, p(3), hmask(3)
    integer :: k, q, r, k1, dir
    do k = 1, ncv
      k1 = modulo(k, ncv) + 1
      e = cv(:, k1) - cv(:, k)
      len_e = norm2(e)
      if (len_e == 0.0_wp) cycle
      nrm = [e(2), -e(1), 0.0_wp]/len_e
      hmask = 0.0_wp
      do dir = 1, 2
        if (whole .and. nhs(dir) >= 3) then
          if (has_edge(hcs(:, 1:nhs(dir), dir), cv(:, k), cv(:, k1))) hmask(dir) = 1.0_wp
        end if
      end do
      w = 0.25_wp*len_e*(zb - za)
      do q = 1, 2
        do r = 1, 2
          p = [cv(:, k) + gx(q)*e, za + gx(r)*(zb - za)]
          call shape_at(c, f, p, 0.0_wp, w*nrm, w*nrm*hmask, i, slot, nl, idl, gl, ml, sl, bad)
        end do
      end do
    end do
  end subroutine side_faces

  !> The faces of the half cell hc (nhc) x [za, zb] along X_dir that are not whole edges of
  !! the cell cv (those side_faces added): N_I n_dir dS into sl(dir), 2 x 2 Gauss points.
  subroutine half_faces(c, f, hc, nhc, cv, ncv, dir, za, zb, i, slot, nl, idl, gl, ml, sl, &
    bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: hc(:, :), cv(:, :), za, zb
    integer, intent(in) :: nhc, ncv, dir, i
    integer, intent(inout) :: slot(:), nl(:), idl(:, :), bad
    real(wp), intent(inout) :: gl(:, :, :), ml(:, :), sl(:, :, :)
    real(wp) :: e(2), len_e, nrm(3), w, p(3)
    integer :: k, q, r, k1
    do k = 1, nhc
      k1 = modulo(k, nhc) + 1
      e = hc(:, k1) - hc(:, k)
      len_e = norm2(e)
      if (len_e == 0.0_wp) cycle
      nrm = 0.0_wp
      nrm(dir) = merge(e(2), -e(1), dir == 1)/len_e
      if (nrm(dir) == 0.0_wp) cycle
      if (has_edge(cv(:, 1:ncv), hc(:, k), hc(:, k1))) cycle
      w = 0.25_wp*len_e*(zb - za)
      do q = 1, 2
        do r = 1, 2
          p = [hc(:, k) + gx(q)*e, za + gx(r)*(zb - za)]
          call shape_at(c, f, p, 0.0_wp, zero3, w*nrm, i, slot, nl, idl, gl, ml, sl, bad)
        end do
      end do
    end do
  end subroutine half_faces

  !> Has polygon v an edge from a to b (the same vertices, in this order)?
  pure logical function has_edge(v, a, b)
    real(wp), intent(in) :: v(:, :), a(2), b(2)
    integer :: k
    has_edge = .false.
    do k = 1, size(v, 2)
      if (all(v(:, k) == a) .and. all(v(:, modulo(k, size(v, 2)) + 1) == b)) then
        has_edge = .true.
        return
      end if
    end do
  end function has_edge

  !> One point per triangle of the fan of polygon cv (ncv) from its vertex mean (as
  !! cell_area_points): the triangles' centroids xc and areas wc (nc of them).
  pure subroutine fan_centroids(cv, ncv, xc, wc, nc)
    real(wp), intent(in) :: cv(:, :)
    integer, intent(in) :: ncv
    real(wp), intent(out) :: xc(:, :), wc(:)
    integer, intent(out) :: nc
    real(wp) :: o(2), a(2), b(2)
    integer :: k
    o = sum(cv(:, 1:ncv), dim=2)/real(ncv, wp)
    nc = 0
    do k = 1, ncv
      a = cv(:, k)
      b = cv(:, modulo(k, ncv) + 1)
      nc = nc + 1
      xc(:, nc) = (o + a + b)/3.0_wp
      wc(nc) = 0.5_wp*((a(1) - o(1))*(b(2) - o(2)) - (a(2) - o(2))*(b(1) - o(1)))
    end do
  end subroutine fan_centroids

  !> Add, at point pp, wm N_I to ml, wn N_I to gl (the cell's face weight times its normal)
  !! and wh N_I to sl (a half cell's) of particle i's slots, for every particle I whose
  !! shape function reaches pp; folded (f%ncg = 3): per component c, rows 3 (c - 1) + 1..3,
  !! an image's N added to its twin's with the component's sign. bad: i when they are
  !! undefined there.
  subroutine shape_at(c, f, pp, wm, wn, wh, i, slot, nl, idl, gl, ml, sl, bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: pp(3), wm, wn(3), wh(3)
    integer, intent(in) :: i
    integer, intent(inout) :: slot(:), nl(:), idl(:, :), bad
    real(wp), intent(inout) :: gl(:, :, :), ml(:, :), sl(:, :, :)
    real(wp) :: n(max_nb)
    integer :: ids(max_nb), nnb, kk, jj, s, cc
    logical :: ok
    call cloud_shape_values(c, pp, nnb, ids, n, ok)
    if (.not. ok) then
      bad = max(bad, i)
      return
    end if
    do kk = 1, nnb
      jj = f%twin(ids(kk))
      s = slot(jj)
      if (s == 0) then
        nl(i) = nl(i) + 1
        s = nl(i)
        slot(jj) = s
        idl(s, i) = jj
        gl(:, s, i) = 0.0_wp
        ml(s, i) = 0.0_wp
        sl(:, s, i) = 0.0_wp
      end if
      ml(s, i) = ml(s, i) + wm*n(kk)
      if (f%ncg == 1) then
        gl(:, s, i) = gl(:, s, i) + wn*n(kk)
        sl(:, s, i) = sl(:, s, i) + wh*n(kk)
      else
        do cc = 1, 3
          gl(3*cc - 2:3*cc, s, i) = gl(3*cc - 2:3*cc, s, i) + f%sgn(cc, ids(kk))*wn*n(kk)
          sl(3*cc - 2:3*cc, s, i) = sl(3*cc - 2:3*cc, s, i) + f%sgn(cc, ids(kk))*wh*n(kk)
        end do
      end if
    end do
  end subroutine shape_at

  !> The tables from the per-point lists: CSR over the points, the compact gradients and
  !! half-cell differences (dims_3d), lumped masses rho0 \int N dV, no hoop term.
  subroutine compress_3d(t, gl, ml, sl, idl, nl, rho0)
    type(solid_tables_t), intent(inout) :: t
    real(wp), intent(in) :: gl(:, :, :), ml(:, :), sl(:, :, :), rho0
    integer, intent(in) :: idl(:, :), nl(:)
    integer :: q, k, e, nnz
    nnz = sum(nl)
    allocate(t%ptr(t%nq + 1), t%nbr(nnz), t%g(t%dims%ngrad, nnz), t%h(nnz), t%mass(t%np), &
      t%gs(t%dims%ngrad, nnz))
    t%h = 0.0_wp
    t%mass = 0.0_wp
    t%ptr(1) = 1
    do q = 1, t%nq
      t%ptr(q + 1) = t%ptr(q) + nl(q)
      do k = 1, nl(q)
        e = t%ptr(q) + k - 1
        t%nbr(e) = idl(k, q)
        t%g(:, e) = gl(:, k, q)
        t%gs(:, e) = sl(:, k, q)
        t%mass(idl(k, q)) = t%mass(idl(k, q)) + rho0*ml(k, q)
      end do
    end do
  end subroutine compress_3d

  !> N_I(X_J) for the physical positions x_J = X_J + sum_I N_I(X_J) d_I (once: the
  !! components share it).
  subroutine positions_3d(b, c, f, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: cnt(:), idj(:, :)
    real(wp), allocatable :: nj(:, :, :)
    real(wp) :: n(max_nb)
    integer :: ids(max_nb), nnb, j, k, e, bad, maxk, m, jj, s
    logical :: ok
    maxk = max_nb
    allocate(cnt(b%np), idj(maxk, b%np), nj(f%ncg, maxk, b%np))
    bad = 0
    !$omp parallel do default(none) shared(b, c, f, cnt, idj, nj) &
    !$omp private(n, ids, nnb, ok, k, m, jj, s) reduction(max: bad) schedule(dynamic, 64)
    do j = 1, b%np
      call cloud_shape_values(c, b%x(:, j), nnb, ids, n, ok)
      if (.not. ok) bad = max(bad, j)
      ! images folded onto their twins (the sign of each component)
      m = 0
      do k = 1, nnb
        jj = f%twin(ids(k))
        do s = 1, m
          if (idj(s, j) == jj) exit
        end do
        if (s > m) then
          m = m + 1
          s = m
          idj(s, j) = jj
          nj(:, s, j) = 0.0_wp
        end if
        if (f%ncg == 1) then
          nj(1, s, j) = nj(1, s, j) + n(k)
        else
          nj(:, s, j) = nj(:, s, j) + f%sgn(:, ids(k))*n(k)
        end if
      end do
      cnt(j) = m
    end do
    !$omp end parallel do
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined at "// &
        "particle "//itoa(bad))
      return
    end if
    allocate(t%pptr(b%np + 1), t%pnbr(sum(cnt)), t%pn(t%dims%npos, sum(cnt)))
    t%pptr(1) = 1
    do j = 1, b%np
      t%pptr(j + 1) = t%pptr(j) + cnt(j)
      do k = 1, cnt(j)
        e = t%pptr(j) + k - 1
        t%pnbr(e) = idj(k, j)
        t%pn(:, e) = nj(:, k, j)
      end do
    end do
  end subroutine positions_3d
end module rkpm_tl3d_m
