!> Builds the bodies a deck describes (generators, particle files, or gmsh scripts meshed in
!! memory), then checks that each is an admissible discretization for its window and basis
!! (Theorem 3.1): the moment matrix must be non-singular everywhere in the body. On a lattice
!! the smallest working support_factor is found by scanning a lattice patch, so the error can
!! name it. A gmsh script (shape = 'geo') becomes the arrays a particle file of
!! tools/mesh_body.py holds (mesh_cells_m) and then takes the particle file's path.
module body_setup_m
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use kinds_m, only: wp, pi
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use body_m, only: body_t, max_cell_vertices, body_whole, mesh_file_t
  use deck_m, only: deck_t, body_spec_t, body_count_var, body_place_var, body_make_vars
  use basis_m, only: mmax, basis_size
  use generators_m, only: make_segment, make_rectangle, make_polygon, make_annulus, make_disk, &
    lattice_cells_explicit, extrude_body, extrude_pick, body_pick, &
    make_from_arrays, set_supports, perturb_interior, annulus_supports, mean_spacing
  use rk_cloud_m, only: rk_cloud_t, cloud_init, cloud_moment
  use moment_matrix_m, only: chol_small
  use kinds_m, only: i64
  use rank_comm_m, only: share_first, rank_comm_t
  use hdf5_io_m, only: read_particle_file_h5, h5file_t, h5_open_read, h5_close, h5_has, &
    h5_shape, h5_read, h5_create, h5_group, h5_write, h5_attr
  use detection_m, only: body_cloud, body_plateau
  use geometry_m, only: geom_none, geom_segment, geom_polygon, geom_annulus, geom_prism, &
    geom_cylinder, signed_distance
  use neighbour_bins_m, only: bins_t, bins_build, bins_candidates
  use rk_cloud_m, only: cloud_det
  use cst4_m, only: cst4_mesh_t, cst4_rectangle, cst4_annulus
  use mesh_cells_m, only: mesh_from_tags, mesh_body_arrays, tet_volume, mesh_index
  use tet4_m, only: tet4_mesh_t, tet4_extruded, tet4_boundary_faces, extruded_tets, &
    tet4_section
  use gmsh_mesh_m, only: gmsh_mesh_model
  use confine_m, only: confine_limits_t
  use log_m, only: log_print
  use tri_file_m, only: tri_file_share
  use tet_file_m, only: tet_file_share, tet_file_region, volume_spacing, mesh_index_t, &
    read_index, node_outside, tet_outside, file_error
  implicit none
  private
  public :: build_bodies, build_body, lattice_admissible, min_support_factor
  public :: read_particle_columns, tet_mesh_body, geo_mesh_file, file_slab, plane_facts_file

  !> Relative pivot below which M counts as singular in the admissibility checks: far above
  !! round-off (1e-16) and far below the weakest genuine pivot of an admissible lattice
  !! (about 1e-6 for a support factor 1% above the Theorem 3.1 limit).
  real(wp), parameter :: pivot_tol = 1.0e-10_wp
  !> Two particles of a file closer than this fraction of the nominal spacing coincide.
  real(wp), parameter :: coincide_tol = 1.0e-3_wp
  !> A particle of one body deeper than this fraction of the smaller nominal spacing inside
  !! another body's region at t = 0 makes the bodies overlap.
  real(wp), parameter :: overlap_tol = 1.0e-2_wp
  !> Without an exact geometry (a particle file), a point counts as inside a body where its
  !! det(M) reaches this fraction of the interior plateau: only a point surrounded by the
  !! body's particles on every side gets there, about half a support inside.
  real(wp), parameter :: overlap_plateau = 0.5_wp
  !> The particle volumes of a file may add up to at most this multiple of the area (volume)
  !! of the box around the particles grown by one spacing.
  real(wp), parameter :: volume_excess = 4.0_wp
  !> A sector's span within this of 360 (degrees, as the deck gives it) is a full ring:
  !! decks give whole or decimal degrees, and no meant sector is within 1e-9 degree of one.
  real(wp), parameter :: full_turn_deg_tol = 1.0e-9_wp

contains

  !> Build and check every body of the deck.
  subroutine build_bodies(deck, bodies, err, share, per_part, mesh_files, comm)
    type(deck_t), intent(in) :: deck
    type(body_t), allocatable, intent(out) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks] of mfcd_mpi, and the bodies made as each rank's share only (an extruded
    !! body a rank's set-up makes its region of from the recipe: dynamic_setup_m
    !! body_per_part): the whole body is never made on a rank (its checks at the rank's
    !! share, so that the ranks may find different errors)
    integer, intent(in), optional :: share(2)
    logical, intent(in), optional :: per_part(:)
    !> the mesh file a gmsh script (shape 'geo') was meshed into once (geo_mesh_file, by
    !! one rank): in 3D (with per_part) read per part as a mesh file is, in 2D read whole
    !! by each rank; '' for other bodies
    character(len=*), intent(in), optional :: mesh_files(:)
    !> the ranks (with share): a mesh file's whole checks shared over them (tet_file_m),
    !! and an error of any rank's body ends every rank's building before the next body's
    !! collective checks (the ranks then agree on the error: mfcd_mpi)
    class(rank_comm_t), intent(inout), optional :: comm
    integer :: k
    real(wp) :: failed(1)
    logical :: part
    allocate(bodies(deck%nbodies))
    do k = 1, deck%nbodies
      part = .false.
      if (present(per_part)) part = per_part(k)
      if (part .and. present(mesh_files)) then
        call build_body(deck, deck%bodies(k), k, bodies(k), err, share, trim(mesh_files(k)), &
          comm)
      else if (part) then
        call build_body(deck, deck%bodies(k), k, bodies(k), err, share, comm=comm)
      else if (present(mesh_files)) then
        ! (a 2D gmsh script one rank meshed into a file: each rank reads it whole)
        call build_body(deck, deck%bodies(k), k, bodies(k), err, mesh_file=trim(mesh_files(k)))
      else
        call build_body(deck, deck%bodies(k), k, bodies(k), err)
      end if
      if (present(comm)) then
        failed = merge(1.0_wp, 0.0_wp, allocated(err))
        call comm%max_real(failed)
        if (failed(1) > 0.0_wp) return
      end if
      if (allocated(err)) return
    end do
    if (deck%run%mode /= 'dynamic') return
    call check_surfaces(deck, bodies, err)
    if (.not. allocated(err)) call check_overlaps(deck, bodies, err)
  end subroutine build_bodies

  !> Contact needs a surface polyline on the master, and on the slave too when the master
  !! deforms (the second pass of eq. 28 swaps the roles). Only a particle file without loop
  !! and order columns lacks one.
  subroutine check_surfaces(deck, bodies, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, im, is
    character(len=:), allocatable :: grp
    do k = 1, deck%ncontacts
      im = deck%contacts(k)%imaster
      is = deck%contacts(k)%islave
      grp = "deck '"//deck%path//"', group &contact (contact "//itoa(k)//"), variable "
      if (bodies(im)%ndim == 3) then
        ! a 3D body's surface is its facets (extruded bodies; contact_pair_m checks them)
        if (.not. allocated(bodies(im)%facets)) then
          call set_error(err, grp//"master = '"//trim(bodies(im)%name)//"': the 3D body "// &
            "has no boundary surface (a cylinder's sector, a particle file), so contact "// &
            "has nothing to measure the gap to; make the master a 'box', an extruded "// &
            "'polygon' or a whole 'cylinder'")
          return
        end if
        cycle
      end if
      if (size(bodies(im)%loop_idx) < 2) then
        call set_error(err, grp//"master = '"//trim(bodies(im)%name)//"': the body has "// &
          "no surface polyline (a particle file without the loop and order columns), so "// &
          "contact has nothing to measure the gap to; add those columns to its file")
        return
      end if
      if (deck%bodies(im)%role == 'deformable' .and. size(bodies(is)%loop_idx) < 2) then
        call set_error(err, grp//"slave = '"//trim(bodies(is)%name)//"': the master '"// &
          trim(bodies(im)%name)//"' deforms, so detection runs both ways (eq. 28) and "// &
          "needs the slave's surface too, but the slave has no surface polyline (a "// &
          "particle file without the loop and order columns); add those columns to its "// &
          "file, or make the master rigid")
        return
      end if
    end do
  end subroutine check_surfaces

  !> Bodies must not overlap in the reference configuration: no particle of one body
  !! deeper than overlap_tol x the smaller spacing inside another body, when at least one of
  !! the two deforms (contact would throw them apart in the first steps and the run would
  !! stop on its energy balance). Inside: the exact geometry's signed distance (generated
  !! shapes and FE rectangles); for a particle file, det(M) of that body above
  !! overlap_plateau x its plateau. The particles of deformable bodies are tested first, so
  !! the message names the body that was most likely misplaced (a rigid target stays put).
  subroutine check_overlaps(deck, bodies, err)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t), allocatable :: clouds(:)
    real(wp), allocatable :: plateau(:)
    real(wp) :: tol, depth, lo(2), hi(2)
    integer :: ka, kb, i, hit, pass
    character(len=:), allocatable :: how
    if (any(bodies%ndim /= 2)) return
    allocate(clouds(size(bodies)), plateau(size(bodies)))
    plateau = 0.0_wp
    do kb = 1, size(bodies)
      if (bodies(kb)%geom%kind /= geom_none .or. checked_whole(bodies(kb))) cycle
      call body_cloud(bodies(kb), clouds(kb), err)
      if (allocated(err)) return
      plateau(kb) = body_plateau(bodies(kb), clouds(kb))
    end do
    do pass = 1, 2
      do ka = 1, size(bodies)
        if ((deck%bodies(ka)%role == 'deformable') .neqv. pass == 1) cycle
        do kb = 1, size(bodies)
          if (ka == kb) cycle
          if (deck%bodies(ka)%role /= 'deformable' .and. deck%bodies(kb)%role /= &
            'deformable') cycle
          ! (a rank's share of a plane mesh file holds no cloud of the body: rank 0 checked
          ! the whole bodies against each other, mfcd_mpi)
          if (checked_whole(bodies(kb))) cycle
          associate (a => bodies(ka), b => bodies(kb))
            tol = overlap_tol*min(minval(a%spacing(1:2)), minval(b%spacing(1:2)))
            ! a generated shape may reach up to a spacing beyond its outermost particles
            lo = minval(b%x, dim=2) - maxval(b%spacing(1:2))
            hi = maxval(b%x, dim=2) + maxval(b%spacing(1:2))
            ! (a rank's share of b: its extent is not b's; its exact shape is the test)
            if (b%held_share) then
              lo = -huge(1.0_wp)
              hi = huge(1.0_wp)
            end if
            hit = 0
            depth = 0.0_wp
            ! (a rank's share of a: its particles, numbered row0 ... in the whole body)
            do i = 1, size(a%x, 2)
              if (any(a%x(:, i) < lo) .or. any(a%x(:, i) > hi)) cycle
              if (b%geom%kind /= geom_none) then
                depth = -signed_distance(b%geom, a%x(:, i))
                if (depth > tol) hit = i
              else if (cloud_det(clouds(kb), a%x(:, i)) >= overlap_plateau*plateau(kb)) then
                hit = i
              end if
              if (hit > 0) exit
            end do
            if (hit > 0) then
              how = ''
              if (b%geom%kind /= geom_none) how = ' by '//rtoa(depth)//' m'
              call set_error(err, "deck '"//deck%path//"', group &body (body "//itoa(ka)// &
                ", '"//trim(a%name)//"'), variable "//body_place_var(deck%bodies(ka)%shape)// &
                ": particle "//itoa(hit + max(a%row0, 1) - 1)//" at ("//rtoa(a%x(1, hit))//", "// &
                rtoa(a%x(2, hit))//") lies inside body '"//trim(b%name)//"'"//how// &
                " at t = 0: bodies may touch but not overlap (tolerance "//rtoa(tol)// &
                " m, 1% of the smaller spacing); move or shrink one of them")
              return
            end if
          end associate
        end do
      end do
    end do

  contains

    !> A rank's share of a plane mesh file (tri_file_m), whose whole body rank 0 checked
    pure logical function checked_whole(b)
      type(body_t), intent(in) :: b
      checked_whole = allocated(b%mfile) .and. b%ndim == 2
    end function checked_whole
  end subroutine check_overlaps



  !> One body from its spec; err names deck, group and variable on failure.
  subroutine build_body(deck, s, k, b, err, share, mesh_file, comm)
    type(deck_t), intent(in) :: deck
    type(body_spec_t), intent(in) :: s
    integer, intent(in) :: k
    type(body_t), intent(out) :: b
    type(error_t), allocatable, intent(inout) :: err
    !> [me, nranks]: an extruded body made as rank me's share only (generators_m
    !! extrude_body; build_bodies)
    integer, intent(in), optional :: share(2)
    !> for a gmsh script: the file it was meshed into (geo_mesh_file), read as rank me's
    !! share in 3D (with share), whole in 2D; '' or absent: the script meshed here
    character(len=*), intent(in), optional :: mesh_file
    !> with share: the ranks, over which a mesh file's whole checks are shared (tet_file_m;
    !! collective then), else each rank reads the whole file for them
    class(rank_comm_t), intent(inout), optional :: comm
    character(len=:), allocatable :: where, what
    real(wp), allocatable :: local(:), xs(:, :), vols(:), xy(:, :)
    integer, allocatable :: loop(:), order(:), tri(:, :), ptr(:)
    real(wp) :: dr, dt, fmin
    integer :: nd, i
    logical :: has_tri, has_cells, tets, from_file, geo_file, plane_part
    type(error_t), allocatable :: e2
    type(cst4_mesh_t) :: mesh
    type(body_t) :: b2, ends
    integer :: none(2)
    real(wp) :: nowhere(2)
    logical :: flat
    nd = deck%run%ndim
    where = "deck '"//deck%path//"', group &body (body "//itoa(k)//", '"//trim(s%name)//"')"
    select case (s%shape)
    case ('segment')
      call make_segment(b, s%lo(1), s%hi(1), s%n(1), e2)
    case ('rectangle')
      if (s%discretization == 'fem') then
        ! CST4 elements on the boxes of the n(1) x n(2) lattice; nodes carry the det(M)
        ! cloud with supports from the element sizes (Section 6)
        ! (a rank's share only, body_per_part: made from the lattice's recipe)
        call cst4_rectangle(s%lo(1:2), s%hi(1:2), s%n(1:2) - 1, s%support_factor(1:2), b, &
          mesh, e2, share)
        if (.not. allocated(e2)) call move_alloc(mesh%tri, b%cells)
      else
        ! (a rank's share only, body_per_part: made from the lattice's recipe)
        call make_rectangle(b, s%lo(1:2), s%hi(1:2), s%n(1:2), e2, share)
      end if
    case ('polygon')
      if (nd == 3) then
        ! the polygon in x-y, extruded along z (the 3D L-shaped or notched block)
        call make_polygon(b2, s%vertices(:, 1:s%nvert), s%spacing(1:2), s%origin, e2)
        if (.not. allocated(e2)) call extrude_body(b2, s%extrude(1), s%extrude(2), &
          max(2, nint((s%extrude(2) - s%extrude(1))/s%spacing(3)) + 1), b, e2, share)
        if (.not. allocated(e2)) call tets_if_fem(b2, b, e2)
      else
        ! (a rank's share only, body_per_part: made from the lattice's recipe)
        call make_polygon(b, s%vertices(:, 1:s%nvert), s%spacing(1:2), s%origin, e2, share)
      end if
    case ('box')
      ! a rectangle in x-y extruded along z: n(1) x n(2) x n(3) lattice points
      call make_rectangle(b2, s%lo(1:2), s%hi(1:2), s%n(1:2), e2)
      if (.not. allocated(e2)) call extrude_body(b2, s%lo(3), s%hi(3), s%n(3), b, e2, share)
      if (.not. allocated(e2)) call tets_if_fem(b2, b, e2)
    case ('annulus_sector')
      if (s%discretization == 'fem') then
        ! CST4 elements on the polar boxes of the annulus lattice
        ! (a rank's share only, body_per_part: made from the polar lattice's recipe)
        call cst4_annulus(s%center, s%r_inner, s%r_outer, s%theta_start*pi/180.0_wp, &
          s%theta_end*pi/180.0_wp, s%n(1), s%n(2), b, mesh, e2, share)
        if (.not. allocated(e2)) call move_alloc(mesh%tri, b%cells)
      else
        call make_annulus(b, s%center, s%r_inner, s%r_outer, s%theta_start*pi/180.0_wp, &
          s%theta_end*pi/180.0_wp, s%n(1), s%n(2), e2)
      end if
    case ('disk')
      call make_disk(b, s%center, s%radius, s%spacing(1), e2, s%theta_end*pi/180.0_wp)
    case ('cylinder')
      ! a disk (or its sector) in x-y, its rings and cells, extruded along z
      call make_disk(b2, s%center, s%radius, s%spacing(1), e2, s%theta_end*pi/180.0_wp)
      if (.not. allocated(e2)) call extrude_body(b2, s%extrude(1), s%extrude(2), &
        max(2, nint((s%extrude(2) - s%extrude(1))/s%spacing(3)) + 1), b, e2, share)
      if (.not. allocated(e2)) call tets_if_fem(b2, b, e2)
    case ('file', 'geo')
      from_file = s%shape == 'file' .and. present(share)
      if (s%shape == 'geo' .and. present(mesh_file) .and. present(share) .and. nd == 3) &
        from_file = len(mesh_file) > 0
      plane_part = .false.
      if (present(mesh_file) .and. present(share) .and. nd == 2) plane_part = len(mesh_file) > 0
      if (plane_part .or. from_file) then
        if (plane_part) then
          ! a rank's share of a plane gmsh script's elements (body_per_part): the file
          ! rank 0 meshed it into and built the whole body from, through every serial
          ! check (mfcd_mpi), read per part (tri_file_m): the share's nodes and
          ! triangles, the boundary loops whole, the same bits as the whole body's
          if (s%shape == 'geo') then
            what = "the mesh of '"//trim(s%file)//"'"
            call tri_file_share(mesh_file, what, share(1), share(2), b, local, e2)
          else
            ! a user's plane particle file: its rows from the file, the whole file's facts
            ! from the one rank 0 wrote (plane_facts_file)
            what = "particle file '"//trim(s%file)//"'"
            call tri_file_share(trim(s%file), what, share(1), share(2), b, local, e2, &
              facts=mesh_file)
          end if
        else if (s%shape == 'geo') then
          ! a rank's share of a tetrahedral mesh file (body_per_part): the file streamed,
          ! the whole mesh never held (tet_file_m); the checks the serial ones, at the
          ! share. A 3D gmsh script's: the file one rank meshed it into (geo_mesh_file),
          ! the same nodes, volumes and tetrahedra as the script meshed here
          ! (tet_mesh_body)
          what = "the mesh of '"//trim(s%file)//"'"
          call tet_file_share(mesh_file, what, share(1), share(2), b, local, e2, comm)
        else
          what = "particle file '"//trim(s%file)//"'"
          call tet_file_share(trim(s%file), what, share(1), share(2), b, local, e2, comm)
          ! (the volumes are the tetrahedra's, checked: check_file_layout's sum of them
          ! cannot exceed the box; the coincident nodes are looked for in the rank's slab
          ! of the body, with det(M): check_particles)
        end if
        ! (an RKPM body integrates over the median-dual cells of the triangles or
        ! tetrahedra: no elements; each rank reads its region's cells or tetrahedra for
        ! them, dynamic_setup_m)
        if (.not. allocated(e2) .and. s%discretization /= 'fem') then
          deallocate(b%cells)
          b%cell0 = 0
          b%ncells = 0
        end if
        if (.not. allocated(e2) .and. s%spacing(1) > 0.0_wp) b%spacing(1:nd) = s%spacing(1:nd)
      else
      ! a gmsh script gives in memory what tools/mesh_body.py writes into a particle file:
      ! from here on the two are one path
      has_tri = .false.
      has_cells = .false.
      tets = s%shape == 'geo' .and. nd == 3
      geo_file = .false.
      if (present(mesh_file)) geo_file = s%shape == 'geo' .and. nd == 2 .and. len(mesh_file) > 0
      if (geo_file) then
        ! a 2D script one rank meshed into a file (geo_mesh_file: what mesh_geo gives, as
        ! tools/mesh_body.py writes it), read whole: the same arrays to the bit
        what = "the mesh of '"//trim(s%file)//"'"
        call read_particle_file_h5(mesh_file, nd, xs, vols, loop, order, e2)
        if (.not. allocated(e2)) call read_mesh_extras(mesh_file, size(xs, 2), has_tri, &
          tri, has_cells, ptr, xy, e2)
      else if (s%shape == 'geo') then
        what = "the mesh of '"//trim(s%file)//"'"
        call mesh_geo(s, where, nd, xs, vols, loop, order, tri, ptr, xy, e2)
        has_tri = .not. allocated(e2)
        has_cells = has_tri .and. .not. tets
      else
        what = "particle file '"//trim(s%file)//"'"
        call read_particles(trim(s%file), nd, xs, vols, loop, order, e2)
        ! a 3D file's tetrahedra (tools/mesh_body.py --3d): the body of their nodes, as a
        ! gmsh script's in memory
        if (.not. allocated(e2) .and. nd == 3) call read_file_tets(trim(s%file), what, xs, &
          vols, tets, tri, e2)
        if (.not. allocated(e2) .and. nd == 3 .and. .not. tets .and. &
          s%role == 'deformable' .and. deck%run%mode == 'dynamic') call set_error(e2, &
          what//" has no /mesh/tetrahedra: a deformable 3D body from a file is its "// &
          "tetrahedral mesh ('fem': its elements; 'rkpm': their median-dual cells); "// &
          "write the file with tools/mesh_body.py --3d, or mesh the script in the deck "// &
          "(shape = 'geo')")
      end if
      if (tets) then
        ! linear tetrahedra of the script's volumes: the body of their nodes
        if (.not. allocated(e2)) call tet_mesh_body(what, xs, tri, s%discretization == &
          'fem' .and. s%role == 'deformable' .and. deck%run%mode == 'dynamic', &
          s%discretization == 'rkpm' .and. s%role == 'deformable' .and. &
          deck%run%mode == 'dynamic', b, local, e2)
        if (.not. allocated(e2) .and. s%shape == 'file') then
          ! a file's spacing from its volume column (checked equal to the tetrahedra's
          ! quarters), summed exactly: the one sum the ranks reading their shares make too
          b%spacing(1:3) = volume_spacing(vols, b%np)
        end if
      else
        if (.not. allocated(e2)) call check_file_values(what, xs, vols, e2)
        if (.not. allocated(e2)) call make_from_arrays(b, xs, vols, loop, order, e2)
      end if
      if (.not. allocated(e2) .and. s%spacing(1) > 0.0_wp) b%spacing(1:nd) = s%spacing(1:nd)
      if (.not. allocated(e2)) call check_file_layout(what, b, e2)
      if (.not. allocated(e2) .and. s%shape == 'file' .and. .not. tets) &
        call read_mesh_extras(trim(s%file), b%np, has_tri, tri, has_cells, ptr, xy, e2)
      if (.not. allocated(e2) .and. .not. tets) call set_mesh_extras(what, s, &
        deck%run%mode == 'dynamic', has_tri, tri, has_cells, ptr, xy, b, local, e2)
      if (.not. allocated(e2) .and. deck%run%mode == 'dynamic' .and. s%role == &
        'deformable' .and. s%discretization == 'rkpm' .and. s%integration /= 'direct' .and. &
        .not. allocated(b%cell_ptr) .and. .not. allocated(b%tets)) then
        call set_error(err, where//", variable integration = '"//trim(s%integration)// &
          "': "//trim(s%integration)//" integrates over each particle's cell, and the "// &
          "particle file '"//trim(s%file)//"' has no /cells (ptr, xy); give a file with "// &
          "them (tools/mesh_body.py writes the median-dual cells of a mesh) or "// &
          "integration = 'direct', a negative control, in plane strain")
        return
      end if
      end if
    end select
    if (allocated(e2)) then
      call body_error(where, s, e2, err)
      return
    end if
    if (b%np < basis_size(s%bid)) then
      call set_error(err, where//', variable '//body_count_var(s%shape)//': the body has '// &
        itoa(b%np)//' particle(s), and the basis '''//trim(s%basis)//''' needs at least '// &
        itoa(basis_size(s%bid))//' (Theorem 3.1); give more particles ('// &
        body_count_var(s%shape)//')')
      return
    end if
    b%name = s%name
    b%shape = s%shape
    b%kid = s%kid
    b%wshape = s%wshape
    b%bid = s%bid
    if (allocated(local)) then
      ! a mesh file: supports from the element sizes around each node
      call set_supports(b, s%support_factor, local)
    else if (s%shape == 'annulus_sector') then
      dr = (s%r_outer - s%r_inner)/real(s%n(1) - 1, wp)
      dt = (s%theta_end - s%theta_start)*pi/180.0_wp
      if (s%theta_end - s%theta_start >= 360.0_wp - full_turn_deg_tol) then
        dt = dt/real(s%n(2), wp)
      else
        dt = dt/real(s%n(2) - 1, wp)
      end if
      ! (and the polar recipe's of a rank's share)
      call annulus_supports(b, s%center, dr, dt, s%support_factor)
    else if (.not. allocated(b%cells) .or. nd == 3) then
      ! (a 3D element body's nodes are its lattice's particles: their det(M) supports too)
      call set_supports(b, s%support_factor)
      ! (set_supports' supports, for the particles an extruded body's recipe makes)
      if (allocated(b%ext)) b%ext%rho = s%support_factor(1:3)*b%spacing(1:3)
      if (allocated(b%lat)) b%lat%rho = s%support_factor(1:2)*b%spacing(1:2)
    end if
    ! an extruded body's recipe is kept where a rank can make its region from it: a
    ! deformable body of a dynamic run, RKPM or tetrahedra (dynamic_setup_m)
    if (allocated(b%ext) .and. (.not. any(s%discretization == ['rkpm', 'fem ']) .or. &
      s%role /= 'deformable' .or. deck%run%mode /= 'dynamic')) deallocate(b%ext)
    ! and a rectangle's, of a deformable body of a dynamic run that stays on its lattice
    ! (no rotation; RKPM by SCNI without a perturbation, or CST4: dynamic_setup_m
    ! body_per_part)
    if (allocated(b%lat) .and. (s%role /= 'deformable' .or. deck%run%mode /= 'dynamic' &
      .or. s%rotate /= 0.0_wp .or. nd /= 2 .or. .not. (s%discretization == 'fem' .or. &
      (s%discretization == 'rkpm' .and. s%integration == 'scni' .and. &
      s%perturbation == 0.0_wp)))) deallocate(b%lat)
    ! Theorem 3.1 on the generating lattice: name the smallest support factor that works.
    if (any(s%shape == ['segment  ', 'rectangle', 'polygon  ', 'box      ']) .and. &
      .not. allocated(b%cells)) then
      if (.not. lattice_admissible(b%kid, b%wshape, b%bid, nd, b%spacing(1:nd), &
        s%support_factor(1:nd))) then
        fmin = min_support_factor(b%kid, b%wshape, b%bid, nd, b%spacing(1:nd))
        call set_error(err, where//', variable support_factor = '// &
          rtoa(minval(s%support_factor(1:nd)))//': too small for basis '''// &
          trim(s%basis)//''' with the '//trim(s%window)//' window (Theorem 3.1: some '// &
          'points are covered by fewer than '//itoa(basis_size(b%bid))// &
          ' non-degenerate particles, so M is singular); use support_factor >= '// &
          rtoa(fmin)//' (a margin above it, e.g. '//rtoa(max(2.0_wp, &
          real(ceiling(2.0_wp*fmin), wp)/2.0_wp))//', is typical)')
        return
      end if
    end if
    ! the deck allows a perturbation on RKPM rectangles and polygons only (deck_m)
    if (s%perturbation > 0.0_wp) call perturb_interior(b, s%perturbation, s%perturbation_seed)
    if (s%rotate /= 0.0_wp .or. any(s%translate(1:nd) /= 0.0_wp)) then
      call place_body(b, s, deck%run%mode == 'dynamic', where, err)
      if (allocated(err)) return
    end if
    if (allocated(b%mfile)) then
      ! (a share of a mesh file: its tetrahedra have positive volumes, checked)
      flat = .false.
    else if (b%held_share) then
      ! a rank's share: the whole body is flat where its first and last layers are (an
      ! extruded body: where its section is; a rectangle where its outermost ring is)
      none = 0
      nowhere = 0.0_wp
      call body_pick(b, 1, b%np, [(-huge(1.0_wp), i = 1, 3)], [(huge(1.0_wp), i = 1, 3)], &
        0, none, nowhere, ends, ends=.true.)
      flat = flat_layout(ends%x)
    else
      flat = b%ndim > 1 .and. flat_layout(b%x)
    end if
    if (flat) then
      call set_error(err, where//', variable '//body_make_vars(s%shape)//': the '//itoa(b%np)// &
        ' particles lie on one '//trim(merge('line ', 'plane', b%ndim == 2))//', a '// &
        'degenerate layout: a '//itoa(b%ndim)//'-D body needs particles spread in every '// &
        'direction, or its moment matrix is singular whatever the support')
      return
    end if
    call check_particles(b, s, where, err)

  contains

    !> A 3D body of discretization 'fem' (deformable; a rigid body keeps its particles):
    !! linear tetrahedra on the extruded lattice (tet4_m), its cells.
    subroutine tets_if_fem(sec, body, e)
      type(body_t), intent(in) :: sec
      type(body_t), intent(inout) :: body
      type(error_t), allocatable, intent(inout) :: e
      type(tet4_mesh_t) :: tm
      integer, allocatable :: tri2(:, :)
      integer :: c0, c1, bad
      logical :: ok
      if (s%discretization /= 'fem' .or. s%role /= 'deformable' .or. &
        deck%run%mode /= 'dynamic') return
      ! (named already for the messages, as build_body names it below)
      body%name = s%name
      if (.not. body%held_share) then
        call tet4_extruded(sec, body, tm, e)
        if (.not. allocated(e)) call move_alloc(tm%tet, body%cells)
        return
      end if
      ! a rank's share (build_bodies on ranks): the section's triangles in the recipe, its
      ! share of the tetrahedra (for /bodies) made from it, cell0 ... of ncells
      call tet4_section(sec, body%name, tri2, e)
      if (allocated(e)) return
      call move_alloc(tri2, body%ext%tri2)
      body%ncells = 3*size(body%ext%tri2, 2)*(body%ext%nz - 1)
      c0 = share_first(body%ncells, share(1), share(2))
      c1 = share_first(body%ncells, share(1) + 1, share(2)) - 1
      body%cell0 = c0
      call extruded_tets(body%ext, c0, c1, body%cells, ok, bad)
      if (.not. ok) call set_error(e, 'tetrahedra of an extruded section: tetrahedron '// &
        itoa(bad)//' has zero volume (a degenerate section triangle)')
    end subroutine tets_if_fem
  end subroutine build_body

  !> The body turned by s%rotate degrees counter-clockwise about its centroid (the volume-
  !! weighted mean of its particles), then moved by s%translate: every position it carries
  !! (particles, explicit cells, merged cell centres, the exact geometry the cells are
  !! clipped by). A translation applies to every shape. A rotation needs cells that turn
  !! with the body: meshes and files with cells, element meshes, annulus sectors, disks,
  !! rigid bodies and detection runs have them; a deformable RKPM rectangle or polygon
  !! integrates over lattice cells computed from its lattice points, so they are first made
  !! explicit polygons (lattice_cells_explicit) that turn with it. A polygon whose outside
  !! lattice cells were merged into particle cells (several pieces a cell) is refused.
  subroutine place_body(b, s, dynamic, where, err)
    type(body_t), intent(inout) :: b
    type(body_spec_t), intent(in) :: s
    logical, intent(in) :: dynamic
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: c(2), rot(2, 2), th
    integer :: nd, i
    logical :: ok
    nd = b%ndim
    if (s%rotate /= 0.0_wp) then
      if (dynamic .and. s%role == 'deformable' .and. .not. allocated(b%cells) .and. &
        .not. allocated(b%cell_ptr) .and. any(s%shape == ['rectangle', 'polygon  '])) then
        call lattice_cells_explicit(b, ok)
        if (.not. ok) then
          call set_error(err, where//', variable rotate = '//rtoa(s%rotate)//': this '// &
            'RKPM polygon''s cells include lattice cells merged from outside it (several '// &
            'pieces a particle), which cannot turn as one cell; give the turned outline as '// &
            'the polygon''s vertices (its lattice then stays along x and y), or mesh it '// &
            '(shape = ''geo''), or make it of elements (discretization = ''fem'')')
          return
        end if
      end if
      th = s%rotate*pi/180.0_wp
      rot = reshape([cos(th), sin(th), -sin(th), cos(th)], [2, 2])
      c = matmul(b%x, b%vol)/sum(b%vol)
      call turn(b%x)
      if (allocated(b%cell_centre)) call turn(b%cell_centre)
      if (allocated(b%merged_centre)) call turn(b%merged_centre)
      if (allocated(b%cell_xy)) call turn(b%cell_xy)
      select case (b%geom%kind)
      case (geom_polygon)
        call turn(b%geom%v)
      case (geom_annulus)
        b%geom%center = c + matmul(rot, b%geom%center - c)
        b%geom%t0 = b%geom%t0 + th
        b%geom%t1 = b%geom%t1 + th
      end select
    end if
    ! (a rank's share holds size(b%x, 2) of the np)
    do i = 1, size(b%x, 2)
      b%x(:, i) = b%x(:, i) + s%translate(1:nd)
    end do
    ! (the rows a rank reads of a mesh file later are moved the same way)
    if (allocated(b%mfile)) b%mfile%shift = s%translate(1:3)
    ! (the particles a rectangle's or an extruded body's recipe makes are moved the same
    ! way)
    if (allocated(b%lat)) then
      b%lat%shifted = .true.
      b%lat%shift = s%translate(1:2)
    end if
    if (allocated(b%ext)) then
      b%ext%shifted = .true.
      b%ext%shift = s%translate(1:3)
    end if
    if (allocated(b%cell_centre)) b%cell_centre = b%cell_centre + &
      spread(s%translate(1:nd), 2, size(b%cell_centre, 2))
    if (allocated(b%merged_centre)) b%merged_centre = b%merged_centre + &
      spread(s%translate(1:nd), 2, size(b%merged_centre, 2))
    ! (explicit cells are x-y polygons, in 3D those of an extruded body's sections)
    if (allocated(b%cell_xy)) b%cell_xy = b%cell_xy + &
      spread(s%translate(1:2), 2, size(b%cell_xy, 2))
    select case (b%geom%kind)
    case (geom_segment)
      b%geom%a = b%geom%a + s%translate(1)
      b%geom%b = b%geom%b + s%translate(1)
    case (geom_polygon, geom_prism)
      b%geom%v = b%geom%v + spread(s%translate(1:2), 2, size(b%geom%v, 2))
    case (geom_annulus, geom_cylinder)
      b%geom%center = b%geom%center + s%translate(1:2)
    end select
    ! an extruded body's span along z (its cells are clipped by it)
    if (b%geom%kind == geom_prism .or. b%geom%kind == geom_cylinder) then
      b%geom%z0 = b%geom%z0 + s%translate(3)
      b%geom%z1 = b%geom%z1 + s%translate(3)
    end if

  contains

    !> Points a(2, n) turned by rot about c.
    subroutine turn(a)
      real(wp), intent(inout) :: a(:, :)
      integer :: j
      do j = 1, size(a, 2)
        a(:, j) = c + matmul(rot, a(:, j) - c)
      end do
    end subroutine turn
  end subroutine place_body

  !> True when the points x(ndim, np) lie on one line (2D) or plane (3D): the determinant of
  !! their covariance vanishes next to the cube (square) of its trace.
  pure logical function flat_layout(x) result(flat)
    real(wp), intent(in) :: x(:, :)
    real(wp) :: c(3, 3), m(3), d, tr
    integer :: nd, i
    nd = size(x, 1)
    m = 0.0_wp
    m(1:nd) = sum(x, dim=2)/real(size(x, 2), wp)
    c = 0.0_wp
    do i = 1, size(x, 2)
      c(1:nd, 1:nd) = c(1:nd, 1:nd) + spread(x(:, i) - m(1:nd), 2, nd)* &
        spread(x(:, i) - m(1:nd), 1, nd)
    end do
    tr = c(1, 1) + c(2, 2) + c(3, 3)
    if (nd == 2) then
      d = c(1, 1)*c(2, 2) - c(1, 2)**2
    else
      d = c(1, 1)*(c(2, 2)*c(3, 3) - c(2, 3)**2) - c(1, 2)*(c(1, 2)*c(3, 3) - c(2, 3)*c(1, 3)) &
        + c(1, 3)*(c(1, 2)*c(2, 3) - c(2, 2)*c(1, 3))
    end if
    flat = d <= 1.0e3_wp*epsilon(1.0_wp)*tr**nd
  end function flat_layout

  !> Every coordinate and volume of a particle file finite (HDF5 files hold NaN as easily);
  !! what names the file ("particle file 'p.h5'").
  subroutine check_file_values(what, x, vol, err)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: x(:, :), vol(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: i
    do i = 1, size(vol)
      if (.not. (all(ieee_is_finite(x(:, i))) .and. ieee_is_finite(vol(i)))) then
        call set_error(err, what//", particle "//itoa(i)// &
          ": a coordinate or the volume is not a finite number (NaN or Infinity); fix "// &
          "the file")
        return
      end if
    end do
  end subroutine check_file_values

  !> A particle file's volumes must fit its particles' extent (a coordinate column read as
  !! the volume does not), and no two particles may coincide (closer than coincide_tol x
  !! the nominal spacing: the same point given twice carries its volume twice); what names
  !! the file.
  subroutine check_file_layout(what, b, err, near, mine)
    character(len=*), intent(in) :: what
    type(body_t), intent(in), target :: b
    type(error_t), allocatable, intent(inout) :: err
    !> a rank's share b of a mesh file (tet_file_m): the nodes of its slab of the body and
    !! those near it, which are compared (the volumes not: they are the tetrahedra's)
    type(body_t), intent(in), target, optional :: near
    !> with near: the nodes of near compared with the others (a rank's slab)
    logical, intent(in), optional :: mine(:)
    type(body_t), pointer :: c
    type(bins_t) :: bins
    integer, allocatable :: cand(:)
    real(wp) :: box, tol, r(3)
    integer :: nd, i, k, nc, j, gi, gj
    nd = b%ndim
    c => b
    if (present(near)) c => near
    box = 0.0_wp
    ! (a share's extent is not the body's, and may be empty: no volume check there)
    if (.not. present(near)) box = product(maxval(b%x, dim=2) - minval(b%x, dim=2) + &
      2.0_wp*b%spacing(1:nd))
    if (.not. present(near) .and. sum(b%vol) > volume_excess*box) then
      call set_error(err, what//": the volumes add up to "// &
        rtoa(sum(b%vol))//" m^"//itoa(nd)//", "//rtoa(sum(b%vol)/box)//" times the box "// &
        "around the particles grown by one spacing ("//rtoa(box)//" m^"//itoa(nd)//"); "// &
        "is a coordinate read as the volume? A "//itoa(nd)//"-D deck reads "// &
        trim(columns_text(nd))//" (a z column belongs to &run ndim = 3)")
      return
    end if
    tol = coincide_tol*minval(b%spacing(1:nd))
    call bins_build(bins, c%x, b%spacing(1:nd), err)
    if (allocated(err)) return
    allocate(cand(c%np))
    r = tol
    do i = 1, c%np
      gi = body_whole(c, i)
      if (present(mine)) then
        if (.not. mine(i)) cycle
      end if
      call bins_candidates(bins, c%x(:, i), r(1:nd), cand, nc)
      do k = 1, nc
        j = cand(k)
        if (j == i) cycle
        gj = body_whole(c, j)
        if (norm2(c%x(:, j) - c%x(:, i)) <= tol) then
          call set_error(err, what//": particles "//itoa(min(gi, gj))// &
            " and "//itoa(max(gi, gj))//" coincide (both at ("//trim(coords(c%x(:, i)))// &
            "), closer than "//rtoa(tol)//" m = 1e-3 of the spacing); give each particle "// &
            "once")
          return
        end if
      end do
    end do
  contains
    pure function coords(p) result(t)
      real(wp), intent(in) :: p(:)
      character(len=:), allocatable :: t
      integer :: d
      t = rtoa(p(1))
      do d = 2, size(p)
        t = t//', '//rtoa(p(d))
      end do
    end function coords
  end subroutine check_file_layout

  !> Rank mf%me's slab lo ... hi of the body of mesh file mf (placed): its extent cut along
  !! its longest side (axis) in mf%nranks equal parts.
  pure subroutine file_slab(mf, lo, hi, axis)
    type(mesh_file_t), intent(in) :: mf
    real(wp), intent(out) :: lo(3), hi(3)
    integer, intent(out) :: axis
    real(wp) :: a, w
    lo = mf%lo + mf%shift
    hi = mf%hi + mf%shift
    axis = maxloc(hi - lo, 1)
    a = lo(axis)
    w = hi(axis) - lo(axis)
    lo(axis) = a + w*real(mf%me, wp)/real(mf%nranks, wp)
    if (mf%me < mf%nranks - 1) hi(axis) = a + w*real(mf%me + 1, wp)/real(mf%nranks, wp)
  end subroutine file_slab

  !> The columns of a plain particle file in ndim dimensions.
  pure function columns_text(nd) result(t)
    integer, intent(in) :: nd
    character(len=:), allocatable :: t
    select case (nd)
    case (1)
      t = 'x volume [loop order]'
    case (2)
      t = 'x y volume [loop order]'
    case default
      t = 'x y z volume [loop order]'
    end select
  end function columns_text

  !> det(M) > 0 at every particle of the body (Theorem 3.1 for any distribution). The
  !! message tells too few covering particles (a support too small) from enough particles
  !! in a degenerate layout (all on a line, for instance), which no support can mend.
  subroutine check_particles(b0, s, where, err)
    type(body_t), intent(in), target :: b0
    type(body_spec_t), intent(in) :: s
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    type(rk_cloud_t) :: c
    real(wp) :: mm(mmax, mmax)
    integer :: i, ncover, bad_i, bad_n, g0, g1
    logical :: ok
    real(wp) :: f, grow(3), lo(3), hi(3)
    type(body_t), pointer :: b
    type(error_t), allocatable :: e2
    !> the particles of b at which M is checked (a rank's share, or its slab)
    logical, allocatable :: mine(:)
    integer :: axis
    type(body_t), target :: near
    integer :: none(2)
    real(wp) :: nowhere(2)
    !> multiples of the present supports tried when enough particles cover a singular point
    real(wp), parameter :: trial(6) = [1.1_wp, 1.25_wp, 1.5_wp, 1.75_wp, 2.0_wp, 2.5_wp]
    ! M at the particles g0 ... g1 of body b (its numbers: b%glob where it holds some of a
    ! larger body's), each from the particles of b that cover it
    b => b0
    g0 = 1
    g1 = b0%np
    ! (a rank's share of a plane mesh file: rank 0 built the whole body and checked it,
    ! mfcd_mpi, before any rank read its share)
    if (allocated(b0%mfile) .and. b0%ndim == 2) return
    if (allocated(b0%mfile)) then
      ! a rank's share of a mesh file: M at the nodes of its slab of the body (a mesh file
      ! numbers its nodes in no spatial order, so the share's own nodes are spread over the
      ! whole body: the slabs, the whole body's extent cut along its longest side in equal
      ! parts, one a rank, hold each node once), from the nodes the largest trial supports
      ! reach (every support at most the factor times the longest edge)
      grow = maxval(trial)*maxval(b0%support_factor)*b0%mfile%lmax + b0%spacing(1:3)
      call file_slab(b0%mfile, lo, hi, axis)
      call tet_file_region(b0, lo - grow, hi + grow, near, err)
      if (allocated(err)) return
      allocate(mine(near%np))
      mine = near%x(axis, :) >= lo(axis) .and. (near%x(axis, :) < hi(axis) .or. &
        (b0%mfile%me == b0%mfile%nranks - 1 .and. near%x(axis, :) <= hi(axis)))
      ! (first, as serially: no node coincides with another, check_file_layout, against
      ! those near it; its message as build_body's)
      call check_file_layout("particle file '"//trim(s%file)//"'", b0, e2, near, mine)
      if (allocated(e2)) then
        call set_error(err, where//', variable '//body_make_vars(s%shape)//': '// &
          e2%message)
        return
      end if
      b => near
    else if (b0%held_share) then
      ! a rank's share of an extruded body (build_bodies on ranks): M at its particles,
      ! from the particles its largest trial supports reach (made from the recipe)
      g0 = b0%row0
      g1 = b0%row0 + size(b0%x, 2) - 1
      ! (or of a rectangle: its recipe b0%lat)
      grow = 0.0_wp
      if (allocated(b0%lat)) then
        grow(1:2) = maxval(trial)*b0%lat%rho + b0%spacing(1:2)
      else
        grow = maxval(trial)*b0%ext%rho + b0%spacing(1:3)
      end if
      none = 0
      nowhere = 0.0_wp
      call body_pick(b0, 1, b0%np, minval(b0%x, dim=2) - grow(1:b0%ndim), &
        maxval(b0%x, dim=2) + grow(1:b0%ndim), 0, none, nowhere, near)
      b => near
    end if
    if (.not. allocated(mine)) then
      allocate(mine(b%np))
      mine = [(body_whole(b, i) >= g0 .and. body_whole(b, i) <= g1, i = 1, b%np)]
    end if
    call body_cloud(b, c, err)
    if (allocated(err)) return
    bad_i = 0
    bad_n = 0
    !$omp parallel do default(none) shared(b, c, mine) private(mm, ncover, ok) &
    !$omp reduction(max: bad_i) reduction(max: bad_n)
    do i = 1, b%np
      if (.not. mine(i)) cycle
      call cloud_moment(c, b%x(:, i), mm, ncover)
      call chol_small(c%m, mm, ok, pivot_tol)
      if (.not. ok .and. body_whole(b, i) > bad_i) then
        bad_i = body_whole(b, i)
        bad_n = ncover
      end if
    end do
    !$omp end parallel do
    if (bad_i == 0) return
    if (bad_n < basis_size(b%bid)) then
      call set_error(err, where//', variable support_factor = '// &
        rtoa(minval(s%support_factor(1:b%ndim)))//': moment matrix singular at particle '// &
        itoa(bad_i)//', covered by only '//itoa(bad_n)//' particle(s) while the basis '''// &
        trim(s%basis)//''' needs at least '//itoa(basis_size(b%bid))//' (Theorem 3.1); '// &
        'increase support_factor')
    else
      ! enough particles, in a layout this support cannot span (a staircase of lattice
      ! points along a curved edge, or all on one line): does a larger support mend it?
      f = mending_factor()
      if (f > 0.0_wp) then
        call set_error(err, where//', variable support_factor = '// &
          rtoa(minval(s%support_factor(1:b%ndim)))//': moment matrix singular at '// &
          'particle '//itoa(bad_i)//' although '//itoa(bad_n)//' particles cover it: '// &
          'their layout there is too narrow for this support (e.g. the staircase of '// &
          'lattice points along a curved edge); support_factor = '// &
          rtoa(f*minval(s%support_factor(1:b%ndim)))//' makes M regular at every '// &
          'particle of the body (checked), or give the body a finer spacing')
      else
        call set_error(err, where//', variable '//body_count_var(s%shape)//': moment '// &
          'matrix singular at particle '//itoa(bad_i)//' although '//itoa(bad_n)// &
          ' particles cover it (the basis '''//trim(s%basis)//''' needs '// &
          itoa(basis_size(b%bid))//'): they lie in a degenerate layout, e.g. all on one '// &
          'line, which no support up to '//rtoa(maxval(trial))//' times the present '// &
          'one mends (checked); check the particle positions (a body needs particles '// &
          'spread in every direction)')
      end if
    end if

  contains

    !> The smallest of the trial multiples of the supports with which M is regular at
    !! every particle (0: none).
    real(wp) function mending_factor() result(fbest)
      type(body_t) :: bb
      type(rk_cloud_t) :: cc
      type(error_t), allocatable :: e2
      integer :: k, j, nc
      logical :: good, okj
      real(wp) :: m2(mmax, mmax)
      fbest = 0.0_wp
      do k = 1, size(trial)
        bb = b
        bb%rho = trial(k)*b%rho
        call body_cloud(bb, cc, e2)
        if (allocated(e2)) return
        good = .true.
        !$omp parallel do default(none) shared(bb, cc, mine) private(m2, nc, okj) &
        !$omp reduction(.and.: good)
        do j = 1, bb%np
          if (.not. mine(j)) cycle
          call cloud_moment(cc, bb%x(:, j), m2, nc)
          call chol_small(cc%m, m2, okj, pivot_tol)
          good = good .and. okj
        end do
        !$omp end parallel do
        if (good) then
          fbest = trial(k)
          return
        end if
      end do
    end function mending_factor
  end subroutine check_particles

  !> True when M is non-singular at every probe of a lattice patch with these supports.
  !! The patch is a corner of a lattice (indices 0 .. 2K per direction), the worst place on
  !! a convex lattice body: probes are a 5^ndim sub-grid of the corner cell and of the
  !! central cell (particles, mid-edges, centres).
  function lattice_admissible(kid, wshape, bid, ndim, spacing, factor) result(ok)
    integer, intent(in) :: kid, wshape, bid, ndim
    real(wp), intent(in) :: spacing(:), factor(:)
    logical :: ok
    integer, parameter :: nsub = 5
    type(rk_cloud_t) :: c
    type(error_t), allocatable :: err
    real(wp), allocatable :: x(:, :), rho(:, :), vol(:)
    real(wp) :: p(3), mm(mmax, mmax)
    integer :: kpatch, nside, np, i, j, ijk(3), ncover, nprobe, cell
    kpatch = ceiling(maxval(factor(1:ndim))) + 2
    nside = 2*kpatch + 1
    np = nside**ndim
    allocate(x(ndim, np), rho(ndim, np), vol(np))
    do i = 1, np
      call unflatten(i - 1, nside, ndim, ijk)
      x(:, i) = real(ijk(1:ndim), wp)*spacing(1:ndim)
      rho(:, i) = factor(1:ndim)*spacing(1:ndim)
    end do
    vol = product(spacing(1:ndim))
    call cloud_init(c, x, rho, vol, kid, wshape, bid, factor(1:ndim)*spacing(1:ndim), err)
    ok = .not. allocated(err)
    nprobe = nsub**ndim
    do cell = 0, kpatch, kpatch
      do j = 1, nprobe
        if (.not. ok) return
        call unflatten(j - 1, nsub, ndim, ijk)
        p = 0.0_wp
        p(1:ndim) = (real(cell, wp) + real(ijk(1:ndim), wp)/real(nsub - 1, wp)) &
          *spacing(1:ndim)
        call cloud_moment(c, p(1:ndim), mm, ncover)
        call chol_small(c%m, mm, ok, pivot_tol)
      end do
    end do
  end function lattice_admissible

  !> Smallest isotropic support factor (0.01 steps, 0.5 .. 8) that is admissible; -1 if none.
  function min_support_factor(kid, wshape, bid, ndim, spacing) result(fmin)
    integer, intent(in) :: kid, wshape, bid, ndim
    real(wp), intent(in) :: spacing(:)
    real(wp) :: fmin
    integer :: k
    real(wp) :: f(3)
    fmin = -1.0_wp
    do k = 50, 800
      f = real(k, wp)/100.0_wp
      if (lattice_admissible(kid, wshape, bid, ndim, spacing, f)) then
        fmin = f(1)
        return
      end if
    end do
  end function min_support_factor

  pure subroutine unflatten(i, n, ndim, ijk)
    integer, intent(in) :: i, n, ndim
    integer, intent(out) :: ijk(3)
    ijk = 0
    ijk(1) = mod(i, n)
    if (ndim > 1) ijk(2) = mod(i/n, n)
    if (ndim > 2) ijk(3) = i/(n*n)
  end subroutine unflatten

  !> Particle file: HDF5 (.h5, .hdf5) or plain columns.
  subroutine read_particles(path, ndim, x, vol, loop, order, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ndim
    real(wp), allocatable, intent(out) :: x(:, :), vol(:)
    integer, allocatable, intent(out) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: l
    l = len_trim(path)
    if (l > 3 .and. (path(max(1, l - 2):l) == '.h5' .or. path(max(1, l - 4):l) == '.hdf5')) then
      call read_particle_file_h5(path, ndim, x, vol, loop, order, err)
    else
      call read_particle_columns(path, ndim, x, vol, loop, order, err)
    end if
  end subroutine read_particles

  !> A gmsh script meshed in memory (&body shape = 'geo'): the script's model, read and
  !! checked with the deck (s%geo, geo_script_m), built and meshed by gmsh in a confined
  !! thread within the body's limits (gmsh_mesh_m), then the nodes, volumes, boundary
  !! loops, counter-clockwise triangles and median-dual cells that tools/mesh_body.py would
  !! write for them (mesh_cells_m). In a 3D run (nd = 3) gmsh meshes the script's volumes
  !! with linear tetrahedra: x (3, np) the nodes of the tetrahedra and tri (4, ne) the
  !! tetrahedra, of positive volume (tet_mesh_body makes the body); vol, loop, order, ptr
  !! and xy are then empty. where names the deck and body for messages. The log says what
  !! gmsh made.
  subroutine mesh_geo(s, where, nd, x, vol, loop, order, tri, ptr, xy, err)
    type(body_spec_t), intent(in) :: s
    character(len=*), intent(in) :: where
    integer, intent(in) :: nd
    real(wp), allocatable, intent(out) :: x(:, :), vol(:), xy(:, :)
    integer, allocatable, intent(out) :: loop(:), order(:), tri(:, :), ptr(:)
    type(error_t), allocatable, intent(inout) :: err
    integer(i64), allocatable :: tags(:), tri_tags(:)
    real(wp), allocatable :: xyz(:)
    character(len=:), allocatable :: version, numbers, script
    type(confine_limits_t) :: limits
    type(error_t), allocatable :: e2
    integer :: k, nv
    character(len=:), allocatable :: elements
    nv = nd + 1
    elements = trim(merge('triangles ', 'tetrahedra', nd == 2))
    script = "the gmsh script '"//trim(s%file)//"'"
    numbers = ''
    do k = 1, s%ngeo
      if (k > 1) numbers = numbers//', '
      numbers = numbers//trim(s%geo_names(k))//' = '//rtoa(s%geo_values(k))
    end do
    ! memory: about 800 bytes a triangle while gmsh meshes (measured on 2D meshes of
    ! 2e4 to 2e6 triangles), about 560 bytes a tetrahedron (a sphere of 8.5e4 and 2.8e5
    ! tetrahedra, gmsh 4.15), so 2 KiB an element allowed, and 256 MiB for gmsh itself
    limits%seconds = s%geo_time_limit
    limits%max_growth = 268435456_i64 + 2048_i64*int(s%geo_max_elements, i64)
    limits%msg_time = where//', variable geo_time_limit = '//rtoa(s%geo_time_limit)// &
      ': meshing '//script//' took longer than '//rtoa(s%geo_time_limit)//' s and was '// &
      'stopped; give the script larger mesh sizes, or raise geo_time_limit if so long a '// &
      'meshing is meant'
    limits%msg_memory = where//', variable geo_max_elements = '// &
      itoa(s%geo_max_elements)//': meshing '//script//' took more than '// &
      itoa(int(limits%max_growth/1048576_i64))//' MiB of memory (256 MiB and 2 KiB an '// &
      'element allowed) and was stopped; give the script larger mesh sizes, or raise '// &
      'geo_max_elements if so large a mesh is meant'
    limits%msg_crash = where//', variable file = '''//trim(s%file)//''': gmsh crashed '// &
      'meshing '//script//' (a fatal signal in gmsh); check the geometry (curves that '// &
      'cross, loops that do not close, a surface without area) or mesh it another way'
    call gmsh_mesh_model(s%geo, nd, limits, tags, xyz, tri_tags, version, e2)
    if (.not. allocated(e2) .and. size(tri_tags)/nv > s%geo_max_elements) then
      call set_error(err, where//', variable geo_max_elements = '// &
        itoa(s%geo_max_elements)//': gmsh made '//itoa(size(tri_tags)/nv)//' '//elements// &
        ' of '// &
        script//', more than geo_max_elements; give the script larger mesh sizes, or '// &
        'raise geo_max_elements if so large a mesh is meant')
      return
    end if
    if (.not. allocated(e2)) call mesh_from_tags(tags, xyz, tri_tags, x, tri, e2, nv)
    if (nd == 3) then
      allocate(vol(0), loop(0), order(0), ptr(0), xy(0, 0))
    else if (.not. allocated(e2)) then
      call mesh_body_arrays(x, tri, vol, loop, order, ptr, xy, e2)
    end if
    if (allocated(e2)) then
      if (len(version) == 0) then
        ! gmsh never started (a build without it, or no confinement): its message says
        ! what to do
        call set_error(err, script//": "//e2%message)
      else if (s%ngeo > 0) then
        call set_error(err, "gmsh "//version//" cannot mesh "//script//" with "// &
          numbers//" (geo_names, geo_values): "//e2%message//"; fix the script or the "// &
          "numbers")
      else
        call set_error(err, "gmsh "//version//" cannot mesh "//script//": "// &
          e2%message//"; fix the script")
      end if
      return
    end if
    if (len(numbers) > 0) numbers = ' with '//numbers
    if (nd == 3) then
      call log_print("body '"//trim(s%name)//"': gmsh "//version//" meshed '"// &
        trim(s%file)//"'"//numbers//": "//itoa(size(x, 2))//" nodes, "// &
        itoa(size(tri, 2))//" tetrahedra")
    else
      call log_print("body '"//trim(s%name)//"': gmsh "//version//" meshed '"// &
        trim(s%file)//"'"//numbers//": "//itoa(size(x, 2))//" nodes, "// &
        itoa(size(tri, 2))//" triangles, "//itoa(maxval(loop))//" boundary loop(s)")
    end if
  end subroutine mesh_geo

  !> The body of a tetrahedral mesh (a 3D gmsh script meshed by mesh_geo): the nodes x
  !! (3, np) are its particles, each with a quarter of the volume of every tetrahedron
  !! tet (4, ne) it belongs to (the row sums of the consistent mass, eq. 70: the lumped
  !! volumes tet4_m gives the element body), summed node 1, 2, 3, 4 of each tetrahedron in
  !! turn; its facets (the closed surface contact needs) are the faces of one tetrahedron
  !! only, and their nodes the boundary particles; the nominal spacing is the cube root of
  !! the mean volume, and local(np) the longest edge at each node (the det(M) supports, as
  !! a 2D mesh's). elements: the body is a finite-element body (its cells the tetrahedra);
  !! dual: an RKPM body integrated over the tetrahedra's median-dual cells (b%tets).
  !! A face in more than two tetrahedra (a mesh that is not conforming) is an error (every
  !! node is in a tetrahedron: mesh_from_tags kept those only); what names the mesh.
  subroutine tet_mesh_body(what, x, tet, elements, dual, b, local, err)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tet(:, :)
    logical, intent(in) :: elements, dual
    type(body_t), intent(inout) :: b
    real(wp), allocatable, intent(inout) :: local(:)
    type(error_t), allocatable, intent(inout) :: err
    type(tet4_mesh_t) :: mesh
    integer, allocatable :: faces(:, :), owner(:), zero(:)
    real(wp), allocatable :: vol(:)
    real(wp) :: len_e
    integer :: np, ne, e, k, i, j, nover
    np = size(x, 2)
    ne = size(tet, 2)
    allocate(local(np))
    call tet_node_volumes(x, tet, vol)
    local = 0.0_wp
    do e = 1, ne
      do k = 1, 3
        do j = k + 1, 4
          i = tet(k, e)
          len_e = norm2(x(:, i) - x(:, tet(j, e)))
          local(i) = max(local(i), len_e)
          local(tet(j, e)) = max(local(tet(j, e)), len_e)
        end do
      end do
    end do
    mesh%ne = ne
    mesh%tet = tet
    call tet4_boundary_faces(mesh, np, faces, owner, over=nover)
    if (nover > 0) then
      call set_error(err, what//": "//itoa(nover)//" faces belong to more than two "// &
        "tetrahedra (the mesh is not conforming); fix the script")
      return
    end if
    call check_file_values(what, x, vol, err)
    if (allocated(err)) return
    allocate(zero(np))
    zero = 0
    call make_from_arrays(b, x, vol, zero, zero, err)
    if (allocated(err)) return
    ! (the spacing of its volumes summed exactly: a mesh file's, which the ranks reading its
    ! shares sum the same way, tet_file_m)
    b%spacing(1:3) = volume_spacing(vol, np)
    do e = 1, size(faces, 2)
      b%boundary(faces(:, e)) = .true.
    end do
    call move_alloc(faces, b%facets)
    if (elements) call move_alloc(mesh%tet, b%cells)
    if (dual) call move_alloc(mesh%tet, b%tets)
    call log_print("  its surface: "//itoa(size(b%facets, 2))//" triangles over "// &
      itoa(count(b%boundary))//" nodes")
  end subroutine tet_mesh_body

  !> Each node's volume vol(np) of the tetrahedra tet (4, ne) over the nodes x (3, np): its
  !! quarter of every tetrahedron it belongs to (the row sums of the consistent mass, eq.
  !! 70), summed node 1, 2, 3, 4 of each tetrahedron in turn (tools/mesh_body.py --3d and
  !! tet_file_m sum them in the same order: the same doubles).
  subroutine tet_node_volumes(x, tet, vol)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tet(:, :)
    real(wp), allocatable, intent(out) :: vol(:)
    real(wp), allocatable :: v(:)
    integer :: e, k
    allocate(vol(size(x, 2)), v(size(tet, 2)))
    do e = 1, size(tet, 2)
      v(e) = tet_volume(x, tet(:, e))
    end do
    vol = 0.0_wp
    do k = 1, 4
      do e = 1, size(tet, 2)
        vol(tet(k, e)) = vol(tet(k, e)) + 0.25_wp*v(e)
      end do
    end do
  end subroutine tet_node_volumes

  !> Body k's 3D gmsh script (shape 'geo') meshed here once into the new file path, as
  !! tools/mesh_body.py --3d writes a script's mesh (/particles/x, /particles/volume with
  !! tet_node_volumes' sums, /mesh/tetrahedra, 1-based), for every rank of mfcd_mpi to read
  !! its part of (tet_file_m): the body the script meshed on a rank gives (tet_mesh_body),
  !! bit for bit, and no rank holds the whole mesh but this one, while it meshes and writes.
  !! A 2D script's as tools/mesh_body.py writes a plane mesh (the nodes' volumes, boundary
  !! loops, triangles and median-dual cells), which every rank reads whole: the same
  !! arrays as mesh_geo's, so gmsh runs on one rank instead of on every one.
  !! gmsh meshes a model whole (its partitioner cuts a mesh already made), so this is the
  !! one rank's work. err names the deck's body and variable as build_body does; a file
  !! that cannot be written is a failed run (exit 1), the path named.
  subroutine geo_mesh_file(deck, k, path, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: x(:, :), vol(:), xy(:, :), nbox(:, :), tbox(:, :)
    integer, allocatable :: loop(:), order(:), tet(:, :), ptr(:)
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    character(len=:), allocatable :: where
    integer :: nd
    where = "deck '"//deck%path//"', group &body (body "//itoa(k)//", '"// &
      trim(deck%bodies(k)%name)//"')"
    nd = deck%run%ndim
    call mesh_geo(deck%bodies(k), where, nd, x, vol, loop, order, tet, ptr, xy, e2)
    if (allocated(e2)) then
      call body_error(where, deck%bodies(k), e2, err)
      return
    end if
    if (nd == 2) then
      ! a plane mesh as tools/mesh_body.py writes it: the nodes, their volumes, boundary
      ! loops, the triangles and the median-dual cells (1-based CSR), read whole by each
      ! rank (build_body: read_particle_file_h5, read_mesh_extras)
      call h5_create(f, path, e2)
      if (.not. allocated(e2)) call h5_group(f, '/particles', e2)
      if (.not. allocated(e2)) call h5_write(f, '/particles/x', x, 'm', e2)
      if (.not. allocated(e2)) call h5_write(f, '/particles/volume', vol, 'm^2', e2)
      if (.not. allocated(e2)) call h5_write(f, '/particles/loop', loop, '1', e2)
      if (.not. allocated(e2)) call h5_write(f, '/particles/order', order, '1', e2)
      if (.not. allocated(e2)) call h5_group(f, '/mesh', e2)
      if (.not. allocated(e2)) call h5_write(f, '/mesh/triangles', tet, '1', e2)
      if (.not. allocated(e2)) call h5_group(f, '/cells', e2)
      if (.not. allocated(e2)) call h5_write(f, '/cells/ptr', ptr, '1', e2)
      if (.not. allocated(e2)) call h5_write(f, '/cells/xy', xy, 'm', e2)
      if (.not. allocated(e2)) call plane_facts(f, x, vol, tet, e2)
    else
      call tet_node_volumes(x, tet, vol)
      call h5_create(f, path, e2)
      if (.not. allocated(e2)) call h5_group(f, '/particles', e2)
      if (.not. allocated(e2)) call h5_write(f, '/particles/x', x, 'm', e2)
      if (.not. allocated(e2)) call h5_write(f, '/particles/volume', vol, 'm^3', e2)
      if (.not. allocated(e2)) call h5_group(f, '/mesh', e2)
      if (.not. allocated(e2)) call h5_write(f, '/mesh/tetrahedra', tet, '1', e2)
      ! (the index: each block of rows' box, for the ranks' reading of their parts)
      call mesh_index(x, tet, nbox, tbox)
      if (.not. allocated(e2)) call h5_write(f, '/mesh/node_box', nbox, 'm', e2)
      if (.not. allocated(e2)) call h5_write(f, '/mesh/tet_box', tbox, 'm', e2)
    end if
    if (.not. allocated(e2)) call h5_attr(f, '/', 'source', "mfcd_mpi: the mesh of '"// &
      trim(deck%bodies(k)%file)//"' (body "//itoa(k)//" of deck '"//deck%path// &
      "'), each rank's "//trim(merge('part', 'copy', nd == 3))//" read from here", e2)
    call h5_close(f, e2)
    if (allocated(e2)) call set_error(err, where//": the mesh of '"// &
      trim(deck%bodies(k)%file)//"' cannot be written to '"//path//"' for the ranks to "// &
      "read ("//e2%message//"); check the space in the directory of &output file", 1)
  end subroutine geo_mesh_file

  !> The whole plane mesh's facts a rank reading its part needs (tri_file_m), as attributes
  !! of f's group /mesh: the spacing make_from_arrays gives, the longest edge, the extent.
  subroutine plane_facts(f, x, vol, tri, err)
    type(h5file_t), intent(in) :: f
    real(wp), intent(in) :: x(:, :), vol(:)
    integer, intent(in) :: tri(:, :)
    type(error_t), allocatable, intent(inout) :: err
    call h5_attr(f, '/mesh', 'spacing', mean_spacing(vol, 2), err)
    if (.not. allocated(err)) call h5_attr(f, '/mesh', 'longest_edge', longest_edge(x, tri), err)
    if (.not. allocated(err)) call h5_attr(f, '/mesh', 'lo', minval(x, dim=2), err)
    if (.not. allocated(err)) call h5_attr(f, '/mesh', 'hi', maxval(x, dim=2), err)
  end subroutine plane_facts

  !> Body k's plane particle file (shape 'file', HDF5 with /mesh/triangles: what
  !! tools/mesh_body.py writes) read per part on ranks: the whole file's facts its readers
  !! need (plane_facts), which a user's file does not carry, written here once into the
  !! new file path (mfcd_mpi: rank 0, from the whole file, which it reads for its checks
  !! anyway) for every rank to read beside its part of the user's file (tri_file_share).
  !! The user's file is only read. A file that cannot be written is a failed run (exit 1).
  subroutine plane_facts_file(deck, k, path, err)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: x(:, :), vol(:), xy(:, :)
    integer, allocatable :: loop(:), order(:), tri(:, :), ptr(:)
    logical :: has_tri, has_cells
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    character(len=:), allocatable :: what
    what = "particle file '"//trim(deck%bodies(k)%file)//"'"
    call read_particle_file_h5(trim(deck%bodies(k)%file), 2, x, vol, loop, order, e2)
    if (.not. allocated(e2)) call read_mesh_extras(trim(deck%bodies(k)%file), size(x, 2), &
      has_tri, tri, has_cells, ptr, xy, e2)
    if (.not. allocated(e2) .and. .not. has_tri) call set_error(e2, what// &
      " has no /mesh/triangles")
    if (allocated(e2)) then
      ! (the whole build of the checks says what is wrong with the file first)
      call set_error(err, "deck '"//deck%path//"', group &body (body "//itoa(k)//", '"// &
        trim(deck%bodies(k)%name)//"'): "//e2%message, 2)
      return
    end if
    call h5_create(f, path, e2)
    if (.not. allocated(e2)) call h5_group(f, '/mesh', e2)
    if (.not. allocated(e2)) call plane_facts(f, x, vol, tri, e2)
    if (.not. allocated(e2)) call h5_attr(f, '/', 'source', "mfcd_mpi: the whole facts "// &
      "of "//what//" (body "//itoa(k)//" of deck '"//deck%path//"'), each rank's part "// &
      "read from that file", e2)
    call h5_close(f, e2)
    if (allocated(e2)) call set_error(err, "the facts of "//what//" cannot be written to '"// &
      path//"' for the ranks to read ("//e2%message//"); check the space in the "// &
      "directory of &output file", 1)
  end subroutine plane_facts_file

  !> The longest edge of the triangles tri over the nodes x (set_mesh_extras' lengths)
  pure real(wp) function longest_edge(x, tri) result(l)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: tri(:, :)
    integer :: e, k
    l = 0.0_wp
    do e = 1, size(tri, 2)
      do k = 1, 3
        l = max(l, norm2(x(:, tri(k, e)) - x(:, tri(modulo(k, 3) + 1, e))))
      end do
    end do
  end function longest_edge

  !> A body's error e2 as build_body reports it: a message that names its own place (it
  !! begins with where: geo_max_elements) as it is, else prefixed by where and the
  !! variables that make the shape.
  subroutine body_error(where, s, e2, err)
    character(len=*), intent(in) :: where
    type(body_spec_t), intent(in) :: s
    type(error_t), intent(in) :: e2
    type(error_t), allocatable, intent(inout) :: err
    if (index(e2%message, where) == 1) then
      call set_error(err, e2%message)
    else
      call set_error(err, where//', variable '//body_make_vars(s%shape)//': '//e2%message)
    end if
  end subroutine body_error

  !> The tetrahedra tet (4, ne) of a 3D particle file (/mesh/tetrahedra, (ne, 4) in h5py,
  !! 1-based rows of /particles/x; tools/mesh_body.py --3d), when it has them (has), over
  !! its particles x (3, np) with volumes vol: every node number in range, every
  !! tetrahedron of positive volume (tet_mesh_body orders nothing: a file's are as given),
  !! and the file's volumes those of the tetrahedra (each node's quarter of its
  !! tetrahedra, which the body takes) within vol_tol, so that a file whose columns
  !! disagree is refused rather than half used. what names the file.
  subroutine read_file_tets(path, what, x, vol, has, tet, err)
    character(len=*), intent(in) :: path, what
    real(wp), intent(in) :: x(:, :), vol(:)
    logical, intent(out) :: has
    integer, allocatable, intent(out) :: tet(:, :)
    type(error_t), allocatable, intent(inout) :: err
    !> the file's volumes against the tetrahedra's: a relative difference beyond this is
    !! not round-off (mesh_body.py writes the same sums in the same order: none at all)
    real(wp), parameter :: vol_tol = 1.0e-9_wp
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer, allocatable :: dims(:)
    integer(i64), allocatable :: tet8(:, :)
    real(wp), allocatable :: v4(:), ve(:)
    type(mesh_index_t) :: ix
    real(wp) :: v
    integer :: l, e, k, np
    has = .false.
    l = len_trim(path)
    if (.not. (l > 3 .and. (path(max(1, l - 2):l) == '.h5' .or. &
      path(max(1, l - 4):l) == '.hdf5'))) return
    np = size(x, 2)
    call h5_open_read(f, path, err)
    if (allocated(err)) return
    has = h5_has(f, '/mesh/tetrahedra')
    if (has) then
      call h5_shape(f, '/mesh/tetrahedra', dims, err)
      if (.not. allocated(err)) then
        if (size(dims) /= 2 .or. dims(1) /= 4) call set_error(err, what// &
          ": /mesh/tetrahedra must be (ne, 4) node numbers")
      end if
      if (.not. allocated(err)) then
        allocate(tet8(4, dims(2)))
        call h5_read(f, '/mesh/tetrahedra', tet8, err)
      end if
      if (.not. allocated(err)) then
        ! range-checked before the conversion to default integers
        if (size(tet8, 2) == 0) call set_error(err, what//": /mesh/tetrahedra is empty")
        if (any(tet8 < 1 .or. tet8 > np) .and. .not. allocated(err)) call file_error(err, &
          what, np, 1, 0, [0, 0, 0, 0], 0.0_wp)
      end if
      if (.not. allocated(err)) tet = int(tet8)
      ! (its index, if it has one: checked as the ranks reading it per part check it)
      if (.not. allocated(err)) call read_index(f, what, np, size(tet, 2), ix, err)
    end if
    call h5_close(f, e2)
    if (allocated(err) .or. .not. has) return
    ! (finite numbers first: no volume of a NaN or Infinity is computed)
    call check_file_values(what, x, vol, err)
    if (allocated(err)) return
    if (ix%has) then
      do k = 1, np
        if (node_outside(ix, k, x(:, k))) then
          call file_error(err, what, np, 3, k, tet(:, 1), 0.0_wp)
          return
        end if
      end do
    end if
    allocate(v4(np), ve(size(tet, 2)))
    v4 = 0.0_wp
    do e = 1, size(tet, 2)
      v = tet_volume(x, tet(:, e))
      ve(e) = v
      if (.not. (v > 0.0_wp)) then
        call file_error(err, what, np, 4, e, tet(:, e), v)
        return
      end if
    end do
    if (ix%has) then
      do e = 1, size(tet, 2)
        if (tet_outside(ix, e, x(:, tet(:, e)))) then
          call file_error(err, what, np, 5, e, tet(:, e), 0.0_wp)
          return
        end if
      end do
    end if
    do k = 1, 4
      do e = 1, size(tet, 2)
        v4(tet(k, e)) = v4(tet(k, e)) + 0.25_wp*ve(e)
      end do
    end do
    do k = 1, np
      if (.not. (abs(vol(k) - v4(k)) <= vol_tol*v4(k))) then
        call set_error(err, what//", particle "//itoa(k)//": its volume "//rtoa(vol(k))// &
          " m^3 is not its quarter of the tetrahedra it belongs to, "//rtoa(v4(k))// &
          " m^3 (a node in no tetrahedron has none): /particles/volume and "// &
          "/mesh/tetrahedra disagree; write the file with tools/mesh_body.py --3d")
        return
      end if
    end do
  end subroutine read_file_tets

  !> What an HDF5 particle file may add to its particles (tools/mesh_body.py writes both):
  !! /mesh/triangles (ne, 3 in h5py; 1-based rows of /particles/x), the elements of an FE
  !! body, and /cells/ptr, /cells/xy, each particle's integration cell (1-based CSR over the
  !! polygon vertices), for SCNI and Gauss. has_tri, has_cells: which of them the file has.
  subroutine read_mesh_extras(path, np, has_tri, tri, has_cells, ptr, xy, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: np
    logical, intent(out) :: has_tri, has_cells
    integer, allocatable, intent(out) :: tri(:, :), ptr(:)
    real(wp), allocatable, intent(out) :: xy(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer, allocatable :: dims(:)
    integer(i64), allocatable :: tri8(:, :), ptr8(:)
    logical :: is_h5
    integer :: l
    l = len_trim(path)
    is_h5 = l > 3 .and. (path(max(1, l - 2):l) == '.h5' .or. path(max(1, l - 4):l) == '.hdf5')
    has_tri = .false.
    has_cells = .false.
    if (.not. is_h5) return
    call h5_open_read(f, path, err)
    if (allocated(err)) return
    has_tri = h5_has(f, '/mesh/triangles')
    has_cells = h5_has(f, '/cells/ptr')
    if (has_cells) has_cells = h5_has(f, '/cells/xy')
    if (has_tri) then
      call h5_shape(f, '/mesh/triangles', dims, err)
      if (.not. allocated(err)) then
        if (size(dims) /= 2 .or. dims(1) /= 3) call set_error(err, "particle file '"// &
          path//"': /mesh/triangles must be (ne, 3) node numbers")
      end if
      if (.not. allocated(err)) then
        allocate(tri8(3, dims(2)))
        call h5_read(f, '/mesh/triangles', tri8, err)
      end if
      if (.not. allocated(err)) then
        ! range-checked before the conversion to default integers
        if (any(tri8 < 1 .or. tri8 > np)) call set_error(err, "particle file '"//path// &
          "': /mesh/triangles names a node outside 1.."//itoa(np))
      end if
      if (.not. allocated(err)) tri = int(tri8)
    end if
    if (has_cells .and. .not. allocated(err)) then
      call h5_shape(f, '/cells/xy', dims, err)
      if (.not. allocated(err)) then
        allocate(ptr8(np + 1), xy(2, dims(2)))
        call h5_read(f, '/cells/ptr', ptr8, err)
      end if
      if (.not. allocated(err)) call h5_read(f, '/cells/xy', xy, err)
      if (.not. allocated(err)) then
        ! checked before the conversion to default integers (set_mesh_extras checks again)
        if (ptr8(1) /= 1 .or. ptr8(np + 1) /= size(xy, 2) + 1 .or. &
          any(ptr8(2:) - ptr8(:np) < 3) .or. any(ptr8(2:) - ptr8(:np) > &
          max_cell_vertices)) call set_error(err, "particle file '"//path// &
          "': /cells/ptr must start at 1, end at the number of /cells/xy vertices + 1 "// &
          "and give every particle a polygon of 3 to "//itoa(max_cell_vertices)// &
          " vertices")
      end if
      if (.not. allocated(err)) ptr = int(ptr8)
    end if
    call h5_close(f, e2)
  end subroutine read_mesh_extras

  !> A mesh's triangles tri(3, ne) (when has_tri) and cells ptr, xy (when has_cells), from a
  !! particle file or a gmsh script (what names it), onto body b: an FE body's elements
  !! (mode dynamic), the integration cells, and local(i), the longest edge of the triangles
  !! at particle i, from which the supports follow a graded mesh. Errors name what is
  !! missing for the body's discretization and integration.
  subroutine set_mesh_extras(what, s, dynamic, has_tri, tri, has_cells, ptr, xy, b, local, err)
    character(len=*), intent(in) :: what
    type(body_spec_t), intent(in) :: s
    logical, intent(in) :: dynamic    !< mode dynamic: the discretization needs its data
    logical, intent(in) :: has_tri, has_cells
    integer, allocatable, intent(in) :: tri(:, :), ptr(:)
    real(wp), allocatable, intent(in) :: xy(:, :)
    type(body_t), intent(inout) :: b
    real(wp), allocatable, intent(inout) :: local(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: e, k, i, j, ne
    real(wp) :: len_e
    if (has_tri) then
      if (any(tri < 1 .or. tri > b%np)) then
        call set_error(err, what//": /mesh/triangles names a node outside 1.."//itoa(b%np))
        return
      end if
    end if
    if (has_cells) then
      if (size(ptr) /= b%np + 1) then
        call set_error(err, what//": /cells/ptr must have one entry per particle and one "// &
          "more")
        return
      end if
      if (ptr(1) /= 1 .or. ptr(b%np + 1) /= size(xy, 2) + 1 .or. &
        any(ptr(2:) - ptr(:b%np) < 3) .or. any(ptr(2:) - ptr(:b%np) > &
        max_cell_vertices)) then
        call set_error(err, what//": /cells/ptr must start at 1, end at the number of "// &
          "/cells/xy vertices + 1 and give every particle a polygon of 3 to "// &
          itoa(max_cell_vertices)//" vertices")
        return
      end if
    end if
    if (s%discretization == 'fem' .and. dynamic) then
      if (.not. has_tri) then
        call set_error(err, what//" has no /mesh/triangles: an FE body needs its elements "// &
          "(tools/mesh_body.py writes them), or discretization = 'rkpm'")
        return
      end if
      b%cells = tri
    end if
    if (has_cells) then
      b%cell_ptr = ptr
      b%cell_xy = xy
    end if
    if (has_tri) then
      ne = size(tri, 2)
      allocate(local(b%np))
      local = 0.0_wp
      do e = 1, ne
        do k = 1, 3
          i = tri(k, e)
          j = tri(modulo(k, 3) + 1, e)
          len_e = norm2(b%x(:, i) - b%x(:, j))
          local(i) = max(local(i), len_e)
          local(j) = max(local(j), len_e)
        end do
      end do
      if (any(local <= 0.0_wp)) then
        call set_error(err, what//": a particle belongs to no triangle of /mesh/triangles "// &
          "(or a triangle is degenerate)")
        return
      end if
    end if
  end subroutine set_mesh_extras

  !> Plain columns, one particle a line: x [y [z]] volume [loop order]; '#' starts a comment.
  !! loop = 0 for interior particles, k > 0 for particles on boundary polyline k, with order
  !! their position along it (counter-clockwise around the material). Every line has the
  !! same columns, ndim + 1 or ndim + 3 of them (a file of another dimension has others);
  !! volumes are positive, loop and order whole numbers.
  subroutine read_particle_columns(path, ndim, x, vol, loop, order, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ndim
    real(wp), allocatable, intent(out) :: x(:, :), vol(:)
    integer, allocatable, intent(out) :: loop(:), order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: u, ios, n, lineno, i, nf, nf1, line1
    character(len=1024) :: line
    character(len=512) :: msg
    real(wp) :: vals(5)
    integer :: lo_or(2)
    character(len=:), allocatable :: at, hint
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(err, "particle file '"//path//"': "//trim(msg))
      return
    end if
    n = 0
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (is_data(line)) n = n + 1
    end do
    allocate(x(ndim, n), vol(n), loop(n), order(n))
    rewind(u)
    i = 0
    lineno = 0
    nf1 = 0
    line1 = 0
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      lineno = lineno + 1
      if (.not. is_data(line)) cycle
      i = i + 1
      at = "particle file '"//path//"' line "//itoa(lineno)
      nf = count_fields(line)
      if (nf /= ndim + 1 .and. nf /= ndim + 3) then
        call set_error(err, at//" has "//itoa(nf)//" columns; a "//itoa(ndim)//"-D deck "// &
          "reads "//columns_text(ndim)//", "//itoa(ndim + 1)//" or "//itoa(ndim + 3)// &
          " columns"//trim(other_dim_hint(nf, ndim)))
        close(u)
        return
      end if
      if (nf1 == 0) then
        nf1 = nf
        line1 = lineno
      else if (nf /= nf1) then
        call set_error(err, at//" has "//itoa(nf)//" columns and line "//itoa(line1)// &
          " has "//itoa(nf1)//"; give every particle the same columns ("// &
          columns_text(ndim)//")")
        close(u)
        return
      end if
      read(line, *, iostat=ios) vals(1:ndim + 1)
      if (ios /= 0) then
        call set_error(err, at//": expected "//itoa(ndim)//" coordinates and a volume, "// &
          "numbers ("//columns_text(ndim)//")")
        close(u)
        return
      end if
      if (.not. all(ieee_is_finite(vals(1:ndim + 1)))) then
        call set_error(err, at//": a coordinate or the volume is not a finite number (NaN "// &
          "or Infinity); fix the file")
        close(u)
        return
      end if
      if (.not. vals(ndim + 1) > 0.0_wp) then
        hint = ''
        if (ndim == 2 .and. nf == 3) hint = '; is the third column a z coordinate?'
        call set_error(err, at//": volume (column "//itoa(ndim + 1)//") = "// &
          rtoa(vals(ndim + 1))//" must be positive ("//columns_text(ndim)//hint//")")
        close(u)
        return
      end if
      x(:, i) = vals(1:ndim)
      vol(i) = vals(ndim + 1)
      lo_or = 0
      if (nf == ndim + 3) then
        read(line, *, iostat=ios) vals(1:ndim + 1), lo_or
        if (ios /= 0) then
          call set_error(err, at//": loop and order (columns "//itoa(ndim + 2)//" and "// &
            itoa(ndim + 3)//") must be whole numbers")
          close(u)
          return
        end if
      end if
      loop(i) = lo_or(1)
      order(i) = lo_or(2)
    end do
    close(u)
  contains
    pure logical function is_data(l)
      character(len=*), intent(in) :: l
      character(len=len(l)) :: t
      t = adjustl(l)
      is_data = len_trim(t) > 0 .and. t(1:1) /= '#'
    end function is_data

    !> Fields separated by blanks, tabs or commas.
    pure integer function count_fields(l) result(nf)
      character(len=*), intent(in) :: l
      integer :: k
      logical :: in_field, sep
      nf = 0
      in_field = .false.
      do k = 1, len_trim(l)
        sep = index(' ,'//achar(9)//achar(13), l(k:k)) > 0
        if (.not. sep .and. .not. in_field) nf = nf + 1
        in_field = .not. sep
      end do
    end function count_fields

    !> "; 4 columns fit a 3-D file ..." when nf columns fit a file of another dimension
    !! (without loop and order columns first: x y z volume rather than x volume loop order).
    pure function other_dim_hint(nf, nd) result(h)
      integer, intent(in) :: nf, nd
      character(len=:), allocatable :: h
      integer :: d, extra
      h = ''
      do extra = 1, 3, 2
        do d = 3, 1, -1
          if (d /= nd .and. nf == d + extra) then
            h = '; '//itoa(nf)//' columns fit a '//itoa(d)//'-D file ('//columns_text(d)// &
              '): set &run ndim = '//itoa(d)//' or drop the extra columns'
            return
          end if
        end do
      end do
    end function other_dim_hint
  end subroutine read_particle_columns
end module body_setup_m
