!> mfcd on MPI ranks (issue 12; doc/parallel.md): `mpirun -np N mfcd_mpi DECK.nml` runs the
!! deck's dynamic problem with each rank stepping its part of every solid, and writes the
!! one HDF5 file (and XDMF) a serial `mfcd DECK.nml` writes, from rank 0. Every rank reads
!! the deck and builds the set-up (so bad input is found before anything is written; an
!! extruded 3D RKPM body is made as each rank's share and region only, and checked there,
!! so the ranks agree on an error first); only rank 0 logs. What the MPI driver does not
!! take yet is refused as bad input (mpi_domain_m: no subcycling). Options: --restart
!! CHECKPOINT.h5, continue from a checkpoint of the deck's run (&output checkpoint_every, by
!! mfcd or mfcd_mpi on any number of ranks);
!! --ghost-margin=F, the margin of the ghost width of contact with a deforming master (a
!! fraction of the width contact needs, default 0.5); --ghost-refresh=never, for the test
!! that proves the refreshes matter. Exit codes as mfcd's: 0 ok, 2 bad input (nothing
!! written), 1 run failed.
program mfcd_mpi
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  use kinds_m, only: wp, i64
  use hdf5_io_m, only: h5file_t, h5_open_rw, h5_attr, h5_close, h5_open_read, h5_has
  use rkpm_tl_m, only: axis_images
  use mpi_f08
  use memory_policy_m, only: memory_policy_apply, resident_kib, memory_trim, read_bytes
  use errors_m, only: error_t, exit_bad_input
  use strings_m, only: itoa
  use version_m, only: code_name, code_version, git_commit
  use deck_m, only: deck_t, read_deck
  use body_m, only: body_t, body_keep_share
  use body_setup_m, only: build_bodies, geo_mesh_file, plane_facts_file
  use file_system_m, only: process_id, path_exists, remove_file
  use tet_file_m, only: tet_file_facets
  use run_output_m, only: timestamp
  use output_path_m, only: check_output_path, output_result_text, scratch_name
  use log_m, only: log_print, log_flush
  use dynamic_setup_m, only: dynamic_setup_t, setup_dynamic, mpi_scene_check, setup_part_t, &
    root_needs_whole, body_per_part
  use explicit_driver_m, only: run_dynamic
  use mpi_domain_m, only: mpi_domain_t, mpi_domain_init, ghost_margin_default
  use mpi_comm_m, only: mpi_ranks_t, mpi_ranks_init
  use run_checkpoint_m, only: checkpoint_check, checkpoint_info_t, body_fingerprints
  implicit none
  type(deck_t) :: deck
  type(body_t), allocatable :: bodies(:)
  type(dynamic_setup_t) :: su
  type(error_t), allocatable :: err
  character(len=4096) :: arg, deck_path
  character(len=:), allocatable :: restart_path
  type(checkpoint_info_t) :: ckpt
  logical :: restart_next
  logical, allocatable :: per_part(:)
  !> the files rank 0 meshed the per-part gmsh scripts into ('' for other bodies)
  character(len=4096), allocatable :: mesh_files(:)
  integer :: me, nranks, code, k, ios, ndeck
  real(wp) :: ghost_margin
  logical :: ghost_refresh
  !> the ranks of MPI_COMM_WORLD: each solid's part on this one
  type(mpi_domain_t), target :: ranks
  !> the same ranks before the domain is made: the bodies' set-up shares a mesh file's
  !! whole checks over them (tet_file_m)
  type(mpi_ranks_t) :: world
  type(setup_part_t) :: sp
  ! freed large blocks go back to the system, so that a rank's peak holds what is alive at
  ! it (memory_policy_m); before MPI allocates anything
  call memory_policy_apply()
  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, me)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call mpi_ranks_init(world, MPI_COMM_WORLD)
  ! only rank 0 logs: the others' standard output goes nowhere
  if (me /= 0) open(unit=output_unit, file='/dev/null', action='write')
  ! options: --ghost-margin=F (contact with deforming masters: the ghost width's margin, a
  ! fraction of the width contact needs; default 0.5), --ghost-refresh=never (testing only:
  ! the first ghost sets are kept, and contacts they do not cover are missed)
  ghost_margin = ghost_margin_default
  ghost_refresh = .true.
  restart_path = ''
  restart_next = .false.
  ndeck = 0
  ios = 0
  do k = 1, command_argument_count()
    call get_command_argument(k, arg)
    if (restart_next) then
      restart_path = trim(arg)
      restart_next = .false.
    else if (trim(arg) == '--restart') then
      restart_next = .true.
    else if (index(arg, '--restart=') == 1) then
      restart_path = trim(arg(11:))
      if (len(restart_path) == 0) ios = 1
    else if (index(arg, '--ghost-margin=') == 1) then
      read(arg(16:), *, iostat=ios) ghost_margin
      if (ios /= 0 .or. .not. (ghost_margin >= 0.0_wp)) ios = 1
    else if (trim(arg) == '--ghost-refresh=never') then
      ghost_refresh = .false.
    else if (arg(1:1) == '-') then
      ios = 1
    else
      ndeck = ndeck + 1
      deck_path = arg
    end if
  end do
  if (ndeck /= 1 .or. ios /= 0 .or. restart_next) then
    if (me == 0) write(error_unit, '(a)') 'usage: mpirun -np N mfcd_mpi [--restart '// &
      'CHECKPOINT.h5] [--ghost-margin=F] DECK.nml   (a checkpoint of the deck''s run by '// &
      'mfcd or mfcd_mpi on any number of ranks; F >= 0, default 0.5: the ghost width of '// &
      'contact with a deforming master is (1 + F) times the width contact needs)'
    call finish(exit_bad_input)
  end if
  arg = deck_path
  call log_print(code_name//' '//code_version//' (git '//git_commit//') '//timestamp()// &
    ' deck '//trim(arg)//', MPI ranks: '//itoa(nranks))
  call read_deck(trim(arg), deck, err)
  if (.not. allocated(err)) call mpi_scene_check(deck, err)
  ! (said, not silent: a part has no quiet state)
  if (.not. allocated(err)) then
    if (deck%solver%skip_quiet .and. any(deck%bodies(1:deck%nbodies)%role == 'deformable')) &
      call log_print('mfcd_mpi: &solver skip_quiet is not applied on ranks: every point '// &
      'is evaluated every step (the serial skipping is exact to round-off, not to the '// &
      'bit: give skip_quiet = .false. to compare with a serial run bit for bit)')
  end if
  ! (an extruded 3D RKPM body is made as each rank's share, its region later from its
  ! recipe: no rank makes the whole body; its checks are then the share's, so the ranks
  ! agree on an error before anything collective)
  if (.not. allocated(err)) then
    allocate(per_part(deck%nbodies), mesh_files(deck%nbodies))
    mesh_files = ''
    do k = 1, deck%nbodies
      per_part(k) = body_per_part(deck, k, nranks, root_needs_whole(deck))
    end do
    call plane_files_vetted()
    call mesh_scripts()
    call check_whole()
  end if
  ! (a script rank 0 could not mesh, a body it found wrong, or a bad output path, ends
  ! every rank first)
  call agree_or_fail(1)
  if (.not. allocated(err)) call build_bodies(deck, bodies, err, [me, nranks], per_part, &
    mesh_files, world)
  call agree_or_fail(exit_bad_input)
  ! the ranks (the set-up's sums go through them too)
  call mpi_domain_init(ranks, MPI_COMM_WORLD, ghost_margin, ghost_refresh, &
    root_needs_whole(deck))
  ! (every rank integrates and keeps only its region's rows of 3D RKPM tables, the masses
  ! summed over the ranks; rank 0 keeps the whole ones when its det(M) fields need them)
  ! (what a checkpoint recognises its bodies by: exact sums over the ranks' shares)
  if (.not. allocated(err)) call body_fingerprints(bodies, ranks%comm)
  ! (a mesh file's facets, found per share, put in rows over the ranks in the whole
  ! mesh's order, which they write into /bodies together)
  if (.not. allocated(err)) call tet_file_facets(bodies, ranks%comm)
  if (.not. allocated(err)) call log_facet_rows()
  sp%me = me
  sp%nranks = nranks
  sp%root_whole = root_needs_whole(deck)
  sp%comm => ranks%comm
  if (.not. allocated(err)) call setup_dynamic(deck, bodies, su, err, part=sp)
  if (.not. allocated(err) .and. len(restart_path) > 0) then
    call checkpoint_check(restart_path, deck, bodies, ckpt, err)
    if (.not. allocated(err)) call log_print("restart: checkpoint '"//restart_path// &
      "' of this deck, step "//itoa(ckpt%step)//", is valid")
  end if
  if (.not. allocated(err) .and. me == 0) call check_output_path(deck, err, restart_path)
  call agree_or_fail(exit_bad_input)
  ! (every rank has read its part of the scripts' meshes: the set-up is done)
  call drop_meshes()
  ! the deformable bodies are the set-up's: past it a rank reads their names, sizes and
  ! fingerprints, and writes its share of their rows and facets into /bodies (rank 0 the
  ! boundary loops too): every rank keeps that share only, before the split, whose peak
  ! the whole bodies would add to
  do k = 1, deck%nbodies
    if (deck%bodies(k)%role == 'deformable') call body_keep_share(bodies(k), me, nranks)
  end do
  call log_memory('after the set-up')
  ! the serial program's driver, given the ranks instead of one
  if (len(restart_path) > 0) then
    call run_dynamic(deck, bodies, su, ranks, err, restart_path)
  else
    call run_dynamic(deck, bodies, su, ranks, err)
  end if
  call agree_or_fail(1)
  call log_memory('at the end')
  call log_print('mfcd_mpi: completed: wrote '//output_result_text(deck))
  call finish(0)

contains

  !> The deformable 3D gmsh scripts (shape 'geo') made per part: rank 0 meshes each once
  !! into a scratch file beside the output (body_setup_m geo_mesh_file; the output path
  !! checked first, so that a bad one is said as before), which every rank then reads its
  !! part of as a mesh file (tet_file_m) and rank 0 removes after the set-up (or when the
  !! run ends earlier): gmsh meshes a model whole, so one rank holds the whole mesh while
  !! gmsh makes it and none after. Collective (rank 0's process id names the files).
  !! A 2D script (any role) the same way: each rank reads its part of the file when the body
  !! is read per part (tri_file_m), else the file whole; gmsh runs on one rank instead of
  !! on every one. A user's plane particle file read per part gets the name of the file
  !! of its whole facts here, which rank 0 writes once it has checked it (check_whole).
  subroutine mesh_scripts()
    integer :: pid, j
    logical :: once(deck%nbodies), facts(deck%nbodies)
    once = deck%bodies(1:deck%nbodies)%shape == 'geo' .and. (per_part .or. &
      deck%run%ndim == 2)
    ! (a user's plane particle file read per part: the whole file's facts, written apart)
    facts = deck%bodies(1:deck%nbodies)%shape == 'file' .and. per_part .and. &
      deck%run%ndim == 2
    if (.not. any(once .or. facts)) return
    pid = process_id()
    call MPI_Bcast(pid, 1, MPI_INTEGER, 0, MPI_COMM_WORLD)
    if (me == 0) call check_output_path(deck, err, restart_path)
    do j = 1, deck%nbodies
      ! (written by rank 0 once it has checked the file: check_whole)
      if (facts(j)) mesh_files(j) = scratch_name(deck, itoa(pid)//'-facts'//itoa(j)//'.h5')
      if (.not. once(j)) cycle
      ! (a plane mesh is read as a particle file, which its name's .h5 says)
      mesh_files(j) = scratch_name(deck, itoa(pid)//'-mesh'//itoa(j)// &
        trim(merge('.h5', '   ', deck%run%ndim == 2)))
      if (me /= 0 .or. allocated(err)) cycle
      call geo_mesh_file(deck, j, trim(mesh_files(j)), err)
      ! (gmsh's freed model back to the system: its thread's arena keeps the pages)
      call memory_trim()
      if (.not. allocated(err)) call log_print("mfcd_mpi: body "//itoa(j)//" ('"// &
        trim(deck%bodies(j)%name)//"'): gmsh meshed '"//trim(deck%bodies(j)%file)// &
        "' once, on rank 0, into '"//trim(mesh_files(j))//"'; each rank reads "// &
        trim(merge('its part of it', 'it whole      ', per_part(j)))// &
        " (removed after the set-up)")
    end do
  end subroutine mesh_scripts

  !> A plane gmsh script's body or a user's plane particle file read per part (tri_file_m)
  !! is not checked on the ranks: rank 0 builds every body of the deck whole once, as mfcd
  !! does (the scripts' from the files it meshed them into), through every serial check
  !! of each body and of the bodies together, and frees them; an error is the serial one
  !! (exit 2). A particle file so checked gets the file of its whole facts
  !! (plane_facts_file). Rank 0 then holds the plane bodies whole at the set-up, as it
  !! holds the mesh while gmsh makes it (doc/parallel.md).
  subroutine check_whole()
    type(body_t), allocatable :: whole(:)
    type(h5file_t) :: f
    real(wp) :: image(2)
    integer :: j
    logical :: plane
    plane = .false.
    do j = 1, deck%nbodies
      if (per_part(j) .and. deck%run%ndim == 2 .and. (deck%bodies(j)%shape == 'geo' .or. &
        deck%bodies(j)%shape == 'file')) plane = .true.
    end do
    if (.not. plane .or. me /= 0 .or. allocated(err)) return
    call build_bodies(deck, whole, err, mesh_files=mesh_files)
    ! (a user's plane particle file, checked: the whole file's facts for the ranks)
    do j = 1, deck%nbodies
      if (allocated(err)) exit
      if (.not. (per_part(j) .and. deck%bodies(j)%shape == 'file')) cycle
      call plane_facts_file(deck, j, trim(mesh_files(j)), err)
      if (.not. allocated(err)) call log_print("mfcd_mpi: body "//itoa(j)//" ('"// &
        trim(deck%bodies(j)%name)//"'): each rank reads its part of '"// &
        trim(deck%bodies(j)%file)//"', rank 0 wrote the whole file's facts into '"// &
        trim(mesh_files(j))//"' (removed after the set-up)")
    end do
    ! (an RKPM body's in axisymmetry: the extent of its mirror images about the axis,
    ! which the whole cloud's grid takes and no share can find, with its file)
    do j = 1, deck%nbodies
      if (allocated(err)) exit
      if (.not. (per_part(j) .and. len_trim(mesh_files(j)) > 0 .and. &
        deck%bodies(j)%discretization == 'rkpm' .and. deck%run%geometry == &
        'axisymmetric')) cycle
      image = [huge(1.0_wp), -huge(1.0_wp)]
      call axis_images(whole(j), image(1), image(2))
      call h5_open_rw(f, trim(mesh_files(j)), err)
      if (.not. allocated(err)) call h5_attr(f, '/mesh', 'axis_images', image, err)
      call h5_close(f, err)
    end do
    if (allocated(whole)) deallocate(whole)
    call memory_trim()
    if (.not. allocated(err)) call log_print('mfcd_mpi: rank 0 built the bodies whole '// &
      'once and checked them (the plane meshes'' bodies are read per part, unchecked '// &
      'on the ranks)')
  end subroutine check_whole

  !> A user's plane particle file is read per part only when it carries what the parts
  !! read (tri_file_m): its triangles (every node's support, and an element body's
  !! elements) and, for an RKPM body, its median-dual cells; else each rank builds it
  !! whole as mfcd does (and a broken file gets the serial message). Rank 0 looks, every
  !! rank learns. Collective.
  subroutine plane_files_vetted()
    type(h5file_t) :: f
    type(error_t), allocatable :: e2
    integer :: j
    do j = 1, deck%nbodies
      if (me /= 0) exit
      if (.not. (per_part(j) .and. deck%run%ndim == 2 .and. &
        deck%bodies(j)%shape == 'file')) cycle
      call h5_open_read(f, trim(deck%bodies(j)%file), e2)
      if (allocated(e2)) then
        per_part(j) = .false.
        deallocate(e2)
        cycle
      end if
      ! (each looked for: h5_has is not pure, which .and. may skip)
      per_part(j) = h5_has(f, '/mesh/triangles')
      if (per_part(j) .and. deck%bodies(j)%discretization == 'rkpm') &
        per_part(j) = h5_has(f, '/cells/ptr')
      if (per_part(j) .and. deck%bodies(j)%discretization == 'rkpm') &
        per_part(j) = h5_has(f, '/cells/xy')
      call h5_close(f, e2)
      if (allocated(e2)) deallocate(e2)
    end do
    call MPI_Bcast(per_part, deck%nbodies, MPI_LOGICAL, 0, MPI_COMM_WORLD)
  end subroutine plane_files_vetted

  !> Rank 0 removes the scratch meshes of mesh_scripts (every rank past reading them).
  subroutine drop_meshes()
    logical :: gone
    integer :: j
    if (me /= 0 .or. .not. allocated(mesh_files)) return
    do j = 1, size(mesh_files)
      if (len_trim(mesh_files(j)) == 0) cycle
      if (path_exists(trim(mesh_files(j)))) gone = remove_file(trim(mesh_files(j)))
      mesh_files(j) = ''
    end do
  end subroutine drop_meshes

  !> The ranks' resident memory now and their peaks so far, smallest and largest (MiB),
  !! in the log (what a rank holds of the whole body shows in how these grow with it:
  !! doc/parallel.md). Collective.
  subroutine log_memory(when)
    character(len=*), intent(in) :: when
    integer(i64) :: m(3), lo(3), hi(3)
    call resident_kib(m(1), m(2))
    ! (and the bytes read so far, in KiB: a mesh file's reading per rank)
    m(3) = read_bytes()
    if (m(3) >= 0) m(3) = m(3)/1024
    call MPI_Allreduce(m, lo, 3, MPI_INTEGER8, MPI_MIN, MPI_COMM_WORLD)
    call MPI_Allreduce(m, hi, 3, MPI_INTEGER8, MPI_MAX, MPI_COMM_WORLD)
    ! (not on Linux: nothing to say)
    if (any(lo(1:2) < 0)) return
    call log_print('mfcd_mpi: resident memory '//when//': '//mib(lo(1), hi(1))// &
      ' MiB a rank (peak so far '//mib(lo(2), hi(2))//' MiB)')
    if (lo(3) >= 0) call log_print('mfcd_mpi: read '//when//': '//mib(lo(3), hi(3))// &
      ' MiB a rank (files and pipes)')
  end subroutine log_memory

  !> The bodies whose surface the ranks hold in rows (an extruded body made per rank, a
  !! mesh file read per part: body_t facet0 > 0): how many facets the most loaded rank
  !! holds of the whole surface's. Collective.
  subroutine log_facet_rows()
    integer :: j, mine, most
    do j = 1, size(bodies)
      if (.not. allocated(bodies(j)%facets) .or. bodies(j)%facet0 == 0) cycle
      mine = size(bodies(j)%facets, 2)
      call MPI_Allreduce(mine, most, 1, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
      call log_print("mfcd_mpi: body "//itoa(j)//" ('"//trim(bodies(j)%name)//"'): its "// &
        "surface's "//itoa(bodies(j)%nfacets)//" facets in rows over the ranks, at most "// &
        itoa(most)//" on a rank")
    end do
  end subroutine log_facet_rows

  function mib(lo, hi) result(txt)
    integer(i64), intent(in) :: lo, hi
    character(len=:), allocatable :: txt
    txt = itoa(int((lo + 512)/1024))
    if (hi /= lo) txt = txt//'-'//itoa(int((hi + 512)/1024))
  end function mib

  !> Any rank's error ends every rank with the code of its kind (bad input 2, else 1).
  subroutine agree_or_fail(kind)
    integer, intent(in) :: kind
    integer :: mine, n
    mine = merge(1, 0, allocated(err))
    call MPI_Allreduce(mine, n, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
    if (n == 0) return
    if (allocated(err)) then
      call log_flush()
      write(error_unit, '(a)') 'mfcd_mpi: error (rank '//itoa(me)//'): '//err%message
      flush(error_unit)
      code = kind
      if (err%code == exit_bad_input) code = exit_bad_input
    else
      code = kind
    end if
    call finish(code)
  end subroutine agree_or_fail

  subroutine finish(c)
    integer, intent(in) :: c
    integer :: cc
    call MPI_Allreduce(c, cc, 1, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
    ! (every rank is here: none reads a scratch mesh any more)
    call drop_meshes()
    call MPI_Finalize()
    if (cc /= 0) stop cc, quiet=.true.
    stop
  end subroutine finish
end program mfcd_mpi
