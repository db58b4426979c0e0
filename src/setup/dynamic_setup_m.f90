!> Set-up of a dynamic run: the one place that turns the deck into the plain inputs of the
!! lower layers. For each deformable body it builds the discretization tables (RKPM by
!! rkpm_tl_m; CST4 elements by cst4_m), the kinematic-condition masks from the deck's &bc
!! boxes, and the solid; for each &contact group a contact pair; and it chooses the time
!! step. Every error names the deck, the group and the variable.
module dynamic_setup_m
  use, intrinsic :: iso_fortran_env, only: output_unit
  use omp_lib, only: omp_get_wtime
  use kinds_m, only: wp
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa, rtoa
  use deck_m, only: deck_t, body_spec_t
  use body_m, only: body_t
  use rank_comm_m, only: rank_comm_t, share_first
  use exact_sum_m, only: exact_sum_t, exact_add, exact_allsum
  use sorting_m, only: sorted_place
  use generators_m, only: extrude_pick, body_pick, body_count, polygon_merges, lattice_corners
  use decomposition_m, only: rcb_tree_t, rcb_build_ranks, rcb_box, rcb_part, region_of, &
    region_rows
  use solid_tables_m, only: solid_tables_t
  use rkpm_tl_m, only: tl_build, scheme_id, tl_region_2d
  use rkpm_tl3d_m, only: tl_build_3d, symmetry_planes_3d, tl_region_3d
  use cst4_m, only: cst4_mesh_t, cst4_tables, cst4_region
  use tet4_m, only: tet4_mesh_t, tet4_tables, tet4_region
  use tet_file_m, only: tet_file_region, tet_file_count
  use tri_file_m, only: tri_file_region, tri_file_count, tri_file_positions
  use body_setup_m, only: file_slab
  use side_surface_m, only: side_surface
  use solid_m, only: solid_t, solid_init, solid_quiet_init, solid_set_gravity, solid_add_spin, &
    solid_np_whole, solid_nq_whole
  use material_m, only: material_constant_names, material_constant
  use stable_step_m, only: step_control_t, step_control_calibrate, spacing_step
  use contact_pair_m, only: side_loop_surface, contact_pair_t, contact_params_t, &
    contact_pair_init, &
    detector_det_m, detector_nts, detector_name, side_facts_t
  use rk_cloud_m, only: rk_cloud_t, cloud_init
  use detection_m, only: share_det_medians, deep_particles, det_at_points
  implicit none
  private
  public :: setup_solids, setup_contacts, setup_time_step, dynamic_setup_t, setup_dynamic
  public :: mpi_scene_check, setup_part_t, root_needs_whole, body_per_part
  public :: side_facts_local

  !> The rank a set-up is for (mfcd_mpi): rank me (from 0) of nranks. A rank keeps, of a
  !! solid's tables, only the rows its box of the decomposition can need (the builders'
  !! box, region_box; the box is decomposition_m's, the one the split cuts the solid
  !! with); rank 0 keeps the whole tables when root_whole: its det(M) fields are
  !! drawn from the whole solids (root_needs_whole).
  type :: setup_part_t
    integer :: me = 0
    integer :: nranks = 1
    logical :: root_whole = .true.
    !> the ranks (for the sums that complete what each rank built of its box)
    class(rank_comm_t), pointer :: comm => null()
  end type setup_part_t

  !> What the set-up of a dynamic run builds before anything is written: the solids of the
  !! deformable bodies (isolid(k): body k's solid, 0 if rigid) and the contact pairs.
  !> A rank's region of a solid in a decomposed set-up: the numbers of the particles its
  !! tables' rows touch or its box holds (ascending), a superset of its part's nodes
  type :: region_rows_t
    integer, allocatable :: glob(:)
    !> the particles of the body the rank made for its region (tl_region_3d), and glob's
    !! places among them, when it made them: a slave's contact side against a rigid
    !! master is set up from them (the whole body is not on the rank)
    type(body_t), allocatable :: body
    integer, allocatable :: places(:)
  end type region_rows_t

  type :: dynamic_setup_t
    type(solid_t), allocatable :: solids(:)
    integer, allocatable :: isolid(:)
    type(contact_pair_t), allocatable :: pairs(:)
    !> on ranks each solid's bisection (region_box), which the split cuts it by (one
    !! part, no cut: serially)
    type(rcb_tree_t), allocatable :: trees(:)
    real(wp) :: wall0 = 0.0_wp             !< wall clock when the set-up began (s)
  end type dynamic_setup_t

contains

  !> Whether rank 0 of an MPI run needs the whole solids after the split: for the det(M)
  !! fields on a plane grid its snapshots draw from the gathered state (&output
  !! det_fields). Otherwise every rank keeps its region only.
  pure logical function root_needs_whole(deck) result(yes)
    type(deck_t), intent(in) :: deck
    yes = deck%output%det_fields
  end function root_needs_whole

  !> The whole set-up of a dynamic run (solids, kinematic conditions, contact pairs), made
  !! once, before anything is written, by a run and by --check alike; its errors are bad
  !! input. quiet: without its log lines.
  subroutine setup_dynamic(deck, bodies, su, err, quiet, part)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(dynamic_setup_t), intent(out) :: su
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: quiet
    type(setup_part_t), intent(in), optional :: part
    type(region_rows_t), allocatable :: regions(:)
    su%wall0 = omp_get_wtime()
    if (.not. present(quiet)) then
      call log_materials(deck)
    else if (.not. quiet) then
      call log_materials(deck)
    end if
    call setup_solids(deck, bodies, su%solids, su%isolid, err, quiet, part, regions, &
      su%trees)
    if (.not. allocated(err)) call setup_contacts(deck, bodies, su%solids, su%isolid, &
      su%pairs, err, quiet, regions, part)
    if (allocated(err)) return
    if (.not. present(quiet)) then
      call scale_warnings(deck, bodies, su%solids, su%isolid)
    else if (.not. quiet) then
      call scale_warnings(deck, bodies, su%solids, su%isolid)
    end if
  end subroutine setup_dynamic

  !> Warnings (not errors) of a likely unit mistake, with the mistake named: a material's
  !! dilatational wave speed outside 100-20,000 m/s (solids: rubber-like to beryllium; E
  !! in MPa or GPa gives 30-1000 times less, a density in g/cm^3 thirty times more), a
  !! body smaller than 1 um or larger than 100 m across (lengths in mm or um), a run that
  !! ends in fewer than 10 steps (t_end in us, or lengths in mm that make every step 1000
  !! times longer). The step count is estimated from the smallest h_min/c_d times cfl
  !! (or the deck's fixed dt); the power iteration of the run is not made for --check.
  subroutine scale_warnings(deck, bodies, solids, isolid)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: isolid(:)
    real(wp), parameter :: c_low = 100.0_wp, c_high = 2.0e4_wp   ! m/s
    real(wp), parameter :: size_low = 1.0e-6_wp, size_high = 100.0_wp   ! m
    integer, parameter :: steps_low = 10
    real(wp) :: c, ext, dt, nsteps, nowhere(2)
    integer :: k, j, none(2)
    type(body_t) :: ends
    none = 0
    nowhere = 0.0_wp
    dt = huge(1.0_wp)
    do k = 1, size(bodies)
      if (allocated(bodies(k)%mfile)) then
        ! (a rank's share of a mesh file: the whole one's extent, read)
        ext = maxval(bodies(k)%mfile%hi - bodies(k)%mfile%lo)
      else if (bodies(k)%held_share) then
        ! (a rank's share of an extruded body: the whole one's extent is its first and
        ! last layers'; of a rectangle, its outermost ring's)
        call body_pick(bodies(k), 1, bodies(k)%np, [(-huge(1.0_wp), j = 1, 3)], &
          [(huge(1.0_wp), j = 1, 3)], 0, none, nowhere, ends, ends=.true.)
        ext = maxval(maxval(ends%x, dim=2) - minval(ends%x, dim=2))
      else
        ext = maxval(maxval(bodies(k)%x, dim=2) - minval(bodies(k)%x, dim=2))
      end if
      if (ext > size_high) call warn("body '"//trim(bodies(k)%name)//"' is "// &
        rtoa(ext)//' m across, outside 1 um - 100 m: lengths are in m (a length in mm '// &
        'is 1000 times too large, in um 1e6 times)')
      if (ext < size_low) call warn("body '"//trim(bodies(k)%name)//"' is "// &
        rtoa(ext)//' m across, outside 1 um - 100 m: lengths are in m (an exponent '// &
        'slipped: e-9 for e-3, or a length in km)')
      if (isolid(k) == 0) cycle
      associate (s => solids(isolid(k)))
        c = s%mat%dilatational_speed()
        if (c < c_low) call warn("body '"//trim(bodies(k)%name)//"': material wave "// &
          'speed c_d = '//rtoa(c)//' m/s is below 100 m/s: youngs_modulus is in Pa (E '// &
          'in MPa gives 1/30 of the speed, in GPa 1/1000), density in kg/m^3')
        if (c > c_high) call warn("body '"//trim(bodies(k)%name)//"': material wave "// &
          'speed c_d = '//rtoa(c)//' m/s is above 20,000 m/s: density is in kg/m^3 (a '// &
          'density in g/cm^3 gives 30 times the speed), youngs_modulus in Pa')
        dt = min(dt, s%t%hmin/c)
      end associate
    end do
    dt = deck%solver%cfl*dt
    if (deck%solver%dt > 0.0_wp) dt = deck%solver%dt
    nsteps = deck%solver%t_end/dt
    if (nsteps < real(steps_low, wp)) call warn('the run ends in about '// &
      rtoa(nsteps)//' steps of '//rtoa(dt)//' s (fewer than 10): t_end = '// &
      rtoa(deck%solver%t_end)//' s is in s (1 us = 1e-6), lengths in m (lengths in mm '// &
      'make every step 1000 times longer)')

  contains

    subroutine warn(text)
      character(len=*), intent(in) :: text
      write(output_unit, '(a)') 'warning: '//text
    end subroutine warn
  end subroutine scale_warnings

  !> Every constant of every material as the run uses it, and where it came from: the deck
  !! ('given'), its preset, or the model's default (b and theta only).
  subroutine log_materials(deck)
    type(deck_t), intent(in) :: deck
    integer :: k, j
    character(len=:), allocatable :: line
    do k = 1, deck%nmaterials
      associate (m => deck%materials(k))
        line = 'material '''//trim(m%name)//''' ('//trim(m%params%model)
        if (len_trim(m%preset) > 0) line = line//', preset '''//trim(m%preset)//''''
        line = line//'):'
        do j = 1, size(material_constant_names)
          if (len_trim(m%source(j)) == 0) cycle
          line = line//' '//trim(material_constant_names(j))//' '// &
            rtoa(material_constant(m%params, j))//' ('//trim(m%source(j))//')'
        end do
        write(output_unit, '(a)') line
      end associate
    end do
  end subroutine log_materials

  !> The solids of the deck's deformable bodies, in deck order; isolid(k) is body k's solid
  !! (0 for a rigid body). quiet: no log lines (a set-up made only for its checks).
  subroutine setup_solids(deck, bodies, solids, isolid, err, quiet, part, regions, trees)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in) :: bodies(:)
    type(solid_t), allocatable, intent(out) :: solids(:)
    integer, allocatable, intent(out) :: isolid(:)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: quiet
    type(setup_part_t), intent(in), optional :: part
    !> on a rank of a decomposed set-up, each solid's region (setup_solid's rows) and
    !! bisection (setup_solid's tree)
    type(region_rows_t), allocatable, intent(out) :: regions(:)
    type(rcb_tree_t), allocatable, intent(out) :: trees(:)
    integer :: k, n, ndef
    logical :: axisym
    axisym = deck%run%geometry == 'axisymmetric'
    allocate(isolid(deck%nbodies))
    isolid = 0
    ndef = 0
    do k = 1, deck%nbodies
      if (deck%bodies(k)%role /= 'deformable') cycle
      ndef = ndef + 1
      isolid(k) = ndef
    end do
    if (ndef == 0) then
      call set_error(err, "deck '"//deck%path//"': mode = 'dynamic' needs at least one "// &
        "deformable body (role = 'deformable')")
      return
    end if
    allocate(solids(ndef), regions(ndef), trees(ndef))
    do k = 1, deck%nbodies
      n = isolid(k)
      if (n == 0) cycle
      call setup_solid(deck, k, bodies(k), axisym, solids(n), err, part, regions(n), &
        trees(n))
      if (allocated(err)) return
      if (present(quiet)) then
        if (quiet) cycle
      end if
      write(output_unit, '(a)') 'dynamic: body '''//trim(bodies(k)%name)//''': '// &
        itoa(solid_np_whole(solids(n)))//' nodes, '//itoa(solid_nq_whole(solids(n)))// &
        ' integration points ('// &
        discretization_text(deck%bodies(k), bodies(k)%ndim)//'), material '''// &
        trim(deck%materials(deck%bodies(k)%imat)%name)//''' ('// &
        solids(n)%mat%model_name()//'), mass '//rtoa(solids(n)%t%total_mass)//' kg'// &
        trim(merge('/m', '  ', .not. axisym .and. bodies(k)%ndim == 2))//'; '// &
        entries_text(solids(n)%t, solid_nq_whole(solids(n)))
      flush(output_unit)
    end do
  end subroutine setup_solids

  !> The tables' entries for the log: all of them, or (a rank's region of a decomposed
  !! set-up, the builders' box) those of the points it kept; nq: the whole solid's points.
  function entries_text(t, nq) result(txt)
    type(solid_tables_t), intent(in) :: t
    integer, intent(in) :: nq
    character(len=:), allocatable :: txt
    integer :: nk
    nk = count(t%ptr(2:t%nq + 1) > t%ptr(1:t%nq))
    txt = itoa(size(t%nbr))//' point-node entries'
    if (nk < nq) txt = txt//" in this rank's region ("//itoa(nk)//' points)'
    txt = txt//' (mean '//itoa(nint(real(size(t%nbr))/real(max(nk, 1))))//' nodes per point)'
  end function entries_text

  pure function discretization_text(s, nd) result(txt)
    type(body_spec_t), intent(in) :: s
    integer, intent(in) :: nd
    character(len=:), allocatable :: txt
    if (s%discretization == 'fem' .and. nd == 3) then
      txt = 'linear tetrahedra with averaged nodal pressure, one point each'
    else if (s%discretization == 'fem') then
      txt = 'CST4 elements, one point each'
    else
      txt = 'RKPM, '//trim(s%integration)
    end if
  end function discretization_text

  !> The solid of deformable body k.
  subroutine setup_solid(deck, k, b, axisym, s, err, part, reg, tree)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(body_t), intent(in), target :: b
    logical, intent(in) :: axisym
    type(solid_t), intent(out) :: s
    type(error_t), allocatable, intent(inout) :: err
    type(setup_part_t), intent(in), optional :: part
    !> with part, when the solid is a shell: its region (region_of: glob), and the body
    !! made for it (tl_region_3d) with the region's places in it
    type(region_rows_t), intent(out), target :: reg
    !> with part on more than one rank: the bisection of its nodes the split will cut it
    !! by (region_box's), the same on every rank
    type(rcb_tree_t), intent(out) :: tree
    type(body_spec_t) :: bs
    type(solid_tables_t) :: t
    type(error_t), allocatable :: e2
    logical, allocatable :: pres(:, :)
    real(wp), allocatable :: vpres(:, :)
    integer, allocatable :: bc_of(:, :)
    character(len=:), allocatable :: where
    type(cst4_mesh_t) :: mesh
    type(tet4_mesh_t) :: tmesh
    real(wp) :: alpha, box(3, 2)
    logical :: split, shell, region, ok
    integer, allocatable :: qrows(:), at(:)
    integer :: nq_whole, j
    !> the body the solid is made of: b, or on a rank the particles of b its region needs
    !! (made from b's recipe: tl_region_3d)
    type(body_t), pointer :: bp
    integer, allocatable :: rows(:)
    !> a region's tetrahedra made from the recipe (tet4_region): their whole mesh's numbers
    integer, allocatable :: eglob(:)
    integer :: ne_whole
    real(wp) :: grow(3), hneg(1)
    bs = deck%bodies(k)
    bp => b
    where = "deck '"//deck%path//"', group &body (body "//itoa(k)//", '"//trim(b%name)//"')"
    if (allocated(b%cells) .and. b%ndim == 3) then
      ! linear tetrahedra with averaged nodal pressure (tet4_m); on a rank, the rows of the
      ! elements of its region (the masses and the rest whole: no sum over the ranks)
      if (region_box(part, b, tree, box)) then
        if (b%held_share) then
          ! (a body no rank holds whole: the rank's tetrahedra and nodes made from its
          ! recipe, tet4_region; the smallest height and the total mass over the ranks)
          allocate(reg%body)
          if (allocated(b%mfile)) then
            ! (a mesh file's: the rows of its tetrahedra within the same reach of the box,
            ! read from the file, tet_file_m; the longest edge the whole mesh's)
            ne_whole = b%mfile%ne
            grow = 2.0_wp*b%mfile%lmax + maxval(b%spacing)
            call tet_file_region(b, box(:, 1) - grow, box(:, 2) + grow, reg%body, e2, &
              tmesh, eglob)
          else
            call tet4_region(b, box, reg%body, tmesh, eglob, ne_whole, e2)
          end if
          bp => reg%body
          if (.not. allocated(e2)) call tet4_tables(bp, tmesh, &
            deck%materials(bs%imat)%params%density, t, e2, box)
          call region_tet_sums(part, tree, bp, t, e2)
          if (allocated(b%mfile)) then
            call log_made(part, b, bp%np, "region's tetrahedra read from its mesh file", &
              ' (nodes)', .not. allocated(e2))
          else
            call log_made(part, b, bp%np, "region's tetrahedra from the body's section "// &
              'and layers', ' (nodes)', .not. allocated(e2))
          end if
        else
          tmesh%ne = size(b%cells, 2)
          tmesh%tet = b%cells
          call tet4_tables(b, tmesh, deck%materials(bs%imat)%params%density, t, e2, box)
        end if
      else
        tmesh%ne = size(b%cells, 2)
        tmesh%tet = b%cells
        call tet4_tables(b, tmesh, deck%materials(bs%imat)%params%density, t, e2)
      end if
      alpha = 0.0_wp
    else if (allocated(b%cells)) then
      ! CST4: on a rank, the rows of the triangles of its region (the masses whole)
      if (region_box(part, b, tree, box)) then
        if (b%held_share) then
          ! (a rectangle or annulus no rank holds whole: the rank's triangles and nodes made from its
          ! lattice's recipe, cst4_region; the smallest altitude and the total mass over
          ! the ranks)
          allocate(reg%body)
          if (allocated(b%mfile)) then
            ! (a plane mesh file's: the triangles within the reach of the box that holds
            ! every triangle whose rows the box keeps and every triangle touching their
            ! nodes, read from the file, tri_file_m; the longest edge the whole mesh's)
            ne_whole = b%mfile%ne
            grow = 2.0_wp*b%mfile%lmax + maxval(b%spacing)
            call tri_file_region(b, box(:, 1) - grow, box(:, 2) + grow, reg%body, e2, &
              mesh, eglob)
          else
            call cst4_region(b, box, reg%body, mesh, eglob, ne_whole)
          end if
          bp => reg%body
          if (.not. allocated(e2)) call cst4_tables(bp, mesh, axisym, &
            deck%materials(bs%imat)%params%density, t, e2, box)
          call region_tet_sums(part, tree, bp, t, e2)
          if (allocated(b%mfile)) then
            call log_made(part, b, bp%np, "region's triangles read from its mesh file", &
              ' (nodes)', .not. allocated(e2))
          else
            call log_made(part, b, bp%np, "region's triangles from the "//trim(b%shape)// &
              "'s lattice", ' (nodes)', .not. allocated(e2))
          end if
        else
          mesh%ne = size(b%cells, 2)
          mesh%tri = b%cells
          call cst4_tables(b, mesh, axisym, deck%materials(bs%imat)%params%density, t, &
            e2, box)
        end if
      else
        mesh%ne = size(b%cells, 2)
        mesh%tri = b%cells
        call cst4_tables(b, mesh, axisym, deck%materials(bs%imat)%params%density, t, e2)
      end if
      alpha = 0.0_wp    ! the SCNI stabilization is a particle method's; elements need none
    else
      ! RKPM: on a rank, the rows of the points its region can need, the masses completed
      ! over the ranks
      if (b%ndim == 3) then
        if (region_box(part, b, tree, box)) then
          if (region_made(deck, k, part, b)) then
            allocate(reg%body)
            if (allocated(b%mfile)) then
              ! (a mesh file's: the nodes the box's cells and their covering particles
              ! reach, by the supports near the box, and the tetrahedra all of whose nodes
              ! are among them, read: tet_file_m)
              call tet_file_region(b, box(:, 1), box(:, 2), reg%body, e2, tmesh, eglob, &
                supports=.true.)
              if (.not. allocated(e2)) call move_alloc(tmesh%tet, reg%body%tets)
              ! (an RKPM solid's points are its particles, not the tetrahedra)
              if (allocated(eglob)) deallocate(eglob)
              bp => reg%body
              call log_made(part, b, bp%np, 'region read from its mesh file', '', &
                .not. allocated(e2))
            else
              call tl_region_3d(b, box, reg%body)
              bp => reg%body
              call log_made(part, b, bp%np, "region from the body's section and layers", &
                '', .true.)
            end if
          end if
          if (.not. allocated(e2)) call tl_build_3d(bp, &
            deck%materials(bs%imat)%params%density, t, e2, box)
        else
          call tl_build_3d(b, deck%materials(bs%imat)%params%density, t, e2)
        end if
      else
        if (region_box(part, b, tree, box)) then
          if (region_made(deck, k, part, b)) then
            allocate(reg%body)
            if (allocated(b%mfile)) then
              ! (a plane mesh file's: the nodes within what tl_build's region cloud takes
              ! of the box, twice the largest support, a cell (within two longest edges
              ! of its node: a median-dual cell lies in the node's triangles) and a
              ! spacing, one spacing more; with their cells, read: tri_file_m)
              grow = 0.0_wp
              grow(1:2) = 2.0_wp*b%support_factor(1:2)*b%mfile%lmax + &
                2.0_wp*b%mfile%lmax + 2.0_wp*b%spacing(1:2)
              call tri_file_region(b, box(:, 1) - grow, box(:, 2) + grow, reg%body, e2)
              bp => reg%body
              call log_made(part, b, bp%np, 'region read from its mesh file', '', &
                .not. allocated(e2))
            else
              ! (a rectangle or polygon no rank holds whole: the rank's region made from
              ! its recipe)
              call tl_region_2d(b, axisym, box, reg%body)
              bp => reg%body
              call log_made(part, b, bp%np, 'region from the '//trim(b%shape)// &
                "'s lattice", '', .true.)
            end if
          end if
          if (.not. allocated(e2)) call tl_build(bp, axisym, scheme_id(bs%integration), &
            deck%materials(bs%imat)%params%density, t, e2, box)
        else
          call tl_build(b, axisym, scheme_id(bs%integration), &
            deck%materials(bs%imat)%params%density, t, e2)
        end if
      end if
      ! (every rank, after an error too: collective; every rank takes the same branch)
      split = .false.
      if (present(part)) split = part%nranks > 1
      if (split) then
        if (region_solid_do(deck, k, part)) then
          call region_masses(part, tree, bp, t, box, rows, e2)
        else
          call whole_masses(part, tree, b, t, e2)
        end if
        ! (a mesh file's: the smallest height of the region's tetrahedra, the least over
        ! the ranks, as every tetrahedron is in some rank's region: the serial minimum)
        if (allocated(b%mfile) .and. b%ndim == 3) then
          hneg = -t%hmin
          call part%comm%max_real(hneg)
          t%hmin = -hneg(1)
        end if
      end if
      alpha = bs%stabilization
    end if
    if (allocated(e2)) then
      call set_error(err, where//": "//e2%message)
      return
    end if
    ! on ranks a shell (but on rank 0 when it keeps the whole solids for its det(M)
    ! fields): what the split reads of the whole solid, without its state
    shell = .false.
    if (present(part)) shell = part%me > 0 .or. .not. part%root_whole
    if (shell .and. .not. allocated(rows)) call region_of(t, bp, box, rows)
    region = .false.
    if (shell) region = region_solid_do(deck, k, part)
    ! (a region shell's conditions at its region's particles only)
    if (region) then
      at = rows
    else
      at = [(j, j = 1, b%np)]
    end if
    call kinematic_masks(deck, k, bp, pres, vpres, bc_of, err, at)
    if (allocated(err)) return
    if (b%ndim == 3) call symmetry_holds(bp, at, pres, vpres)
    deallocate(at)
    if (region) then
      ! the shell numbered over its region: its tables, positions, conditions and
      ! velocities at the region's particles and the points whose rows it kept, with the
      ! maps to the whole solid's numbers (what the split reads of it, mpi_domain_m)
      nq_whole = t%nq
      call region_rows(t, rows, qrows, ok)
      if (.not. ok) call set_error(e2, "the region of this rank lacks a particle its "// &
        "kept rows touch (an internal error of the set-up)")
      if (.not. allocated(e2)) call solid_init(s, b%name, t, bp%x(:, rows), &
        deck%materials(bs%imat)%params, alpha, bs%velocity(1:b%ndim), pres, vpres, e2, &
        shell)
      if (.not. allocated(e2)) then
        s%part%region = .true.
        ! (a region body's places as the whole body's numbers; its points are its
        ! particles)
        if (allocated(bp%glob)) then
          reg%places = rows
          rows = bp%glob(rows)
          if (allocated(eglob)) then
            ! (a region's tetrahedra: their numbers in the whole mesh)
            qrows = eglob(qrows)
            nq_whole = ne_whole
          else
            qrows = bp%glob(qrows)
            nq_whole = bp%np_whole
          end if
        end if
        call move_alloc(qrows, s%part%qglob)
        s%part%nglob = rows
        s%part%np_whole = b%np
        s%part%nq_whole = nq_whole
      end if
    else
      call solid_init(s, b%name, t, b%x, deck%materials(bs%imat)%params, alpha, &
        bs%velocity(1:b%ndim), pres, vpres, e2, shell)
    end if
    if (allocated(e2)) then
      call set_error(err, where//": "//e2%message)
      return
    end if
    call move_alloc(bc_of, s%bc_of)
    ! the foot-radius band of body_measures: one nominal spacing
    s%spacing = minval(b%spacing(1:b%ndim))
    call solid_set_gravity(s, deck%run%gravity(1:b%ndim))
    if (bs%angular_velocity /= 0.0_wp) call solid_add_spin(s, bs%angular_velocity)
    ! (quiet points are skipped by the serial driver only: a part has none)
    if (deck%solver%skip_quiet .and. .not. shell) then
      call solid_quiet_init(s, bs%velocity(1:b%ndim))
      ! quiet points are those still in the uniform initial motion: under gravity or a
      ! spin no point is (a free fall strains nothing, but the skipping does not know it)
      if (any(deck%run%gravity /= 0.0_wp) .or. bs%angular_velocity /= 0.0_wp) then
        s%quiet_on = .false.
        s%all_awake = .true.
        s%awake = .true.
        s%qact = .true.
      end if
    end if
    ! (read_deck refuses subcycle for anything but element meshes against rigid masters)
    s%sub%on = deck%solver%subcycle .and. s%t%interpolating
    if (allocated(rows)) call move_alloc(rows, reg%glob)
  end subroutine setup_solid

  !> The box of this rank's region of body b for the set-up of its tables (the box of
  !! rkpm_tl3d_m tl_build_3d, rkpm_tl_m tl_build, tet4_m tet4_tables and cst4_m
  !! cst4_tables; in 2D its first two rows; tree: the bisection the split will make,
  !! mpi_domain_m make_part, built when the run has ranks). On one rank of mfcd_mpi the
  !! whole space: every cell or element, without the transpose the split makes again.
  !! .false.: no box (a serial run; rank 0 when it keeps the whole solids for its det(M)
  !! fields, setup_part_t).
  logical function region_box(part, b, tree, box) result(has)
    type(setup_part_t), intent(in), optional :: part
    type(body_t), intent(in) :: b
    type(rcb_tree_t), intent(out) :: tree
    real(wp), intent(out) :: box(3, 2)
    box(:, 1) = -huge(1.0_wp)
    box(:, 2) = huge(1.0_wp)
    has = .false.
    if (.not. present(part)) return
    if (part%nranks == 1) then
      has = .true.
      return
    end if
    ! (each rank gives its share of the particles, a contiguous run of the numbering, as
    ! the bodies will be generated per part: the tree is the same, rcb_build's)
    if (b%held_share) then
      ! (the body made as the share: build_bodies on ranks)
      call rcb_build_ranks(b%x, part%nranks, part%comm, tree)
    else
      call rcb_build_ranks(b%x(:, share_first(b%np, part%me, part%nranks): &
        share_first(b%np, part%me + 1, part%nranks) - 1), part%nranks, part%comm, tree)
    end if
    has = part%me > 0 .or. .not. part%root_whole
    if (has) call rcb_box(tree, part%me + 1, box(:, 1), box(:, 2))
  end function region_box

  !> The particle of body b (a rank's share of it, made as such: b%held_share) nearest to
  !! point y, its number in the whole body, the first in the numbering among equals, as a
  !! scan of the whole body finds it: each rank's nearest in its share, then the least
  !! distance over the ranks and the least number at it. Collective.
  integer function whole_nearest(part, b, y) result(q)
    type(setup_part_t), intent(in) :: part
    type(body_t), intent(in) :: b
    real(wp), intent(in) :: y(:)
    real(wp) :: best(1), mine(1), at(1)
    integer :: j
    mine = huge(1.0_wp)
    q = 0
    do j = 1, size(b%x, 2)
      if (norm2(b%x(:, j) - y(1:b%ndim)) < mine(1)) then
        mine = norm2(b%x(:, j) - y(1:b%ndim))
        q = b%row0 + j - 1
      end if
    end do
    best = -mine
    call part%comm%max_real(best)
    ! (numbers below 2**53 are exact reals)
    at = -real(huge(1), wp)
    if (mine(1) == -best(1) .and. q > 0) at = -real(q, wp)
    call part%comm%max_real(at)
    q = nint(-at(1))
  end function whole_nearest

  !> Whether body k is made as each rank's share only on nranks ranks (build_bodies'
  !! per_part: the whole body is never made on a rank; its set-up makes the rank's region
  !! from the body's recipe, region_made, or its tetrahedra's, tet4_region): a deformable
  !! 3D body of RKPM particles or of tetrahedra extruded along z
  !! (shape 'box', 'cylinder' or 'polygon') set up as a region shell (no rank keeps the
  !! whole solids, root_whole; no spin: region_solid_do), in any contact: a deforming
  !! master's and a self-contact's sides take the whole body's detection scalars and
  !! surface from the ranks (side_facts); or a body of tetrahedra from a mesh file
  !! (tet_file_m: each rank reads its share and region of the file), or from a 3D gmsh
  !! script (shape 'geo'), which one rank meshes into such a file first (mfcd_mpi); or a
  !! rectangle in the plane that stays on its lattice, RKPM or CST4, in any contact (its
  !! region from the lattice's recipe: tl_region_2d, cst4_region); or a plane gmsh
  !! script's linear triangles, or its RKPM body (not by Gauss), in any contact but a
  !! self-contact (tri_file_m: each rank reads its share and region of the file rank 0
  !! meshed it into and checked the whole bodies from, mfcd_mpi).
  logical function body_per_part(deck, k, nranks, root_whole) result(yes)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k, nranks
    logical, intent(in) :: root_whole
    integer :: l
    associate (bs => deck%bodies(k))
      yes = nranks > 1 .and. .not. root_whole .and. deck%run%ndim == 3 .and. &
        deck%run%mode == 'dynamic' .and. bs%role == 'deformable' .and. &
        any(bs%discretization == ['rkpm', 'fem ']) .and. bs%angular_velocity == 0.0_wp .and. &
        any(bs%shape == ['box     ', 'cylinder', 'polygon '])
      ! a rectangle or polygon in the plane on its lattice (RKPM by SCNI without a
      ! perturbation, or CST4 on a rectangle), or the CST4 elements of an annulus sector
      ! on its polar lattice (no rotation), in any contact (a deforming
      ! master's or a self-contact's sides take the whole body's det(M) facts over the
      ! ranks and its whole boundary polyline from the recipe, side_facts): made from its
      ! lattice's recipe
      if (.not. yes) yes = nranks > 1 .and. .not. root_whole .and. deck%run%ndim == 2 .and. &
        deck%run%mode == 'dynamic' .and. bs%role == 'deformable' .and. &
        (bs%discretization == 'fem' .or. (bs%discretization == 'rkpm' .and. &
        bs%integration == 'scni' .and. bs%perturbation == 0.0_wp)) .and. &
        bs%angular_velocity == 0.0_wp .and. bs%rotate == 0.0_wp .and. &
        (bs%shape == 'rectangle' .or. bs%shape == 'polygon' .or. &
        (bs%shape == 'annulus_sector' .and. bs%discretization == 'fem'))
      ! (a polygon's when its lattice merges no cell along the outline, so that each
      ! particle's cell is its own lattice cell clipped: generators_m polygon_walk)
      if (yes .and. bs%shape == 'polygon') yes = .not. polygon_merges( &
        bs%vertices(:, 1:bs%nvert), bs%spacing(1:2), bs%origin(1:2))
      ! a plane gmsh script's linear triangles, meshed once by rank 0 into a file that it
      ! then builds the whole body from and checks (mfcd_mpi), read per part (tri_file_m),
      ! in any contact (a deforming master's or a self-contact's sides take the whole
      ! polyline and det(M)'s medians from the file and the ranks: side_facts)
      ! (or RKPM over its median-dual cells, one point a particle: the whole cloud's
      ! extremes and largest supports from the file's facts, rkpm_tl_m tl_build, in
      ! axisymmetry its images' extent too; Gauss integration's points are not the
      ! particles a region numbers)
      ! A user's plane particle file in HDF5 (tools/mesh_body.py's layout) the same way,
      ! rank 0 writing the whole file's facts apart (body_setup_m plane_facts_file), when
      ! it carries the triangles (and an RKPM body its cells: mfcd_mpi plane_files_vetted)
      l = len_trim(bs%file)
      if (.not. yes) yes = nranks > 1 .and. .not. root_whole .and. deck%run%ndim == 2 .and. &
        deck%run%mode == 'dynamic' .and. bs%role == 'deformable' .and. &
        (bs%discretization == 'fem' .or. (bs%discretization == 'rkpm' .and. &
        bs%integration /= 'gauss')) .and. &
        (bs%shape == 'geo' .or. (bs%shape == 'file' .and. l > 3 .and. &
        (bs%file(max(1, l - 2):l) == '.h5' .or. bs%file(max(1, l - 4):l) == '.hdf5'))) .and. &
        bs%angular_velocity == 0.0_wp .and. bs%rotate == 0.0_wp
      ! a tetrahedral mesh file (tools/mesh_body.py --3d), its elements or their median-
      ! dual cells, in any contact (the sides' whole-body facts from the file: side_facts);
      ! a 3D gmsh script, meshed once by rank 0 into such a file (mfcd_mpi: geo_mesh_file)
      if (.not. yes) then
        yes = nranks > 1 .and. .not. root_whole .and. deck%run%ndim == 3 .and. &
          deck%run%mode == 'dynamic' .and. bs%role == 'deformable' .and. &
          any(bs%discretization == ['rkpm', 'fem ']) .and. bs%angular_velocity == 0.0_wp .and. &
          (bs%shape == 'geo' .or. (bs%shape == 'file' .and. l > 3 .and. &
          (bs%file(max(1, l - 2):l) == '.h5' .or. bs%file(max(1, l - 4):l) == '.hdf5')))
      end if
    end associate
  end function body_per_part

  !> Whether a rank makes only the particles of body k its region needs (tl_region_3d), not
  !! the whole body, for the solid's set-up: a 3D extruded body with its recipe (a
  !! deformable RKPM body: body_setup_m) set up as a region shell (region_solid_do) on
  !! more than one rank. The same on every rank.
  logical function region_made(deck, k, part, b) result(yes)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(setup_part_t), intent(in), optional :: part
    type(body_t), intent(in) :: b
    yes = .false.
    if (.not. present(part)) return
    if (part%nranks == 1 .or. .not. (allocated(b%ext) .or. allocated(b%mfile) .or. &
      (allocated(b%lat) .and. b%held_share))) return
    yes = region_solid_do(deck, k, part)
  end function region_made

  !> Whether body k's solid is set up as a region shell on every rank (region_rows: no
  !! array over the whole solid; for RKPM its masses completed over the regions only,
  !! region_masses, rather than over every particle, whole_masses): when every rank
  !! holds a shell of it (no rank keeps the whole solids) and nothing reads the solid
  !! outside a rank's region before the split: no plane spin (its centre of mass sums
  !! every particle's). (The contact sides on it are set up over the region too, a
  !! deforming master's and a self-contact's included: their ghosts' inverse masses come
  !! from their owners.) The same on every rank (the deck's).
  logical function region_solid_do(deck, k, part) result(yes)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(setup_part_t), intent(in) :: part
    yes = .not. part%root_whole .and. deck%bodies(k)%angular_velocity == 0.0_wp
  end function region_solid_do

  !> The lumped masses of an RKPM solid t of body b over a rank's region (region_of, made
  !! here: rows) in a decomposed set-up, each the serial one to the bit, without a sum
  !! over every particle: a rank that integrated only the cells its box needs has the
  !! masses of the particles in its box (its part, tree) whole, the same sums in the same
  !! order as the serial run; the region's other particles' masses come from the ranks
  !! whose boxes hold them (the requests' counts by an all-to-all, P numbers a rank, then
  !! the numbers and the masses point to point to those ranks only). The masses outside
  !! the region are set to 0 (nothing reads them: region_solid_do), the total is the exact
  !! sum of the parts' (for the log). An error on a rank (a cell too few particles cover)
  !! reaches all first. Collective.
  subroutine region_masses(part, tree, b, t, box, rows, err)
    type(setup_part_t), intent(in) :: part
    type(rcb_tree_t), intent(in) :: tree
    type(body_t), intent(in) :: b
    type(solid_tables_t), intent(inout) :: t
    real(wp), intent(in) :: box(3, 2)
    integer, allocatable, intent(out) :: rows(:)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: sbuf(:), rbuf(:), back(:), got(:)
    integer, allocatable :: owner(:), to(:), from(:), sptr(:), rptr(:), bptr(:), fill(:), &
      cnt(:), asked(:)
    type(exact_sum_t) :: e
    integer :: i, j, r, np, me
    if (.not. associated(part%comm)) error stop 'region_masses: setup_part_t%comm not set'
    me = part%comm%me
    np = part%comm%nranks
    if (failed_on_a_rank(part, err, .not. allocated(t%mass))) return
    call region_of(t, b, box, rows)
    ! (b may hold some particles of a larger body, glob: the requests and answers are in
    ! the whole body's numbers)
    ! each region particle's part (0-based rank); the requests grouped by rank
    allocate(owner(size(rows)), cnt(np), asked(np))
    cnt = 0
    do j = 1, size(rows)
      owner(j) = rcb_part(tree, b%x(:, rows(j))) - 1
      if (owner(j) /= me) cnt(owner(j) + 1) = cnt(owner(j) + 1) + 1
    end do
    ! (each rank learns how many each other rank asks it for: P counts a rank)
    call part%comm%alltoall_int(cnt, asked)
    to = pack([(r, r = 0, np - 1)], cnt > 0)
    from = pack([(r, r = 0, np - 1)], asked > 0)
    allocate(sptr(size(to) + 1), fill(np))
    sptr(1) = 1
    do i = 1, size(to)
      fill(to(i) + 1) = sptr(i)
      sptr(i + 1) = sptr(i) + cnt(to(i) + 1)
    end do
    allocate(sbuf(sptr(size(to) + 1) - 1), rptr(size(from) + 1), rbuf(0))
    do j = 1, size(rows)
      r = owner(j)
      if (r == me) cycle
      if (allocated(b%glob)) then
        sbuf(fill(r + 1)) = real(b%glob(rows(j)), wp)
      else
        sbuf(fill(r + 1)) = real(rows(j), wp)
      end if
      fill(r + 1) = fill(r + 1) + 1
    end do
    call part%comm%sparse_exchange(to, sptr, sbuf, from, rptr, rbuf)
    ! the answers: the masses of the particles asked for, which this rank's box holds
    allocate(back(rptr(size(from) + 1) - 1), bptr(size(to) + 1), got(0))
    do i = 1, size(back)
      if (allocated(b%glob)) then
        back(i) = t%mass(sorted_place(b%glob, nint(rbuf(i))))
      else
        back(i) = t%mass(nint(rbuf(i)))
      end if
    end do
    call part%comm%sparse_exchange(from, rptr, back, to, bptr, got)
    ! in the order asked (the requests' order per rank)
    fill(to + 1) = sptr(1:size(to))
    e = exact_sum_t()
    do j = 1, size(rows)
      r = owner(j)
      if (r == me) then
        call exact_add(e, t%mass(rows(j)))
        cycle
      end if
      t%mass(rows(j)) = got(fill(r + 1))
      fill(r + 1) = fill(r + 1) + 1
    end do
    ! (zero between the region's particles, ascending: no mask over the whole body)
    j = 1
    do i = 1, b%np
      if (j <= size(rows)) then
        if (rows(j) == i) then
          j = j + 1
          cycle
        end if
      end if
      t%mass(i) = 0.0_wp
    end do
    t%total_mass = exact_allsum(e, part%comm)
  end subroutine region_masses

  !> The log's line for body b made per rank (its region of nr particles made as what
  !! says; unit: ' (nodes)' for elements), when say: the most particles a rank made of it
  !! against the whole body's (check_mpi_run.py --made reads it). Collective (say may
  !! differ between the ranks: each takes part).
  subroutine log_made(part, b, nr, what, unit, say)
    type(setup_part_t), intent(in) :: part
    type(body_t), intent(in) :: b
    integer, intent(in) :: nr
    character(len=*), intent(in) :: what, unit
    logical, intent(in) :: say
    real(wp) :: made(1)
    made = real(max(nr, size(b%x, 2)), wp)
    call part%comm%max_real(made)
    if (say) write(output_unit, '(a)') "dynamic: body '"//trim(b%name)//"': made per "// &
      'rank (its share, then its '//what//'), at most '//itoa(nint(made(1)))// &
      ' particles'//unit//' on a rank, of '//itoa(b%np)//' (the whole body is made on '// &
      trim(merge('no rank                               ', &
      'no rank past rank 0''s checks of it    ', .not. (allocated(b%mfile) .and. &
      b%ndim == 2)))//')'
  end subroutine log_made

  !> The whole mesh's smallest height (the time step's) and total mass (for the log) for
  !! the tables t of a rank's tetrahedra of body b made from its recipe (tet4_region): the
  !! least of the ranks' heights (every tetrahedron is on some rank: the serial minimum,
  !! exactly) and the exact sum of the masses of the nodes in each rank's part (tree). An
  !! error on a rank reaches all first. Collective.
  subroutine region_tet_sums(part, tree, b, t, err)
    type(setup_part_t), intent(in) :: part
    type(rcb_tree_t), intent(in) :: tree
    type(body_t), intent(in) :: b
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: h(1)
    type(exact_sum_t) :: e
    integer :: i
    if (failed_on_a_rank(part, err, .not. allocated(t%mass))) return
    h = -t%hmin
    call part%comm%max_real(h)
    t%hmin = -h(1)
    do i = 1, b%np
      if (rcb_part(tree, b%x(:, i)) == part%me + 1) call exact_add(e, t%mass(i))
    end do
    t%total_mass = exact_allsum(e, part%comm)
  end subroutine region_tet_sums

  !> Whether the set-up failed on any rank (err, or bad: a result missing) before a
  !! collective step, said on the ranks without a message of their own. Collective.
  logical function failed_on_a_rank(part, err, bad) result(failed)
    type(setup_part_t), intent(in) :: part
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in) :: bad
    real(wp) :: flag(1)
    flag = 0.0_wp
    if (allocated(err) .or. bad) flag = 1.0_wp
    call part%comm%max_real(flag)
    failed = flag(1) > 0.0_wp
    if (failed .and. .not. allocated(err)) call set_error(err, 'the set-up failed on '// &
      'another rank (its message is on its standard error)')
  end function failed_on_a_rank

  !> The lumped masses of an RKPM solid whole on every rank of a decomposed set-up: a rank that
  !! integrated only the cells its box needs (tl_build_3d's and tl_build's box) has the masses of
  !! the particles in its box whole (the same sums in the same order) and the others' partial. Each
  !! rank gives those of the particles the bisection puts in its part (every particle in exactly
  !! one), zero for the rest, and one sum over the ranks makes every mass the serial one to the bit
  !! (x + 0 = x), so that whatever reads a mass before the split (the contact sides' inverse masses,
  !! a spin's centre of mass, the total) or after it (a part's ghost nodes) reads the serial one. An
  !! error on a rank (a cell too few particles cover, found by the ranks that integrate it) reaches
  !! all in the same sum. Collective.
  subroutine whole_masses(part, tree, b, t, err)
    type(setup_part_t), intent(in) :: part
    type(rcb_tree_t), intent(in) :: tree
    type(body_t), intent(in) :: b
    type(solid_tables_t), intent(inout) :: t
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: m(:)
    integer :: i, n
    if (.not. associated(part%comm)) error stop 'whole_masses: setup_part_t%comm not set'
    n = b%np
    allocate(m(n + 1))
    m = 0.0_wp
    ! (an error may come before the masses exist)
    if (allocated(t%mass) .and. .not. allocated(err)) then
      do i = 1, n
        if (rcb_part(tree, b%x(:, i)) == part%me + 1) m(i) = t%mass(i)
      end do
    end if
    if (allocated(err)) m(n + 1) = 1.0_wp
    call part%comm%sum_real(m)
    if (m(n + 1) > 0.0_wp .and. .not. allocated(err)) call set_error(err, 'the set-up '// &
      'failed on another rank (its message is on its standard error)')
    if (allocated(err)) return
    t%mass = m(1:n)
    t%total_mass = sum(t%mass)
  end subroutine whole_masses

  !> A body with symmetry planes (a quarter or half cylinder, rkpm_tl3d_m): the particles
  !! on a plane are their own mirror images, so their component normal to it is held at 0
  !! (as the 2D axisymmetric solid holds the radial component on the axis); no &bc group
  !! holds it (no reaction is reported). pres and vpres over the particles at
  !! (kinematic_masks').
  subroutine symmetry_holds(b, at, pres, vpres)
    type(body_t), intent(in) :: b
    integer, intent(in) :: at(:)
    logical, intent(inout) :: pres(:, :)
    real(wp), intent(inout) :: vpres(:, :)
    integer :: normal(2), n, m, i
    real(wp) :: pos(2), tol
    call symmetry_planes_3d(b, normal, pos, n)
    tol = 1.0e-9_wp*maxval(b%spacing(1:3))
    do m = 1, n
      do i = 1, size(at)
        if (abs(b%x(normal(m), at(i)) - pos(m)) <= tol) then
          pres(normal(m), i) = .true.
          vpres(normal(m), i) = 0.0_wp
        end if
      end do
    end do
  end subroutine symmetry_holds

  !> The deck's &bc groups of body k as masks over the nodes' reference positions: a node
  !! inside a group's box has that component prescribed (held at 0 for 'fixed', moved at
  !! the given velocity for 'velocity'). The masks over the particles at (every one, or a
  !! rank's region); a box that holds no particle of the whole body is an error.
  subroutine kinematic_masks(deck, k, b, pres, vpres, bc_of, err, at)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    type(body_t), intent(in) :: b
    logical, allocatable, intent(out) :: pres(:, :)
    real(wp), allocatable, intent(out) :: vpres(:, :)
    integer, allocatable, intent(out) :: bc_of(:, :)   !< the group of each (the last)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in) :: at(:)
    integer :: j, i, c, nsel
    allocate(pres(b%ndim, size(at)), vpres(b%ndim, size(at)), bc_of(b%ndim, size(at)))
    pres = .false.
    vpres = 0.0_wp
    bc_of = 0
    do j = 1, deck%nbcs
      if (deck%bcs(j)%ibody /= k) cycle
      c = deck%bcs(j)%component
      nsel = 0
      do i = 1, size(at)
        if (in_bc(at(i))) then
          pres(c, i) = .true.
          vpres(c, i) = merge(deck%bcs(j)%value, 0.0_wp, deck%bcs(j)%kind == 'velocity')
          bc_of(c, i) = j
          nsel = nsel + 1
        end if
      end do
      ! (none at a rank's region: whether the whole body has one, the same answer on
      ! every rank, without walking it twice when at is all of it)
      if (nsel == 0 .and. allocated(b%glob)) then
        ! (b some particles of a larger body: any of the whole body's, from its recipe or
        ! its mesh file)
        if (allocated(b%mfile) .and. b%ndim == 2) then
          nsel = tri_file_count(b, deck%bcs(j)%region_lo(1:3), deck%bcs(j)%region_hi(1:3))
        else if (allocated(b%mfile)) then
          nsel = tet_file_count(b, deck%bcs(j)%region_lo(1:3), deck%bcs(j)%region_hi(1:3))
        else
          nsel = body_count(b, deck%bcs(j)%region_lo(1:3), deck%bcs(j)%region_hi(1:3))
        end if
      else if (nsel == 0 .and. size(at) < b%np) then
        do i = 1, b%np
          if (in_bc(i)) then
            nsel = 1
            exit
          end if
        end do
      end if
      if (nsel == 0) then
        call set_error(err, "deck '"//deck%path//"', group &bc (bc "//itoa(j)// &
          "), variable region_lo/region_hi: the box holds no node of body '"// &
          trim(b%name)//"'; enlarge it (reference coordinates, m)")
        return
      end if
    end do

  contains

    logical function in_bc(i)
      integer, intent(in) :: i
      in_bc = all(b%x(:, i) >= deck%bcs(j)%region_lo(1:b%ndim)) .and. &
        all(b%x(:, i) <= deck%bcs(j)%region_hi(1:b%ndim))
    end function in_bc
  end subroutine kinematic_masks

  !> The contact pairs of the deck's &contact groups, with their log lines (none if quiet).
  subroutine setup_contacts(deck, bodies, solids, isolid, pairs, err, quiet, regions, part)
    type(deck_t), intent(in) :: deck
    type(body_t), intent(in), target :: bodies(:)
    type(solid_t), intent(in) :: solids(:)
    integer, intent(in) :: isolid(:)
    type(contact_pair_t), allocatable, intent(out) :: pairs(:)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: quiet
    !> the solids' regions on a rank (setup_solids): a slave's side against a rigid
    !! master holds its region only
    type(region_rows_t), intent(in), optional, target :: regions(:)
    !> the ranks, for the sides of a body no rank holds whole (side_facts; collective)
    type(setup_part_t), intent(in), optional :: part
    logical :: cut, cutm
    type(contact_params_t) :: prm
    type(error_t), allocatable :: e2
    integer :: k, im, is, kb
    !> each body no rank holds whole that is a deforming master or in a self-contact: what
    !! its sides take of it (side_facts), made once
    type(side_facts_t), allocatable, target :: facts(:)
    type(side_facts_t), pointer :: fs, fm
    logical, allocatable :: made(:)
    logical :: loud
    type(body_t), pointer :: bsp, bmp
    integer, pointer :: rs(:), rm(:)
    allocate(facts(deck%nbodies), made(deck%nbodies))
    made = .false.
    loud = .true.
    if (present(quiet)) loud = .not. quiet
    allocate(pairs(deck%ncontacts))
    do k = 1, deck%ncontacts
      associate (cs => deck%contacts(k))
        prm%eps_cr = cs%eps_cr
        prm%eps_rel = cs%eps_rel
        prm%mu = cs%mu
        prm%detector = merge(detector_nts, detector_det_m, cs%detector == 'node_to_segment')
        prm%compare = cs%compare_detectors
        prm%skip_far = cs%skip_far
        prm%shared_mass = cs%shared_mass
        prm%self_contact = cs%imaster == cs%islave
        prm%self_radius = cs%self_radius
        prm%track_edge = cs%edge_point(1) > -huge(1.0_wp)
        if (prm%track_edge) prm%edge_point = cs%edge_point
        im = cs%imaster
        is = cs%islave
        ! a rigid master moves at its &body velocity (a ram, a die)
        prm%master_velocity = 0.0_wp
        if (isolid(im) == 0) prm%master_velocity = deck%bodies(im)%velocity
        cut = .false.
        if (present(regions) .and. isolid(is) > 0) cut = allocated(regions(isolid(is))%glob)
        ! (a deforming master's pair, or a self-contact: both sides over the regions)
        cutm = .false.
        if (cut .and. isolid(im) > 0) cutm = allocated(regions(isolid(im))%glob)
        if (cutm .and. (bodies(is)%held_share .or. bodies(im)%held_share)) then
          ! (a side whose body no rank holds whole: over the region the rank made of it,
          ! with what it takes of the whole body found over the ranks)
          ! (a side of a body some rank holds whole takes no facts: its pointer is null,
          ! an absent optional argument)
          call side_of(is, bsp, rs, fs)
          if (.not. allocated(e2)) call side_of(im, bmp, rm, fm)
          if (.not. allocated(e2)) call contact_pair_init(pairs(k), prm, bsp, isolid(is), &
            bmp, isolid(im), solids, deck%run%geometry == 'axisymmetric', e2, rs, rm, fs, fm)
          ! (the tracked edge particle: the whole body's nearest, its whole number)
          if (prm%track_edge .and. bodies(is)%held_share) pairs(k)%edge = &
            whole_nearest(part, bodies(is), cs%edge_point)
        else if (cutm) then
          call contact_pair_init(pairs(k), prm, bodies(is), isolid(is), bodies(im), &
            isolid(im), solids, deck%run%geometry == 'axisymmetric', e2, &
            regions(isolid(is))%glob, regions(isolid(im))%glob)
        else if (cut .and. allocated(regions(isolid(is))%body) .and. isolid(im) == 0 .and. &
          im /= is) then
          ! (the slave's region as the rank made it: the whole body is not on the rank)
          call contact_pair_init(pairs(k), prm, regions(isolid(is))%body, isolid(is), &
            bodies(im), isolid(im), solids, deck%run%geometry == 'axisymmetric', e2, &
            regions(isolid(is))%places)
          ! (the tracked edge particle: the whole body's nearest to edge_point, its number
          ! in the whole body, as a whole body's pair holds it; the region's may not hold it)
          if (prm%track_edge .and. present(part)) pairs(k)%edge = whole_nearest(part, &
            bodies(is), cs%edge_point)
        else if (cut) then
          call contact_pair_init(pairs(k), prm, bodies(is), isolid(is), bodies(im), &
            isolid(im), solids, deck%run%geometry == 'axisymmetric', e2, &
            regions(isolid(is))%glob)
        else
          call contact_pair_init(pairs(k), prm, bodies(is), isolid(is), bodies(im), &
            isolid(im), solids, deck%run%geometry == 'axisymmetric', e2)
        end if
        if (allocated(e2)) then
          call set_error(err, "deck '"//deck%path//"', group &contact (contact "// &
            itoa(k)//"): "//e2%message)
          return
        end if
      end associate
      ! (a body's facts once no later pair reads them: each side keeps its own surface, a
      ! third copy would add to the set-up's peak)
      do kb = 1, deck%nbodies
        if (made(kb) .and. .not. any(deck%contacts(k + 1:)%imaster == kb .or. &
          deck%contacts(k + 1:)%islave == kb)) facts(kb) = side_facts_t()
      end do
      if (present(quiet)) then
        if (quiet) cycle
      end if
      associate (p => pairs(k))
        write(output_unit, '(a,es10.3,a,es10.3,a,es10.3,a,i0,a,f5.2,a)') 'contact: master '''// &
          trim(p%side(2)%name)//''' ('//trim(merge('deformable', 'rigid     ', p%both_ways))// &
          ', det(M) plateau ', p%side(2)%plateau, '), slave '''//trim(p%side(1)%name)// &
          ''': threshold ', p%side(2)%threshold, ' (eps_cr ', p%eps_cr, '), ', &
          p%side(2)%surface%nseg, ' surface segments, mu = ', p%mu, &
          trim(merge('; detection both ways (eq. 28)', '                              ', &
          p%both_ways))
        write(output_unit, '(a,es10.3,a)') 'contact: det(M_master) at its surface '// &
          'particles (median) ', p%side(2)%surface_det, trim(merge( &
          '; warning: the threshold is above it, shallow penetrations go undetected', &
          '                                                                        ', &
          p%side(2)%threshold > p%side(2)%surface_det))
        write(output_unit, '(a,es10.3,a,i0,a,i0,a)') 'contact: detector '// &
          detector_name(p%detector)//trim(merge(' (compared with the other on every step)', &
          '                                        ', p%compare))//'; segment buckets of ', &
          p%side(2)%buckets%cell, ' m, ', p%side(2)%buckets%nc(1), ' x ', &
          p%side(2)%buckets%nc(2), ' cells'
        if (p%self) write(output_unit, '(a,i0,a,f5.2,a)') 'contact: self-contact of '''// &
          trim(p%side(1)%name)//''': ', p%side(1)%ncand, ' surface particles checked '// &
          'against det(M) of their non-neighbours (beyond ', deck%contacts(k)%self_radius, &
          ' supports in the reference configuration), two passes a step'
        if (p%shared_mass .and. p%both_ways) write(output_unit, '(a)') 'contact: eq. (93) '// &
          'with the master nodes'' masses shared among the particles that push them '// &
          '(shared_mass)'
        if (p%shared_mass .and. .not. p%both_ways) write(output_unit, '(a)') 'contact: '// &
          'shared_mass has no effect: the master is rigid'
        flush(output_unit)
      end associate
    end do

  contains

    !> The body and rows side_init takes for body kb: the region the rank made of it, and
    !! the places in it, with its facts f (made here on first use: collective, and every
    !! rank walks the same pairs), when no rank holds it whole; else the body and its
    !! region, f null.
    subroutine side_of(kb, bp, rows, f)
      integer, intent(in) :: kb
      type(body_t), pointer, intent(out) :: bp
      integer, pointer, intent(out) :: rows(:)
      type(side_facts_t), pointer, intent(out) :: f
      f => null()
      if (.not. bodies(kb)%held_share) then
        bp => bodies(kb)
        rows => regions(isolid(kb))%glob
        return
      end if
      if (.not. allocated(regions(isolid(kb))%body)) error stop &
        'setup_contacts: a body held as a share without its region made'
      bp => regions(isolid(kb))%body
      rows => regions(isolid(kb))%places
      f => facts(kb)
      if (made(kb)) return
      if (.not. present(part)) error stop 'setup_contacts: a share without the ranks'
      call side_facts(part%comm, bodies(kb), bp%glob, facts(kb), e2, &
        deck%run%geometry == 'axisymmetric')
      made(kb) = .true.
      if (allocated(e2) .or. .not. loud) return
      if (bodies(kb)%ndim == 2) then
        write(output_unit, '(a,i0,a)') 'contact: the sides of '''//trim(bodies(kb)%name)// &
          ''' took at the set-up its whole boundary polyline (', facts(kb)%surf2%nseg, &
          ' segments, perimeter-sized) and det(M)''s plateau and surface median over the ranks'
        return
      end if
      write(output_unit, '(a,i0,a,i0,a)') 'contact: the sides of '''//trim(bodies(kb)%name)// &
        ''' took at the set-up the facets near each rank''s region, at most ', &
        facts(kb)%nf_most, ' of its ', facts(kb)%surf3%nf_whole, ' on a rank'
    end subroutine side_of
  end subroutine setup_contacts

  !> What the sides over a rank's region of body b take of the whole body (contact_pair_m
  !! side_facts_t), when the rank holds only its share of b (b%held_share: made from its
  !! recipe b%ext or read from its mesh file): the part of its closed surface with every
  !! facet that has a vertex among the region's particles inner (ascending numbers in the
  !! whole body; side_surface_m side_surface: from the ranks' rows of the surface, with
  !! the whole surface's cell size and counts), side_facts_local's, then det(M)'s plateau
  !! and surface median over the ranks (detection_m share_det_medians). Each is what
  !! side_init makes of the whole body, to the bit (test_side_facts; mpi_run_3d_made),
  !! the surface restricted to those facets. Collective; an error on a rank reaches every
  !! rank.
  subroutine side_facts(comm, b, inner, f, err, axisym)
    class(rank_comm_t), intent(inout) :: comm
    type(body_t), intent(in) :: b
    integer, intent(in) :: inner(:)
    type(side_facts_t), intent(out) :: f
    type(error_t), allocatable, intent(inout) :: err
    !> a plane body's geometry (its polyline's segments on the axis are dropped)
    logical, intent(in) :: axisym
    real(wp), allocatable :: det(:), xloop(:, :)
    logical, allocatable :: deep(:), bnd(:)
    real(wp) :: flag(1), most(1)
    ! (a body whose generator could not close its surface has none: side_init says so)
    if (allocated(b%facets)) call side_surface(comm, b, inner, f%surf3, err)
    ! (a plane body's: its whole boundary polyline, perimeter-sized, from its recipe; a
    ! plane mesh file's from its loops' rows of the file)
    if (b%ndim == 2 .and. allocated(b%mfile)) then
      call tri_file_positions(b, b%loop_idx, xloop, err)
      if (.not. allocated(err)) call side_loop_surface(b, axisym, f%surf2, err, xloop)
    else if (b%ndim == 2) then
      call side_loop_surface(b, axisym, f%surf2, err)
    end if
    most = real(f%surf3%nf, wp)
    call comm%max_real(most)
    f%nf_most = nint(most(1))
    if (.not. allocated(err)) call side_facts_local(b, f, det, deep, err, bnd)
    if (.not. allocated(det)) allocate(det(0), deep(0))
    flag = 0.0_wp
    if (allocated(err)) flag = 1.0_wp
    call comm%max_real(flag)
    if (flag(1) > 0.0_wp) then
      if (.not. allocated(err)) call set_error(err, "body '"//trim(b%name)//"': its "// &
        "surface or det(M) failed on another rank")
      return
    end if
    ! (the particles det was taken at: the share's, or a slab's, bnd)
    if (allocated(bnd)) then
      call share_det_medians(comm, det, deep, bnd, f%plateau, f%surface_det)
    else
      call share_det_medians(comm, det, deep, b%boundary, f%plateau, f%surface_det)
    end if
  end subroutine side_facts

  !> side_facts' part that needs no other rank, of body b held as a rank's share: the
  !! extremes of the reference positions (a mesh file's from its extent; an extruded
  !! body's from its first and last layers: the section is every layer's) and the largest
  !! support (the file's longest edge times the factors, or the recipe's); det(M) at the
  !! share's particles and whether each is deep (detection_m deep_particles), in a cloud
  !! of the particles within a support of them (and a spacing) on the whole cloud's bins'
  !! grid, so that every sum runs in the whole cloud's order.
  subroutine side_facts_local(b, f, det, deep, err, bnd)
    type(body_t), intent(in) :: b
    type(side_facts_t), intent(inout) :: f
    real(wp), allocatable, intent(out) :: det(:)
    logical, allocatable, intent(out) :: deep(:)
    type(error_t), allocatable, intent(inout) :: err
    !> the boundary flags of the particles det is taken at when they are not the share's
    !! (a plane mesh file's: its slab's), else unallocated
    logical, allocatable, intent(out), optional :: bnd(:)
    type(body_t) :: ends, near
    type(rk_cloud_t) :: c
    integer :: n, j, none(2), nd, run, r0, r1, axis
    real(wp) :: nowhere(2), lo(3), hi(3), reach(3)
    logical, allocatable :: deep_run(:), mine(:)
    integer, allocatable :: at(:)
    none = 0
    nowhere = 0.0_wp
    nd = b%ndim
    if (allocated(b%mfile) .and. nd == 2) then
      ! a plane mesh file's (tri_file_m): its extent and largest support from the file's
      ! facts, placed (as a tetrahedral file's below); det(M) at the nodes of the rank's
      ! slab of the extent, not its share (a gmsh numbering spreads a share over the whole
      ! body; the slabs hold each node once, and the medians are k-th values, whatever
      ! rank holds which), in a cloud of the nodes within a support (and a spacing) of it
      f%lo(1:2) = b%mfile%lo(1:2) + b%mfile%shift(1:2)
      f%hi(1:2) = b%mfile%hi(1:2) + b%mfile%shift(1:2)
      f%rmax(1:2) = b%support_factor(1:2)*b%mfile%lmax
      call file_slab(b%mfile, lo, hi, axis)
      reach = 0.0_wp
      reach(1:2) = f%rmax(1:2) + maxval(b%spacing(1:2))
      call tri_file_region(b, lo - reach, hi + reach, near, err, cells=.false.)
      if (allocated(err)) return
      mine = near%x(axis, :) >= lo(axis) .and. (near%x(axis, :) < hi(axis) .or. &
        (b%mfile%me == b%mfile%nranks - 1 .and. near%x(axis, :) <= hi(axis)))
      at = pack([(j, j = 1, near%np)], mine)
      call cloud_init(c, near%x, near%rho, near%vol, b%kid, b%wshape, b%bid, b%h(1:2), &
        err, grid_lo=f%lo(1:2), grid_hi=f%hi(1:2), rmax=f%rmax(1:2))
      if (allocated(err)) return
      allocate(det(size(at)))
      call det_at_points(c, near%x(:, at), det)
      deep = deep_particles(c, near%boundary, near%x(:, at), near%rho(:, at))
      if (present(bnd)) bnd = near%boundary(at)
      return
    end if
    if (allocated(b%lat)) then
      ! a rectangle's: its outermost ring's extremes (every coordinate of its lattice),
      ! and its recipe's supports
      call body_pick(b, 1, huge(1), [(-huge(1.0_wp), j = 1, 3)], &
        [(huge(1.0_wp), j = 1, 3)], 0, none, nowhere, ends, ends=.true.)
      f%lo(1:2) = minval(ends%x, dim=2)
      f%hi(1:2) = maxval(ends%x, dim=2)
      f%rmax(1:2) = b%lat%rho
      ! det(M) at the share's particles, in a cloud of those within a support of them (a
      ! CST4 share's corners and box centres apart: the centres are numbered after every
      ! corner, so a share of both spans the body)
      n = size(b%x, 2)
      allocate(det(n), deep(n))
      do run = 1, 2
        r0 = 1
        r1 = n
        if (b%lat%cst4) then
          ! (the share's corners, then its centres: rows r0 ... r1)
          j = lattice_corners(b%lat) - b%row0 + 1
          if (run == 1) r1 = min(n, j)
          if (run == 2) r0 = max(1, j + 1)
        else if (run == 2) then
          exit
        end if
        if (r1 < r0) cycle
        reach(1:2) = f%rmax(1:2) + maxval(b%spacing(1:2))
        lo(1:2) = minval(b%x(:, r0:r1), dim=2) - reach(1:2)
        hi(1:2) = maxval(b%x(:, r0:r1), dim=2) + reach(1:2)
        call body_pick(b, 1, huge(1), lo(1:2), hi(1:2), 0, none, nowhere, near)
        call cloud_init(c, near%x, near%rho, near%vol, b%kid, b%wshape, b%bid, b%h(1:2), &
          err, grid_lo=f%lo(1:2), grid_hi=f%hi(1:2), rmax=f%rmax(1:2))
        if (allocated(err)) return
        call det_at_points(c, b%x(:, r0:r1), det(r0:r1))
        deep_run = deep_particles(c, near%boundary, b%x(:, r0:r1), b%rho(:, r0:r1))
        deep(r0:r1) = deep_run
      end do
      return
    end if
    if (allocated(b%mfile)) then
      ! a mesh file's (tet_file_m): its extent, read whole, placed (a rounding is monotonic:
      ! the least of the placed positions is the least placed), and the longest support,
      ! the factors times the longest edge (each node's support is its longest edge's)
      f%lo = b%mfile%lo + b%mfile%shift
      f%hi = b%mfile%hi + b%mfile%shift
      f%rmax = b%support_factor(1:3)*b%mfile%lmax
    else
      call extrude_pick(b, 1, huge(1), [(-huge(1.0_wp), j = 1, 3)], &
        [(huge(1.0_wp), j = 1, 3)], 0, none, nowhere, ends, ends=.true.)
      f%lo = minval(ends%x, dim=2)
      f%hi = maxval(ends%x, dim=2)
      f%rmax = b%ext%rho
    end if
    ! the share's particles and those within a support of them (and a spacing)
    n = size(b%x, 2)
    reach = f%rmax + maxval(b%spacing)
    lo = huge(1.0_wp)
    hi = -huge(1.0_wp)
    if (n > 0) then
      lo = minval(b%x, dim=2) - reach
      hi = maxval(b%x, dim=2) + reach
    end if
    if (allocated(b%mfile)) then
      call tet_file_region(b, lo, hi, near, err)
      if (allocated(err)) return
    else
      call extrude_pick(b, 1, huge(1), lo, hi, 0, none, nowhere, near)
    end if
    call cloud_init(c, near%x, near%rho, near%vol, b%kid, b%wshape, b%bid, b%h(1:3), err, &
      grid_lo=f%lo, grid_hi=f%hi, rmax=f%rmax)
    if (allocated(err)) return
    allocate(det(n))
    call det_at_points(c, b%x, det)
    deep = deep_particles(c, near%boundary, b%x, b%rho)
  end subroutine side_facts_local
  !> The time-step policy: the deck's fixed dt, or (dt = 0) cfl x the critical step that
  !! follows the deformation; calibrated once against the power iteration, on the ranks'
  !! parts (comm: the ranks; collective).
  subroutine setup_time_step(deck, solids, ctl, comm)
    type(deck_t), intent(in) :: deck
    type(solid_t), intent(inout) :: solids(:)
    type(step_control_t), intent(out) :: ctl
    class(rank_comm_t), intent(inout) :: comm
    real(wp) :: dts, v(1)
    integer :: k
    call step_control_calibrate(ctl, solids, comm)
    dts = huge(1.0_wp)
    do k = 1, size(solids)
      dts = min(dts, spacing_step(solids(k)))
    end do
    ! (h_min of the part: the smallest over the ranks)
    v = -dts
    call comm%max_real(v)
    dts = -v(1)
    ctl%cfl = deck%solver%cfl
    ctl%adaptive = .not. (deck%solver%dt > 0.0_wp)
    if (.not. ctl%adaptive) then
      ctl%dt_fixed = deck%solver%dt
      write(output_unit, '(a,es10.3,a,es10.3,a,es10.3,a,f6.3,a)') 'dynamic: dt = ', &
        ctl%dt_fixed, ' s fixed by the deck; critical step 2/omega_max = ', ctl%dtc0, &
        ' s (h_min/c_d = ', dts, ' s): dt is ', ctl%dt_fixed/ctl%dtc0, ' of critical'
      if (ctl%dt_fixed > ctl%dtc0) write(output_unit, '(a)') 'dynamic: warning: dt '// &
        'exceeds the estimated critical step; the run is likely to go unstable'
    else
      write(output_unit, '(a,f5.2,a,es10.3,a,es10.3,a)') 'dynamic: dt = cfl ', ctl%cfl, &
        ' x critical step 2/omega_max (power iteration at t = 0: ', ctl%dtc0, &
        ' s; h_min/c_d = ', dts, ' s), re-estimated every step from the deformation'
    end if
    flush(output_unit)
  end subroutine setup_time_step

  !> What the MPI driver (mfcd_mpi) cannot run on ranks yet, as bad input (before anything
  !! is written).
  subroutine mpi_scene_check(deck, err)
    type(deck_t), intent(in) :: deck
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    character(len=*), parameter :: what = "deck '"
    if (deck%run%mode /= 'dynamic') then
      call set_error(err, what//deck%path//"', group &run, variable mode: the MPI driver "// &
        "runs mode = 'dynamic' only; run mfcd for the others")
      return
    end if
    if (deck%solver%subcycle) then
      call set_error(err, what//deck%path//"', group &solver, variable subcycle: not yet "// &
        "with MPI; set subcycle = .false. or run mfcd")
      return
    end if
    do k = 1, deck%ncontacts
      associate (c => deck%contacts(k))
        if (deck%bodies(c%imaster)%role == 'rigid') cycle
        ! a deforming master (or self-contact): its ghost particles (contact_dist_sm)
        if (c%detector /= 'det_m' .or. c%compare_detectors) then
          call set_error(err, what//deck%path//"', group &contact, variable detector: "// &
            "against the deforming master '"//trim(c%master)//"' the MPI driver takes "// &
            "detector = 'det_m' (and compare_detectors = .false.); run mfcd for the others")
          return
        end if
      end associate
    end do
  end subroutine mpi_scene_check
end module dynamic_setup_m
