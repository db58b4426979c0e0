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
!!  - the lumped mass M_I = rho0 \int N_I dV (the x-y cell's fan triangles, rkpm_tl_m's
!!    cell_area_points, x 2 Gauss points in z).
!! The three displacement components share one shape function (no symmetry axis to fold in
!! 3D), so the gradients are stored per component in the layout of dims_3d (ngrad = 9: dN/dX1,
!! dN/dX2, dN/dX3 for u1, then for u2, then for u3) and the position table holds N three
!! times. The sub-cell stabilization (the 2D builder's right and upper halves) is not built
!! here yet: gs and ws are zero.
module rkpm_tl3d_m
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use body_m, only: body_t, max_cell_vertices
  use dims_m, only: dims_3d
  use solid_tables_m, only: solid_tables_t, tables_transpose
  use geometry_m, only: geom_prism, geom_cylinder, clip_polygon_box
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_shape
  use neighbour_bins_m, only: bins_candidates
  use rkpm_tl_m, only: cell_area_points
  implicit none
  private
  public :: tl_build_3d

  integer, parameter :: max_nb = 1024   !< particles covering one evaluation point (3D)
  integer, parameter :: max_cv = max_cell_vertices
  !> two Gauss points on [0, 1]
  real(wp), parameter :: gx(2) = [0.5_wp - 0.5_wp/sqrt(3.0_wp), 0.5_wp + 0.5_wp/sqrt(3.0_wp)]
  real(wp), parameter :: zero3(3) = 0.0_wp   !< no face: a volume point adds mass only

contains

  !> The SCNI tables of 3D lattice body b (reference configuration); rho0: density (kg/m^3).
  subroutine tl_build_3d(b, rho0, t, err)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(out) :: t
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: c
    real(wp), allocatable :: gl(:, :, :), ml(:, :)
    integer, allocatable :: idl(:, :), nl(:), cand(:)
    integer :: np, maxk, i, n, bad
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
    t%dims = dims_3d
    t%scheme = 1
    call cloud_init(c, b%x, b%rho, b%vol, b%kid, b%wshape, b%bid, b%h(1:3), err)
    if (allocated(err)) return
    t%hmin = minval(b%spacing(1:3))
    ! the most particles one cell's points can touch: those within rmax + half a cell
    allocate(cand(np))
    maxk = 1
    do i = 1, np
      call bins_candidates(c%bins, b%x(:, i), c%rmax(1:3) + 0.5_wp*b%spacing(1:3), cand, n)
      maxk = max(maxk, n)
    end do
    allocate(gl(3, maxk, np), ml(maxk, np), idl(maxk, np), nl(np))
    allocate(t%xq(3, np), t%owner(np), t%wgt(np), t%fix1(np))
    t%fix1 = .false.
    bad = 0
    call cell_integrals(b, c, maxk, gl, ml, idl, nl, t%wgt, bad)
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined in the "// &
        "cell of particle "//itoa(bad)//" (too few particles cover a point of it; a larger "// &
        "support_factor mends it)")
      return
    end if
    t%xq = b%x
    t%owner = [(i, i = 1, np)]
    call compress_3d(t, gl, ml, idl, nl, rho0)
    call positions_3d(b, c, t, err)
    if (allocated(err)) return
    call tables_transpose(t)
    t%total_mass = sum(t%mass)
    t%total_volume = sum(t%wgt)
  end subroutine tl_build_3d

  !> For each particle i: the volume of its cell (vol(i)), the unnormalised face integrals
  !! \oint N_I n dS (gl) and volume integrals \int N_I dV (ml) of the particles I touching
  !! it (idl, nl), then gl divided by the volume. bad: the largest particle whose cell has a
  !! point where the shape functions are undefined (0: none).
  subroutine cell_integrals(b, c, maxk, gl, ml, idl, nl, vol, bad)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    integer, intent(in) :: maxk
    real(wp), intent(out) :: gl(:, :, :), ml(:, :), vol(:)
    integer, intent(out) :: idl(:, :), nl(:)
    integer, intent(inout) :: bad
    real(wp) :: cv(2, max_cv), half(3), o(3), za, zb, area, e(2), len_e, nrm(2)
    real(wp) :: xg(2, 3*max_cv), wg(3*max_cv), p(3), w
    integer :: ncv, ngp, i, k, q, r, np
    integer, allocatable :: slot(:)
    np = b%np
    half = 0.5_wp*b%spacing(1:3)
    !$omp parallel default(none) shared(b, c, maxk, gl, ml, idl, nl, vol, half, np) &
    !$omp private(cv, o, za, zb, area, e, len_e, nrm, xg, wg, p, w, ncv, ngp, k, q, r, &
    !$omp slot) reduction(max: bad)
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
      ! volume integrals: the fan's points at two z levels
      do r = 1, 2
        do q = 1, ngp
          p = [xg(:, q), za + gx(r)*(zb - za)]
          call shape_at(c, p, 0.5_wp*wg(q)*(zb - za), zero3, i, slot, nl, idl, gl, ml, bad)
        end do
      end do
      ! the end faces: n = -e3 at za, +e3 at zb
      do q = 1, ngp
        call shape_at(c, [xg(:, q), za], 0.0_wp, [0.0_wp, 0.0_wp, -wg(q)], i, slot, nl, idl, &
          gl, ml, bad)
        call shape_at(c, [xg(:, q), zb], 0.0_wp, [0.0_wp, 0.0_wp, wg(q)], i, slot, nl, idl, &
          gl, ml, bad)
      end do
      ! the side faces: each edge times [za, zb], 2 x 2 Gauss points
      do k = 1, ncv
        e = cv(:, modulo(k, ncv) + 1) - cv(:, k)
        len_e = norm2(e)
        if (len_e == 0.0_wp) cycle
        nrm = [e(2), -e(1)]/len_e
        do q = 1, 2
          do r = 1, 2
            p = [cv(:, k) + gx(q)*e, za + gx(r)*(zb - za)]
            w = 0.25_wp*len_e*(zb - za)
            call shape_at(c, p, 0.0_wp, [w*nrm(1), w*nrm(2), 0.0_wp], i, slot, nl, idl, gl, &
              ml, bad)
          end do
        end do
      end do
      if (vol(i) > 0.0_wp) gl(:, 1:nl(i), i) = gl(:, 1:nl(i), i)/vol(i)
      do k = 1, nl(i)
        slot(idl(k, i)) = 0
      end do
    end do
    !$omp end do
    deallocate(slot)
    !$omp end parallel
  end subroutine cell_integrals

  !> Add, at point pp, wm N_I to ml and wn N_I to gl (the face's weight times its normal)
  !! of particle i's slots, for every particle I whose shape function reaches pp. bad: i
  !! when they are undefined there.
  subroutine shape_at(c, pp, wm, wn, i, slot, nl, idl, gl, ml, bad)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: pp(3), wm, wn(3)
    integer, intent(in) :: i
    integer, intent(inout) :: slot(:), nl(:), idl(:, :), bad
    real(wp), intent(inout) :: gl(:, :, :), ml(:, :)
    real(wp) :: n(max_nb), dn(3, max_nb)
    integer :: ids(max_nb), nnb, kk, jj, s
    logical :: ok
    call cloud_shape(c, pp, nnb, ids, n, dn, ok)
    if (.not. ok) then
      bad = max(bad, i)
      return
    end if
    do kk = 1, nnb
      jj = ids(kk)
      s = slot(jj)
      if (s == 0) then
        nl(i) = nl(i) + 1
        s = nl(i)
        slot(jj) = s
        idl(s, i) = jj
        gl(:, s, i) = 0.0_wp
        ml(s, i) = 0.0_wp
      end if
      ml(s, i) = ml(s, i) + wm*n(kk)
      gl(:, s, i) = gl(:, s, i) + wn*n(kk)
    end do
  end subroutine shape_at

  !> The tables from the per-point lists: CSR over the points, the gradients repeated for
  !! the three components (dims_3d), lumped masses rho0 \int N dV, no hoop term, no
  !! stabilization yet.
  subroutine compress_3d(t, gl, ml, idl, nl, rho0)
    type(solid_tables_t), intent(inout) :: t
    real(wp), intent(in) :: gl(:, :, :), ml(:, :), rho0
    integer, intent(in) :: idl(:, :), nl(:)
    integer :: q, k, e, nnz
    nnz = sum(nl)
    allocate(t%ptr(t%nq + 1), t%nbr(nnz), t%g(9, nnz), t%h(nnz), t%mass(t%np))
    allocate(t%gs(9, nnz), t%ws(3, t%nq))
    t%gs = 0.0_wp
    t%ws = 0.0_wp
    t%h = 0.0_wp
    t%mass = 0.0_wp
    t%ptr(1) = 1
    do q = 1, t%nq
      t%ptr(q + 1) = t%ptr(q) + nl(q)
      do k = 1, nl(q)
        e = t%ptr(q) + k - 1
        t%nbr(e) = idl(k, q)
        t%g(1:3, e) = gl(:, k, q)
        t%g(4:6, e) = gl(:, k, q)
        t%g(7:9, e) = gl(:, k, q)
        t%mass(idl(k, q)) = t%mass(idl(k, q)) + rho0*ml(k, q)
      end do
    end do
  end subroutine compress_3d

  !> N_I(X_J) for the physical positions x_J = X_J + sum_I N_I(X_J) d_I (each component).
  subroutine positions_3d(b, c, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: cnt(:), idj(:, :)
    real(wp), allocatable :: nj(:, :)
    real(wp) :: n(max_nb), dn(3, max_nb)
    integer :: ids(max_nb), nnb, j, k, e, bad, maxk
    logical :: ok
    maxk = max_nb
    allocate(cnt(b%np), idj(maxk, b%np), nj(maxk, b%np))
    bad = 0
    !$omp parallel do default(none) shared(b, c, cnt, idj, nj) private(n, dn, ids, nnb, ok, k) &
    !$omp reduction(max: bad) schedule(dynamic, 64)
    do j = 1, b%np
      call cloud_shape(c, b%x(:, j), nnb, ids, n, dn, ok)
      cnt(j) = nnb
      if (.not. ok) bad = max(bad, j)
      do k = 1, nnb
        idj(k, j) = ids(k)
        nj(k, j) = n(k)
      end do
    end do
    !$omp end parallel do
    if (bad > 0) then
      call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined at "// &
        "particle "//itoa(bad))
      return
    end if
    allocate(t%pptr(b%np + 1), t%pnbr(sum(cnt)), t%pn(3, sum(cnt)))
    t%pptr(1) = 1
    do j = 1, b%np
      t%pptr(j + 1) = t%pptr(j) + cnt(j)
      do k = 1, cnt(j)
        e = t%pptr(j) + k - 1
        t%pnbr(e) = idj(k, j)
        t%pn(:, e) = nj(k, j)
      end do
    end do
  end subroutine positions_3d
end module rkpm_tl3d_m
