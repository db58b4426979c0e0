!> Total-Lagrangian RKPM tables in three dimensions (Section 4 of the paper, stated for any
!! dimension; issue 23): stabilized conforming nodal integration (SCNI) over the particles'
!! lattice cells, or over the median-dual cells of a tetrahedral mesh whose nodes are the
!! particles (a gmsh script's volumes: dual_cell_integrals), computed once from the
!! reference configuration.
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
  use sorting_m, only: incidence_csr
  use kinds_m, only: wp, pi
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use body_m, only: body_t, max_cell_vertices, body_cell, body_whole
  use generators_m, only: extrude_pick
  use heap_m, only: heap_return
  use dims_m, only: dims_3d, dims_3d_folded
  use solid_tables_m, only: solid_tables_t, tables_transpose
  use geometry_m, only: geom_prism, geom_cylinder, clip_polygon_box, polygon_area, &
    cross => cross3
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_shape_values, cloud_candidates
  use neighbour_bins_m, only: bins_candidates
  use rkpm_tl_m, only: cell_area_points
  use tet4_m, only: tet4_mesh_t, tet4_face_neighbours
  implicit none
  private
  public :: tl_build_3d, tl_region_3d, symmetry_planes_3d

  integer, parameter :: max_nb = 1024   !< particles covering one evaluation point (3D)
  integer, parameter :: max_cv = max_cell_vertices
  !> two Gauss points on [0, 1]
  real(wp), parameter :: gx(2) = [0.5_wp - 0.5_wp/sqrt(3.0_wp), 0.5_wp + 0.5_wp/sqrt(3.0_wp)]
  real(wp), parameter :: zero3(3) = 0.0_wp   !< no face: a volume point adds mass only
  !> A half cell holding less than this fraction of its cell's volume is empty (as in the
  !! 2D builder: clipping round-off, far below any genuine half).
  real(wp), parameter :: empty_half = 1.0e-9_wp
  !> Particles per block of the build (scni_tables_3d, positions_3d): a block's cells are
  !! kept row by row (the entries each has) until the block is packed, so the build's peak
  !! is the packed tables and not np rows padded to the most candidates any cell has (a few
  !! hundred, 60 B each compact, 156 B folded; issue 23: 10^6 particles in 3D).
  integer, parameter :: block_np = 4096

  !> Rows of a table, packed (the entries each row has, in order): one cell's, or one
  !! block's kept until every block's count is known. Particle ids, values a (g or N), b
  !! (gs) and m (\int N dV, a cell's).
  type :: rows_t
    integer, allocatable :: id(:)
    real(wp), allocatable :: a(:, :), b(:, :), m(:)
  end type rows_t

  !> The shape functions of a body with symmetry planes folded onto its particles: cloud
  !! particle k is particle twin(k) (k itself for k <= np), its displacement mirrored in
  !! the components with sgn(c, k) = -1; ncg the components whose shape functions are
  !! stored (1: compact, 3: folded, per component).
  type :: fold_t
    integer :: np = 0, ncg = 1
    integer, allocatable :: twin(:)
    real(wp), allocatable :: sgn(:, :)
  end type fold_t

  !> One thread's work space for one cell's integrals (cell_integrals, dual_cell_integrals):
  !! the slot of each particle touching the cell (slot, over the particles; 0: none), their
  !! ids (idl(1:nl)), face integrals (gl), volume integrals (ml) and half cells' (sl), at
  !! most maxk of them; and the particles whose supports may reach the cell
  !! (cand(1:ncand), cloud_candidates: the only ones its points scan).
  type :: cell_work_t
    integer :: nl = 0, ncand = 0
    integer, allocatable :: slot(:), idl(:), cand(:)
    real(wp), allocatable :: gl(:, :), ml(:), sl(:, :)
  end type cell_work_t

  !> The connectivity the median-dual cells of a tetrahedral mesh need (dual_mesh): the
  !! tetrahedra at each particle (idx(ptr(i) : ptr(i+1)-1), in mesh order), the one across
  !! each face (nbr(f, e), face f opposite node f, 0 on the boundary), the smallest height
  !! of a tetrahedron (the time step's length, as tet4_m's) and the longest edge (m).
  type :: dual_mesh_t
    integer, allocatable :: ptr(:), idx(:), nbr(:, :)
    real(wp) :: hmin = 0.0_wp, lmax = 0.0_wp
  end type dual_mesh_t

  !> The centroid of the piece of a tetrahedron that is its node a's median-dual cell (the
  !! points where a's barycentric coordinate is the largest): a's coordinate there has the
  !! mean of the largest of four uniform spacings, (1 + 1/2 + 1/3 + 1/4)/4 = 25/48, each
  !! other node's (1 - 25/48)/3 = 23/144.
  real(wp), parameter :: piece_own = 25.0_wp/48.0_wp, piece_other = 23.0_wp/144.0_wp

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
  !! near (3, 2), a region (lower, upper corner; a rank's box grown by what its cells can
  !! reach, scni_tables_3d): only the particles and images within it enter the cloud, in
  !! the same order, with the whole cloud's extremes and largest supports (cloud_init's
  !! grid), so every point whose covering particles lie within near gets the whole
  !! cloud's shape functions to the bit; twin and sgn are the region cloud's.
  subroutine folded_cloud(b, c, f, err, near)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(out) :: c
    type(fold_t), intent(out) :: f
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: near(3, 2)
    integer :: normal(2), nplanes, i, m, k, ni, q, pass, nkeep
    real(wp) :: pos(2), tol, y(3), dist, lo(3), hi(3), sg(3)
    real(wp), allocatable :: xe(:, :), rhoe(:, :), vole(:)
    logical :: cross(2)
    type(body_t) :: ends_b
    call symmetry_planes_3d(b, normal, pos, nplanes)
    f%np = b%np
    f%ncg = merge(3, 1, nplanes > 0)
    tol = 1.0e-9_wp*maxval(b%spacing(1:3))
    cross = .false.
    ! two passes over the particles and their images (at most 3 each: two planes and the
    ! image of the image) in the cloud's order: the first counts those in the region and
    ! finds the whole cloud's extremes, the second stores the region's
    do pass = 1, 2
      ni = 0
      lo = huge(1.0_wp)
      hi = -huge(1.0_wp)
      if (pass == 2) allocate(xe(3, nkeep), rhoe(3, nkeep), vole(nkeep), f%twin(nkeep), &
        f%sgn(3, nkeep))
      call walk(b)
      nkeep = ni
    end do
    if (allocated(b%mfile)) then
      ! b holds some nodes of a mesh file's body (a rank's region, read: tet_file_m): the
      ! whole cloud's extremes are the file's, placed (no images: a mesh has no symmetry
      ! planes), and its largest supports the factors times the longest edge
      lo = b%mfile%lo + b%mfile%shift
      hi = b%mfile%hi + b%mfile%shift
    else if (allocated(b%glob)) then
      ! b holds some particles of a larger body (a rank's region, made from its recipe:
      ! generators_m extrude_pick): the whole cloud's extremes are those of its first and
      ! last layers' entries (the layers' sections are the same, z rises with the layer),
      ! taken with the same operations (min and max are exact)
      call extrude_pick(b, 1, huge(1), [(-huge(1.0_wp), m = 1, 3)], &
        [(huge(1.0_wp), m = 1, 3)], 0, normal, pos, ends_b, ends=.true.)
      lo = huge(1.0_wp)
      hi = -huge(1.0_wp)
      pass = 0
      call walk(ends_b)
    end if
    if (present(near)) then
      call cloud_init(c, xe, rhoe, vole, b%kid, b%wshape, b%bid, b%h(1:3), err, lo, hi, &
        body_rmax(b))
    else
      call cloud_init(c, xe, rhoe, vole, b%kid, b%wshape, b%bid, b%h(1:3), err)
    end if
    ! (signs are read only where the components are folded)
    if (f%ncg /= 3) deallocate(f%sgn)

  contains

    !> Every particle of body bb and its images, in the cloud's order (add_entry)
    subroutine walk(bb)
      type(body_t), intent(in) :: bb
      do i = 1, bb%np
        call add_entry(bb, bb%x(:, i), i, [1.0_wp, 1.0_wp, 1.0_wp])
      end do
      do i = 1, bb%np
        do m = 1, nplanes
          dist = abs(bb%x(normal(m), i) - pos(m))
          cross(m) = dist > tol .and. dist < bb%rho(normal(m), i)
        end do
        ! the images across each plane it reaches, and across both (the quarter's corner)
        do q = 1, 3
          if (q > 1 .and. nplanes < 2) exit
          if (q <= 2) then
            if (.not. cross(min(q, 2))) cycle
          else
            if (.not. (cross(1) .and. cross(2))) cycle
          end if
          y = bb%x(:, i)
          sg = 1.0_wp
          do k = 1, nplanes
            if (q == k .or. q == 3) then
              y(normal(k)) = 2.0_wp*pos(k) - y(normal(k))
              sg(normal(k)) = -1.0_wp
            end if
          end do
          call add_entry(bb, y, i, sg)
        end do
      end do
    end subroutine walk

    !> The next entry of the cloud, at y, of particle i of bb with the signs sg: counted
    !! and stored when within the region (pass 1, 2); the extremes over every entry (pass
    !! 0: only those).
    subroutine add_entry(bb, y, i, sg)
      type(body_t), intent(in) :: bb
      real(wp), intent(in) :: y(3), sg(3)
      integer, intent(in) :: i
      lo = min(lo, y)
      hi = max(hi, y)
      if (pass == 0) return
      if (present(near)) then
        if (any(y < near(:, 1)) .or. any(y > near(:, 2))) return
      end if
      ni = ni + 1
      if (pass == 1) return
      xe(:, ni) = y
      rhoe(:, ni) = bb%rho(:, i)
      vole(ni) = bb%vol(i)
      f%twin(ni) = i
      f%sgn(:, ni) = sg
    end subroutine add_entry
  end subroutine folded_cloud

  !> The SCNI tables of 3D lattice body b (reference configuration); rho0: density (kg/m^3).
  !! box (3, 2), a rank's box of the decomposition (lower, upper corner; doc/parallel.md):
  !! the rows are kept only for the cells whose particles' supports can reach into the box
  !! (its own points and every ghost point it can have; the others' rows are empty). Every
  !! cell is still integrated, so the masses, volumes and stabilization weights of all
  !! particles are the whole body's, to the bit, and the position table is whole. Such
  !! tables are only cut into a part (decomposition_m local_part_build): they get no
  !! transpose, so no force is evaluated on them.
  subroutine tl_build_3d(b, rho0, t, err, box)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(out) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: box(3, 2)
    if (b%ndim /= 3 .or. (b%geom%kind /= geom_prism .and. b%geom%kind /= geom_cylinder &
      .and. .not. allocated(b%tets))) then
      call set_error(err, "body '"//trim(b%name)//"': the 3D RKPM tables need a 3D body "// &
        "extruded along z (shape 'box', 'cylinder', or a 'polygon' with extrude) or a "// &
        "tetrahedral mesh (shape 'geo')")
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
    t%np = b%np
    t%nq = b%np
    t%axisym = .false.
    t%scheme = 1
    call scni_tables_3d(b, rho0, t, err, box)
    if (allocated(err)) return
    ! (the cloud is gone by now: the transpose's arrays take its place at the build's peak;
    ! a region's rows are only cut into a rank's part, whose own tables get their transpose)
    if (.not. present(box)) call tables_transpose(t)
    t%total_mass = sum(t%mass)
    t%total_volume = sum(t%wgt)
  end subroutine tl_build_3d

  !> The particles of extruded body b (made from its recipe, generators_m extrude_pick: the
  !! whole body need not exist) that tl_build_3d's tables for box read: those whose
  !! position or mirror image lies within the box grown by what its cells can reach
  !! (scni_tables_3d's region cloud), and one spacing more; as body r numbered over them
  !! (r%glob: their numbers in b), in b's order. tl_build_3d(r, ..., box) then makes
  !! the same rows as tl_build_3d(b, ..., box), over r's numbers.
  subroutine tl_region_3d(b, box, r)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: box(3, 2)
    type(body_t), intent(out) :: r
    real(wp) :: grow(3), pos(2)
    integer :: normal(2), n
    grow = region_reach(b%ext%rho, 0.5_wp*b%spacing(1:3)) + b%spacing(1:3)
    call symmetry_planes_3d(b, normal, pos, n)
    call extrude_pick(b, 1, b%np, box(:, 1) - grow, box(:, 2) + grow, n, normal, pos, r)
  end subroutine tl_region_3d

  !> The largest supports of body b's whole cloud: its particles' (b%rho), or for a rank's
  !! region of a mesh file's body, the factors times the whole mesh's longest edge (each
  !! node's support is its longest edge's: tet_file_m).
  pure function body_rmax(b) result(r)
    type(body_t), intent(in) :: b
    real(wp) :: r(3)
    if (allocated(b%mfile)) then
      r = b%support_factor(1:3)*b%mfile%lmax
    else
      r = maxval(b%rho, dim=2)
    end if
  end function body_rmax

  !> Whether b is a rank's region of a mesh file read by the supports near its box
  !! (mesh_file_t rbox set), whose cells scni_tables_3d chooses by them.
  pure logical function by_supports(b)
    type(body_t), intent(in) :: b
    by_supports = .false.
    if (allocated(b%mfile)) by_supports = b%mfile%rbox(1) >= 0.0_wp
  end function by_supports

  !> How far beyond a rank's box the region cloud of scni_tables_3d reaches: a kept
  !! cell's particle lies within rmax + reach of the box, a point of the cell within
  !! reach of its particle, and a particle covering it within rmax of it; one reach more
  !! for the rounding of the candidates' boxes (cell_candidates) and a perturbed
  !! lattice's cells. rmax: the largest supports; reach: a cell's reach from its particle.
  pure function region_reach(rmax, reach) result(grow)
    real(wp), intent(in) :: rmax(3), reach(3)
    real(wp) :: grow(3)
    grow = 2.0_wp*rmax + 3.0_wp*reach
  end function region_reach

  !> tl_build_3d's tables but the transpose. The cells are integrated block by block
  !! (block_np particles), each cell's row kept compact (the entries it has) until its
  !! block is packed; the CSR arrays are allocated once the total is known and filled from
  !! the blocks. The tables are those of one pass over all the cells with padded (maxk, np)
  !! arrays, to the bit: the same entries in the same order, the masses summed in the same
  !! order.
  subroutine scni_tables_3d(b, rho0, t, err, box)
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: rho0
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: box(3, 2)
    type(rk_cloud_t) :: c
    type(fold_t) :: f
    type(rows_t), allocatable :: rows(:), cells(:)
    type(dual_mesh_t) :: dm
    integer, allocatable :: nl(:), cand(:)
    logical, allocatable :: keep(:)
    integer :: np, maxk, i, n, bad, ng, kb, i0, i1
    real(wp) :: reach(3), grow(3)
    np = b%np
    t%hmin = minval(b%spacing(1:3))
    reach = 0.5_wp*b%spacing(1:3)
    if (allocated(b%tets)) then
      ! median-dual cells: the particle's tetrahedra, their connectivity; a cell reaches
      ! no farther than the longest edge of the mesh from its particle (a rank's region of
      ! a mesh file: the whole mesh's; its smallest height the region's, which the set-up
      ! takes the least of over the ranks)
      call dual_mesh(b, dm)
      t%hmin = dm%hmin
      reach = dm%lmax
      if (allocated(b%mfile)) reach = b%mfile%lmax
    end if
    if (present(box)) then
      ! the cloud of the region (region_reach)
      grow = region_reach(body_rmax(b), reach)
      call folded_cloud(b, c, f, err, reshape([box(:, 1) - grow, box(:, 2) + grow], [3, 2]))
    else
      call folded_cloud(b, c, f, err)
    end if
    if (allocated(err)) return
    t%dims = dims_3d
    if (f%ncg == 3) t%dims = dims_3d_folded
    ng = 3*f%ncg
    ! the cells integrated and kept: with a box, those whose particle lies within the
    ! candidates' reach (rmax + the cell's reach, per axis) of it: a cell's row holds only
    ! particles within that reach of the cell's particle (bins_candidates below), so every
    ! cell touching a particle in the box is kept, and the masses of the particles in the
    ! box are whole (the same sums in the same order); the other cells get their volume
    ! only (whole_masses, dynamic_setup_m, completes the masses of the others)
    allocate(keep(np))
    keep = .true.
    if (present(box)) then
      if (by_supports(b)) then
        ! a region read by the supports near the box (tet_file_m tet_file_region): the
        ! cells whose particle lies within R + l_i of the box, R the largest support of
        ! the box's particles, l_i the longest edge at particle i (its cell's reach):
        ! every cell a particle of the box covers a point of; the region holds every
        ! particle such a cell's rows read
        do i = 1, np
          keep(i) = all(max(box(:, 1) - b%x(:, i), 0.0_wp, b%x(:, i) - box(:, 2)) <= &
            b%mfile%rbox + maxval(b%rho(:, i)/b%support_factor(1:3)))
        end do
      else
        do i = 1, np
          keep(i) = all(b%x(:, i) >= box(:, 1) - (c%rmax(1:3) + reach)) .and. &
            all(b%x(:, i) <= box(:, 2) + (c%rmax(1:3) + reach))
        end do
      end if
    end if
    ! the most particles one cell's points can touch: those within rmax + the cell's reach
    ! (the cloud holds the mirror images too)
    allocate(cand(c%np))
    maxk = 1
    do i = 1, np
      if (.not. keep(i)) cycle
      call bins_candidates(c%bins, b%x(:, i), c%rmax(1:3) + reach, cand, n)
      maxk = max(maxk, n)
    end do
    deallocate(cand)
    ! the arrays of np entries before the blocks: on the heap (when not mapped) the blocks
    ! then lie above them, and gather_rows frees them from the top down
    allocate(t%xq(3, np), t%owner(np), t%wgt(np), t%fix1(np), t%ws(3, np), t%mass(np), &
      t%ptr(np + 1), t%pptr(np + 1), nl(np))
    t%fix1 = .false.
    t%mass = 0.0_wp
    allocate(rows((np + block_np - 1)/block_np), cells(min(block_np, np)))
    bad = 0
    do kb = 1, size(rows)
      i0 = (kb - 1)*block_np + 1
      i1 = min(np, kb*block_np)
      if (allocated(b%tets)) then
        call dual_cell_integrals(b, dm, c, f, i0, maxk, keep(i0:i1), cells(1:i1 - i0 + 1), &
          t%wgt(i0:i1), t%ws(:, i0:i1), bad)
      else
        call cell_integrals(b, c, f, i0, maxk, keep(i0:i1), cells(1:i1 - i0 + 1), &
          t%wgt(i0:i1), t%ws(:, i0:i1), bad)
      end if
      ! (the first block with such a cell stops the build: its largest such particle)
      if (bad > 0) then
        call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined in "// &
          "the cell of particle "//itoa(body_whole(b, bad))//" (too few particles cover "// &
          "a point of it; a larger support_factor mends it)")
        return
      end if
      call pack_rows(cells(1:i1 - i0 + 1), ng, rho0, rows(kb), nl(i0:i1), t%mass, &
        keep(i0:i1))
    end do
    ! (the blocks' per-cell rows are freed; the ones below the mmap threshold would stay
    ! resident on the heap under the CSR arrays below: 15-20 MiB of a rank's set-up peak
    ! on the weak bench, more on some ranks than others)
    call heap_return()
    t%xq = b%x
    t%owner = [(i, i = 1, np)]
    t%ptr(1) = 1
    do i = 1, np
      t%ptr(i + 1) = t%ptr(i) + nl(i)
    end do
    deallocate(nl)
    n = t%ptr(np + 1) - 1
    allocate(t%nbr(n), t%g(ng, n), t%gs(ng, n), t%h(n))
    t%h = 0.0_wp
    call gather_rows(rows, t%ptr, t%nbr, t%g, t%gs)
    call positions_3d(b, c, f, keep, t, err)
  end subroutine scni_tables_3d

  !> One block's cells packed into r (each freed once copied): the entries of the kept
  !! cells in order (ids, gradients g, half-cell differences gs; nl of each cell, 0 for a
  !! cell not kept), the lumped masses rho0 \int N dV of every cell added to mass cell by
  !! cell, entry by entry, as the whole table's rows give them (the same sums in the same
  !! order).
  subroutine pack_rows(cells, ng, rho0, r, nl, mass, keep)
    type(rows_t), intent(inout) :: cells(:)
    integer, intent(in) :: ng
    real(wp), intent(in) :: rho0
    type(rows_t), intent(out) :: r
    integer, intent(out) :: nl(:)
    real(wp), intent(inout) :: mass(:)
    logical, intent(in) :: keep(:)
    integer :: j, k, e
    do j = 1, size(cells)
      nl(j) = 0
      if (keep(j)) nl(j) = size(cells(j)%id)
    end do
    allocate(r%id(sum(nl)), r%a(ng, sum(nl)), r%b(ng, sum(nl)))
    e = 0
    do j = 1, size(cells)
      do k = 1, size(cells(j)%id)
        mass(cells(j)%id(k)) = mass(cells(j)%id(k)) + rho0*cells(j)%m(k)
        if (.not. keep(j)) cycle
        e = e + 1
        r%id(e) = cells(j)%id(k)
        r%a(:, e) = cells(j)%a(:, k)
        r%b(:, e) = cells(j)%b(:, k)
      end do
      deallocate(cells(j)%id, cells(j)%a, cells(j)%b, cells(j)%m)
    end do
  end subroutine pack_rows

  !> The packed blocks copied into the CSR arrays (ptr over the particles, block k holding
  !! rows (k - 1) block_np + 1, ...): ids into nbr, a into va, b into vb when present; each
  !! block freed once copied, the last first, so that blocks on the heap go back to the
  !! system as its top shrinks (mapped ones go back as they are freed) and the copy's peak
  !! stays near one set of tables.
  subroutine gather_rows(rows, ptr, nbr, va, vb)
    type(rows_t), intent(inout) :: rows(:)
    integer, intent(in) :: ptr(:)
    integer, intent(out) :: nbr(:)
    real(wp), intent(out) :: va(:, :)
    real(wp), intent(out), optional :: vb(:, :)
    integer :: kb, e0, n
    do kb = size(rows), 1, -1
      e0 = ptr((kb - 1)*block_np + 1) - 1
      n = size(rows(kb)%id)
      nbr(e0 + 1:e0 + n) = rows(kb)%id
      va(:, e0 + 1:e0 + n) = rows(kb)%a
      if (present(vb)) vb(:, e0 + 1:e0 + n) = rows(kb)%b
      deallocate(rows(kb)%id, rows(kb)%a)
      if (allocated(rows(kb)%b)) deallocate(rows(kb)%b)
    end do
  end subroutine gather_rows

  !> For the particles i = i0, ..., i0 + size(cells) - 1 (a block; cell j = i - i0 + 1):
  !! the volume of its cell (vol(j)), the unnormalised face integrals \oint N_I n dS (gl)
  !! and volume integrals \int N_I dV (ml) of the particles I touching it (idl, nl), then
  !! gl divided by the volume; the half cells' smoothed gradients minus the cell's (sl) and
  !! their weights (ws); the cell's row into cells(j) (id, a = gl, b = sl, m = ml). gl, ml,
  !! sl, idl are one thread's (cell_work_t), for one cell of at most maxk candidates: they
  !! stay in its caches (a block's padded cells did not: 5-10% slower). Each cell is its
  !! own (any thread count gives the same). bad: the largest particle whose cell has a
  !! point where the shape functions are undefined (0: none).
  subroutine cell_integrals(b, c, f, i0, maxk, keep, cells, vol, ws, bad)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    integer, intent(in) :: i0, maxk
    logical, intent(in) :: keep(:)
    type(rows_t), intent(inout) :: cells(:)
    real(wp), intent(out) :: vol(:), ws(:, :)
    integer, intent(inout) :: bad
    real(wp) :: cv(2, max_cv), half(3), o(3), za, zb, zm, area, vh(3), hcs(2, max_cv, 2)
    real(wp) :: xg(2, 3*max_cv), wg(3*max_cv), lo(2), hi(2), xc(2, max_cv), wc(max_cv)
    integer :: ncv, ngp, i, j, q, r, np, dir, nhs(2), nc, ic
    type(cell_work_t) :: w
    real(wp), parameter :: big = huge(1.0_wp)/4.0_wp
    np = b%np
    half = 0.5_wp*b%spacing(1:3)
    !$omp parallel default(none) shared(b, c, f, i0, maxk, keep, cells, vol, ws, half, np) &
    !$omp private(cv, o, za, zb, zm, area, vh, hcs, xg, wg, lo, hi, xc, wc, ncv, ngp, &
    !$omp i, ic, q, r, dir, nhs, nc, w) reduction(max: bad)
    call work_init(w, np, c%np, 3*f%ncg, maxk)
    ! (chunks of 16: a block of 4096 cells still keeps 16 threads busy to its end)
    !$omp do schedule(dynamic, 16)
    do j = 1, size(cells)
      i = i0 + j - 1
      w%nl = 0
      o = b%x(:, i)
      if (allocated(b%cell_ptr)) then
        ic = body_cell(b, i)
        ncv = min(b%cell_ptr(ic + 1) - b%cell_ptr(ic), max_cv)
        cv(:, 1:ncv) = b%cell_xy(:, b%cell_ptr(ic):b%cell_ptr(ic) + ncv - 1)
      else
        call clip_polygon_box(b%geom%v, o(1:2) - half(1:2), o(1:2) + half(1:2), cv, ncv)
      end if
      za = max(b%geom%z0, o(3) - half(3))
      zb = min(b%geom%z1, o(3) + half(3))
      call cell_area_points(cv, ncv, xg, wg, ngp)
      area = sum(wg(1:ngp))
      vol(j) = area*(zb - za)
      ! (a cell not kept: its volume only, an empty row)
      if (.not. keep(j)) then
        call finish_cell(f%ncg, vol(j), zero3, w, ws(:, j), cells(j))
        cycle
      end if
      ! the particles whose supports may reach the prism (every point below is in it)
      call cell_candidates(c, [minval(cv(1, 1:ncv)), minval(cv(2, 1:ncv)), za], &
        [maxval(cv(1, 1:ncv)), maxval(cv(2, 1:ncv)), zb], w)
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
            zero3, i, w, bad)
        end do
      end do
      ! the end faces, n = -e3 at za and +e3 at zb (the top face is the X3 half cell's too)
      do q = 1, ngp
        call shape_at(c, f, [xg(:, q), za], 0.0_wp, [0.0_wp, 0.0_wp, -wg(q)], zero3, i, w, bad)
        call shape_at(c, f, [xg(:, q), zb], 0.0_wp, [0.0_wp, 0.0_wp, wg(q)], &
          merge([0.0_wp, 0.0_wp, wg(q)], zero3, zb > zm), i, w, bad)
      end do
      ! the side faces; an edge that is whole in a half cell is that half cell's face too
      call side_faces(c, f, cv, ncv, za, zb, hcs, nhs, .true., i, w, bad)
      ! the half cells' own faces: their edges that are not whole edges of the cell (the
      ! cut at x = X1 or y = X2, pieces of edges it splits)
      do dir = 1, 2
        vh(dir) = 0.0_wp
        if (nhs(dir) < 3) cycle
        ! (its volume only: the shoelace area, no quadrature points)
        vh(dir) = polygon_area(hcs(:, :, dir), nhs(dir))*(zb - za)
        call half_faces(c, f, hcs(:, :, dir), nhs(dir), cv, ncv, dir, za, zb, i, w, bad)
      end do
      ! the half cell along X3: the polygon times [zm, zb]; its face at zm (-e3)
      vh(3) = area*(zb - zm)
      if (zb > zm) then
        do q = 1, ngp
          call shape_at(c, f, [xg(:, q), zm], 0.0_wp, zero3, [0.0_wp, 0.0_wp, -wg(q)], i, w, bad)
        end do
      end if
      call finish_cell(f%ncg, vol(j), vh, w, ws(:, j), cells(j))
    end do
    !$omp end do
    !$omp end parallel
  end subroutine cell_integrals

  !> The connectivity of body b's tetrahedra b%tets for their median-dual cells
  !! (dual_mesh_t).
  subroutine dual_mesh(b, dm)
    type(body_t), intent(in) :: b
    type(dual_mesh_t), intent(out) :: dm
    type(tet4_mesh_t) :: mesh
    real(wp) :: xt(3, 4), v, amax
    integer :: ne, e, k, l
    ne = size(b%tets, 2)
    call incidence_csr(b%tets, b%np, dm%ptr, dm%idx)
    mesh%ne = ne
    mesh%tet = b%tets
    call tet4_face_neighbours(mesh, b%np, dm%nbr)
    dm%hmin = huge(1.0_wp)
    dm%lmax = 0.0_wp
    do e = 1, ne
      xt = b%x(:, b%tets(:, e))
      v = abs(tet_volume6(xt))/6.0_wp
      ! the smallest height, 3 V over the largest face
      amax = 0.0_wp
      do k = 1, 4
        amax = max(amax, norm2(face_area(xt, k)))
        do l = k + 1, 4
          dm%lmax = max(dm%lmax, norm2(xt(:, l) - xt(:, k)))
        end do
      end do
      dm%hmin = min(dm%hmin, 3.0_wp*v/amax)
    end do
  end subroutine dual_mesh

  !> Six times the signed volume of the tetrahedron xt (3, 4).
  pure real(wp) function tet_volume6(xt) result(v6)
    real(wp), intent(in) :: xt(3, 4)
    v6 = dot_product(xt(:, 2) - xt(:, 1), cross(xt(:, 3) - xt(:, 1), xt(:, 4) - xt(:, 1)))
  end function tet_volume6

  !> The area vector of the face of xt (3, 4) opposite its node k (either orientation).
  pure function face_area(xt, k) result(a)
    real(wp), intent(in) :: xt(3, 4)
    integer, intent(in) :: k
    real(wp) :: a(3), p(3, 3)
    p = xt(:, pack([1, 2, 3, 4], [1, 2, 3, 4] /= k))
    a = 0.5_wp*cross(p(:, 2) - p(:, 1), p(:, 3) - p(:, 1))
  end function face_area

  !> The centroid of the face of xt (3, 4) opposite its node k, its nodes summed in the
  !! tetrahedron's order (the same bits from every particle's cell).
  pure function face_centroid(xt, k) result(p)
    real(wp), intent(in) :: xt(3, 4)
    integer, intent(in) :: k
    real(wp) :: p(3)
    integer :: l
    p = 0.0_wp
    do l = 1, 4
      if (l /= k) p = p + xt(:, l)
    end do
    p = p/3.0_wp
  end function face_centroid

  !> The midpoint of the edge of xt between its nodes k and l, in the tetrahedron's order.
  pure function edge_midpoint(xt, k, l) result(p)
    real(wp), intent(in) :: xt(3, 4)
    integer, intent(in) :: k, l
    real(wp) :: p(3)
    p = 0.5_wp*(xt(:, min(k, l)) + xt(:, max(k, l)))
  end function edge_midpoint

  !> As cell_integrals, for a body of tetrahedra (b%tets): particle i's cell is its
  !! median-dual cell, the union over its tetrahedra of the piece where its barycentric
  !! coordinate is the largest (bounded by the edge midpoints, the face centroids and the
  !! centroid: a quarter of the tetrahedron's volume, convex), so the cells tile the mesh.
  !! Per piece:
  !!  - the volume integral: one point, the piece's centroid (exact for linear N; the
  !!    masses are row sums, their total exact by the partition of unity);
  !!  - the faces between the cell and its neighbours' cells: for each edge at the particle,
  !!    the two triangles (edge midpoint, face centroid, centroid), the normal towards the
  !!    edge's other node; computed from the tetrahedron's nodes in its own order, so the
  !!    neighbour's cell integrates the same triangle at the same points with the opposite
  !!    normal, and a uniform stress leaves no force on an interior particle;
  !!  - on the mesh's boundary, the piece's part of the boundary face (the particle, two
  !!    edge midpoints, the face centroid: two triangles), the face's outward normal.
  !! One point per triangle, its centroid: exact for linear N, which is what the patch
  !! test needs; a cell has some 60 to 150 triangles, each small beside the supports (the
  !! rule at 2/3, 1/6, 1/6 of the vertices, three points, moved the 3D Hertz sphere's
  !! measures by 0.1% at most and took 2.4 times the set-up: doc/verification.md).
  !! The half cell along X_j (the sub-cell stabilization) is the union of the pieces whose
  !! tetrahedron's centroid lies beyond the particle along X_j: its faces are those of the
  !! cell on its pieces and the pieces' faces towards a piece of the same cell outside it.
  subroutine dual_cell_integrals(b, dm, c, f, i0, maxk, keep, cells, vol, ws, bad)
    type(body_t), intent(in) :: b
    type(dual_mesh_t), intent(in) :: dm
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    integer, intent(in) :: i0, maxk
    logical, intent(in) :: keep(:)
    type(rows_t), intent(inout) :: cells(:)
    real(wp), intent(out) :: vol(:), ws(:, :)
    integer, intent(inout) :: bad
    real(wp) :: xt(3, 4), ct(3), cn(3), v, vh(3), mask(3), hm(3), fc(3), pm(3), lo(3), hi(3)
    integer :: i, j, k, e, en, ka, q, r, s, q1, q2, np
    logical :: inside(3)
    type(cell_work_t) :: w
    np = b%np
    !$omp parallel default(none) shared(b, dm, c, f, i0, maxk, keep, cells, vol, ws, np) &
    !$omp private(xt, ct, cn, v, vh, mask, hm, fc, pm, lo, hi, i, k, e, en, ka, q, r, s, q1, q2, &
    !$omp inside, w) reduction(max: bad)
    call work_init(w, np, c%np, 3*f%ncg, maxk)
    !$omp do schedule(dynamic, 16)
    do j = 1, size(cells)
      i = i0 + j - 1
      w%nl = 0
      vol(j) = 0.0_wp
      vh = 0.0_wp
      ! (a cell not kept: its volume only, summed as below, an empty row)
      if (.not. keep(j)) then
        do k = dm%ptr(i), dm%ptr(i + 1) - 1
          xt = b%x(:, b%tets(:, dm%idx(k)))
          vol(j) = vol(j) + 0.25_wp*(abs(tet_volume6(xt))/6.0_wp)
        end do
        call finish_cell(f%ncg, vol(j), vh, w, ws(:, j), cells(j))
        cycle
      end if
      ! the particles whose supports may reach the cell (it lies in its tetrahedra)
      lo = b%x(:, i)
      hi = b%x(:, i)
      do k = dm%ptr(i), dm%ptr(i + 1) - 1
        do q = 1, 4
          lo = min(lo, b%x(:, b%tets(q, dm%idx(k))))
          hi = max(hi, b%x(:, b%tets(q, dm%idx(k))))
        end do
      end do
      call cell_candidates(c, lo, hi, w)
      do k = dm%ptr(i), dm%ptr(i + 1) - 1
        e = dm%idx(k)
        xt = b%x(:, b%tets(:, e))
        ka = findloc(b%tets(:, e), i, 1)
        v = abs(tet_volume6(xt))/6.0_wp
        ct = 0.25_wp*((xt(:, 1) + xt(:, 2)) + (xt(:, 3) + xt(:, 4)))
        inside = ct > xt(:, ka)
        mask = merge(1.0_wp, 0.0_wp, inside)
        vol(j) = vol(j) + 0.25_wp*v
        vh = vh + 0.25_wp*v*mask
        pm = piece_own*xt(:, ka) + piece_other*(sum(xt, dim=2) - xt(:, ka))
        call shape_at(c, f, pm, 0.25_wp*v, zero3, zero3, i, w, bad)
        ! the faces towards the neighbours' cells: edge (ka, q), in the faces (ka, q, r)
        do q = 1, 4
          if (q == ka) cycle
          do r = 1, 4
            if (r == ka .or. r == q) cycle
            s = 10 - ka - q - r
            call dual_triangle(c, f, edge_midpoint(xt, ka, q), face_centroid(xt, s), ct, &
              xt(:, q) - xt(:, ka), 1.0_wp, mask, i, w, bad)
          end do
        end do
        ! the tetrahedron's faces at the particle (opposite its node r): the body's
        ! boundary, or (for the half cells only) a face towards a piece outside the half
        do r = 1, 4
          if (r == ka) cycle
          en = dm%nbr(r, e)
          if (en == 0) then
            hm = mask
          else
            cn = 0.25_wp*((b%x(:, b%tets(1, en)) + b%x(:, b%tets(2, en))) + &
              (b%x(:, b%tets(3, en)) + b%x(:, b%tets(4, en))))
            hm = merge(1.0_wp, 0.0_wp, inside .and. .not. cn > xt(:, ka))
            if (all(hm == 0.0_wp)) cycle
          end if
          fc = face_centroid(xt, r)
          q1 = merge(1, 2, ka /= 1 .and. r /= 1)
          if (q1 == 2 .and. (ka == 2 .or. r == 2)) q1 = 3
          q2 = 10 - ka - r - q1
          call dual_triangle(c, f, xt(:, ka), edge_midpoint(xt, ka, q1), fc, fc - xt(:, r), &
            merge(1.0_wp, 0.0_wp, en == 0), hm, i, w, bad)
          call dual_triangle(c, f, xt(:, ka), fc, edge_midpoint(xt, ka, q2), fc - xt(:, r), &
            merge(1.0_wp, 0.0_wp, en == 0), hm, i, w, bad)
        end do
      end do
      call finish_cell(f%ncg, vol(j), vh, w, ws(:, j), cells(j))
    end do
    !$omp end do
    !$omp end parallel
  end subroutine dual_cell_integrals

  !> The triangle p1, p2, p3 of a cell's boundary, its area vector turned to have a
  !! positive component along dir (outward), at one point, its centroid (summed in the
  !! order given: the same point from each cell that has it): N_I n dA times wc into the
  !! cell's face integrals, times wh(j) into the half cell j's.
  subroutine dual_triangle(c, f, p1, p2, p3, dir, wc, wh, i, w, bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: p1(3), p2(3), p3(3), dir(3), wc, wh(3)
    integer, intent(in) :: i
    type(cell_work_t), intent(inout) :: w
    integer, intent(inout) :: bad
    real(wp) :: a(3)
    a = 0.5_wp*cross(p2 - p1, p3 - p1)
    if (dot_product(a, dir) < 0.0_wp) a = -a
    call shape_at(c, f, (p1 + p2 + p3)/3.0_wp, 0.0_wp, wc*a, wh*a, i, w, bad)
  end subroutine dual_triangle

  !> The candidates of w (cloud_candidates) for a cell in the box [lo, hi]: the box grown
  !! by a relative 1e-9 of its size and of the largest support, so that rounding in the
  !! test cannot drop a particle that covers a point of the cell.
  subroutine cell_candidates(c, lo, hi, w)
    type(rk_cloud_t), intent(in) :: c
    real(wp), intent(in) :: lo(3), hi(3)
    type(cell_work_t), intent(inout) :: w
    real(wp) :: r(3)
    r = 0.5_wp*(hi - lo)*(1.0_wp + 1.0e-9_wp) + 1.0e-9_wp*maxval(c%rmax)
    call cloud_candidates(c, 0.5_wp*(lo + hi), r, w%cand, w%ncand)
  end subroutine cell_candidates

  !> One thread's work space (cell_work_t) over np particles and a cloud of ncloud (with
  !! the mirror images), ng rows of gradients, at most maxk particles touching a cell.
  subroutine work_init(w, np, ncloud, ng, maxk)
    type(cell_work_t), intent(out) :: w
    integer, intent(in) :: np, ncloud, ng, maxk
    allocate(w%slot(np), w%idl(maxk), w%cand(ncloud), w%gl(ng, maxk), w%ml(maxk), &
      w%sl(ng, maxk))
    w%slot = 0
  end subroutine work_init

  !> Cell j's row from its unnormalised integrals (cell_integrals, dual_cell_integrals):
  !! the face integrals gl divided by the cell's volume vol (the smoothed gradients); each
  !! half cell's (volume vh(dir), direction dir; rows dir, dir + 3, dir + 6 when the ncg = 3
  !! components are folded) divided by its volume minus the cell's, and its weight
  !! ws(dir) = V_h (1 + V_h/(V_L - V_h)); a half that is (nearly) empty or (nearly) the
  !! whole cell gets none. The nl entries (ids idl, gl, sl and the volume integrals ml) go
  !! into cell, and their slots are cleared.
  subroutine finish_cell(ncg, vol, vh, w, ws, cell)
    integer, intent(in) :: ncg
    real(wp), intent(in) :: vol, vh(3)
    type(cell_work_t), intent(inout) :: w
    real(wp), intent(out) :: ws(3)
    type(rows_t), intent(inout) :: cell
    integer :: dir, q, nl
    nl = w%nl
    if (vol > 0.0_wp) w%gl(:, 1:nl) = w%gl(:, 1:nl)/vol
    do dir = 1, 3
      if (vh(dir) > empty_half*vol .and. vol - vh(dir) > empty_half*vol) then
        do q = dir, 3*ncg, 3
          w%sl(q, 1:nl) = w%sl(q, 1:nl)/vh(dir) - w%gl(q, 1:nl)
        end do
        ws(dir) = vh(dir)*(1.0_wp + vh(dir)/(vol - vh(dir)))
      else
        do q = dir, 3*ncg, 3
          w%sl(q, 1:nl) = 0.0_wp
        end do
        ws(dir) = 0.0_wp
      end if
    end do
    allocate(cell%id(nl), cell%a(3*ncg, nl), cell%b(3*ncg, nl), cell%m(nl))
    cell%id = w%idl(1:nl)
    cell%a = w%gl(:, 1:nl)
    cell%b = w%sl(:, 1:nl)
    cell%m = w%ml(1:nl)
    do q = 1, nl
      w%slot(w%idl(q)) = 0
    end do
  end subroutine finish_cell

  !> The side faces of the prism polygon cv (ncv) x [za, zb], 2 x 2 Gauss points each:
  !! N_I n dS into gl (the cell), and N_I n_j dS into sl(j) where the edge is whole in the
  !! half cell j (hcs(:, :, j), nhs(j): an edge of it with the same two vertices).
  subroutine side_faces(c, f, cv, ncv, za, zb, hcs, nhs, whole, i, w, bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: cv(:, :), za, zb, hcs(:, :, :)
    integer, intent(in) :: ncv, nhs(2), i
    logical, intent(in) :: whole
    type(cell_work_t), intent(inout) :: w
    integer, intent(inout) :: bad
    real(wp) :: e(2), len_e, nrm(3), wq, p(3), hmask(3)
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
      wq = 0.25_wp*len_e*(zb - za)
      do q = 1, 2
        do r = 1, 2
          p = [cv(:, k) + gx(q)*e, za + gx(r)*(zb - za)]
          call shape_at(c, f, p, 0.0_wp, wq*nrm, wq*nrm*hmask, i, w, bad)
        end do
      end do
    end do
  end subroutine side_faces

  !> The faces of the half cell hc (nhc) x [za, zb] along X_dir that are not whole edges of
  !! the cell cv (those side_faces added): N_I n_dir dS into sl(dir), 2 x 2 Gauss points.
  subroutine half_faces(c, f, hc, nhc, cv, ncv, dir, za, zb, i, w, bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: hc(:, :), cv(:, :), za, zb
    integer, intent(in) :: nhc, ncv, dir, i
    type(cell_work_t), intent(inout) :: w
    integer, intent(inout) :: bad
    real(wp) :: e(2), len_e, nrm(3), wq, p(3)
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
      wq = 0.25_wp*len_e*(zb - za)
      do q = 1, 2
        do r = 1, 2
          p = [hc(:, k) + gx(q)*e, za + gx(r)*(zb - za)]
          call shape_at(c, f, p, 0.0_wp, zero3, wq*nrm, i, w, bad)
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
  !! and wh N_I to sl (a half cell's) of cell j's slots (particle i's cell), for every
  !! particle I whose shape function reaches pp; folded (f%ncg = 3): per component c, rows
  !! 3 (c - 1) + 1..3, an image's N added to its twin's with the component's sign. bad: i
  !! when they are undefined there.
  subroutine shape_at(c, f, pp, wm, wn, wh, i, w, bad)
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    real(wp), intent(in) :: pp(3), wm, wn(3), wh(3)
    integer, intent(in) :: i
    type(cell_work_t), intent(inout) :: w
    integer, intent(inout) :: bad
    real(wp) :: n(max_nb)
    integer :: ids(max_nb), nnb, kk, jj, s, cc
    logical :: ok
    call cloud_shape_values(c, pp, nnb, ids, n, ok, w%cand(1:w%ncand))
    if (.not. ok) then
      bad = max(bad, i)
      return
    end if
    do kk = 1, nnb
      jj = f%twin(ids(kk))
      s = w%slot(jj)
      if (s == 0) then
        w%nl = w%nl + 1
        s = w%nl
        w%slot(jj) = s
        w%idl(s) = jj
        w%gl(:, s) = 0.0_wp
        w%ml(s) = 0.0_wp
        w%sl(:, s) = 0.0_wp
      end if
      w%ml(s) = w%ml(s) + wm*n(kk)
      if (f%ncg == 1) then
        w%gl(:, s) = w%gl(:, s) + wn*n(kk)
        w%sl(:, s) = w%sl(:, s) + wh*n(kk)
      else
        do cc = 1, 3
          w%gl(3*cc - 2:3*cc, s) = w%gl(3*cc - 2:3*cc, s) + f%sgn(cc, ids(kk))*wn*n(kk)
          w%sl(3*cc - 2:3*cc, s) = w%sl(3*cc - 2:3*cc, s) + f%sgn(cc, ids(kk))*wh*n(kk)
        end do
      end if
    end do
  end subroutine shape_at

  !> N_I(X_J) for the physical positions x_J = X_J + sum_I N_I(X_J) d_I (once: the
  !! components share it), block by block as the cells (scni_tables_3d); t%pptr is
  !! allocated. Only the particles whose cells are kept (scni_tables_3d) get their row.
  subroutine positions_3d(b, c, f, keep, t, err)
    type(body_t), intent(in) :: b
    type(rk_cloud_t), intent(in) :: c
    type(fold_t), intent(in) :: f
    logical, intent(in) :: keep(:)
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    type(rows_t), allocatable :: rows(:)
    integer, allocatable :: cnt(:), idj(:, :)
    real(wp), allocatable :: nj(:, :, :)
    real(wp) :: n(max_nb)
    integer :: ids(max_nb), nnb, j, k, e, bad, m, jj, s, kb, i0, i1, l
    logical :: ok
    allocate(cnt(b%np), idj(max_nb, min(block_np, b%np)), nj(f%ncg, max_nb, min(block_np, b%np)))
    allocate(rows((b%np + block_np - 1)/block_np))
    do kb = 1, size(rows)
      i0 = (kb - 1)*block_np + 1
      i1 = min(b%np, kb*block_np)
      bad = 0
      !$omp parallel do default(none) shared(b, c, f, keep, cnt, idj, nj, i0, i1) &
      !$omp private(n, ids, nnb, ok, k, m, jj, s, l) reduction(max: bad) schedule(dynamic, 16)
      do j = i0, i1
        l = j - i0 + 1
        ! (a particle whose cell is not kept: no row, as its cell has none)
        cnt(j) = 0
        if (.not. keep(j)) cycle
        call cloud_shape_values(c, b%x(:, j), nnb, ids, n, ok)
        if (.not. ok) bad = max(bad, j)
        ! images folded onto their twins (the sign of each component)
        m = 0
        do k = 1, nnb
          jj = f%twin(ids(k))
          do s = 1, m
            if (idj(s, l) == jj) exit
          end do
          if (s > m) then
            m = m + 1
            s = m
            idj(s, l) = jj
            nj(:, s, l) = 0.0_wp
          end if
          if (f%ncg == 1) then
            nj(1, s, l) = nj(1, s, l) + n(k)
          else
            nj(:, s, l) = nj(:, s, l) + f%sgn(:, ids(k))*n(k)
          end if
        end do
        cnt(j) = m
      end do
      !$omp end parallel do
      if (bad > 0) then
        call set_error(err, "body '"//trim(b%name)//"': RK shape functions undefined at "// &
          "particle "//itoa(body_whole(b, bad)))
        return
      end if
      allocate(rows(kb)%id(sum(cnt(i0:i1))), rows(kb)%a(f%ncg, sum(cnt(i0:i1))))
      e = 0
      do j = i0, i1
        do k = 1, cnt(j)
          e = e + 1
          rows(kb)%id(e) = idj(k, j - i0 + 1)
          rows(kb)%a(:, e) = nj(:, k, j - i0 + 1)
        end do
      end do
    end do
    deallocate(idj, nj)
    t%pptr(1) = 1
    do j = 1, b%np
      t%pptr(j + 1) = t%pptr(j) + cnt(j)
    end do
    allocate(t%pnbr(t%pptr(b%np + 1) - 1), t%pn(t%dims%npos, t%pptr(b%np + 1) - 1))
    call gather_rows(rows, t%pptr, t%pnbr, t%pn)
  end subroutine positions_3d
end module rkpm_tl3d_m
