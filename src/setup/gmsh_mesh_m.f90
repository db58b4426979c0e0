!> gmsh in memory: builds the model of a gmsh script, as mfcd's reader made it
!! (geo_script_m: every call with plain numbers), through gmsh's C API (gmshc.h, bound here
!! with ISO_C_BINDING) and meshes it with linear triangles (a 2D run) or linear tetrahedra
!! (a 3D run: the model's volumes), for &body shape = 'geo'. gmsh's
!! own interpreter never sees the user's text: no script is merged or opened, so nothing
!! of gmsh's language but the subset reaches gmsh.
!!
!! gmsh runs in a confined thread (confine_m, src/io/confine.c): it cannot create, change or
!! remove a file, start a process or read standard input (its GUI toolkit, FLTK, writes
!! preference files when gmsh starts, as root /etc/fltk/fltk.org/fltk.prefs; the write
!! fails there), it runs with / as its working directory (PETSc, linked into gmsh, reads
!! .petscrc and petscrc from the working directory when gmsh starts, and their options can
!! make it write files or start a debugger) and /dev/null as HOME, and it has a wall-clock
!! and a memory limit, past which the process ends with exit code 2 and a message saying
!! which limit and how to raise it. Nothing is written before, so nothing is lost.
!!
!! The calls are those gmsh's parser makes for the same script (Gmsh.y of gmsh 4: a point's
!! size 0 is "none", a 3-point ellipse is start, centre, start, end), in the script's order,
!! then synchronize, Mesh.ElementOrder 1, generate 2 (3 in a 3D run), the nodes and the
!! elements of that dimension, finalize; regression_geo_equivalence checks that the mesh is
!! gmsh's mesh of the script, bit for bit. Compiled when the build finds gmsh (MFCD_GMSH,
!! cmake/MfcdFindGmsh.cmake); gmsh_mesh_stub_m.f90 is this module without it.
!!
!! The task sets the floating-point traps off in its own thread (a Debug build traps invalid
!! operations, which gmsh's arithmetic may raise and handle); mfcd's threads keep theirs.
module gmsh_mesh_m
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_size_t, c_char, c_ptr, &
    c_null_ptr, c_null_char, c_associated, c_f_pointer, c_loc, c_funloc, c_funptr
  use, intrinsic :: ieee_exceptions, only: ieee_set_halting_mode, ieee_all
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use strings_m, only: itoa
  use confine_m, only: confine_limits_t, confined_run
  use geo_script_m, only: geo_model_t, geo_field_type, geo_field_option, geo_mesh_option, &
    op_point, op_line, op_circle, op_ellipse, op_spline, op_bspline, op_curve_loop, &
    op_plane_surface, op_surface, op_surface_loop, op_volume, op_field, op_field_number, &
    op_field_list, op_background, op_mesh_option
  implicit none
  private
  public :: gmsh_built_in, gmsh_version, gmsh_mesh_model

  !> This build meshes .geo files (the stub says .false.).
  logical, parameter :: gmsh_built_in = .true.
  !> gmsh's element types of the 3-node triangle and the 4-node tetrahedron.
  integer(c_int), parameter :: triangle_3 = 2, tetrahedron_4 = 4

  interface
    subroutine gmshInitialize(argc, argv, readConfigFiles, run, ierr) &
      bind(C, name='gmshInitialize')
      import :: c_int, c_ptr
      integer(c_int), value :: argc
      type(c_ptr), value :: argv
      integer(c_int), value :: readConfigFiles, run
      integer(c_int), intent(out) :: ierr
    end subroutine gmshInitialize
    subroutine gmshFinalize(ierr) bind(C, name='gmshFinalize')
      import :: c_int
      integer(c_int), intent(out) :: ierr
    end subroutine gmshFinalize
    subroutine gmshFree(p) bind(C, name='gmshFree')
      import :: c_ptr
      type(c_ptr), value :: p
    end subroutine gmshFree
    subroutine gmshOptionSetNumber(name, value, ierr) bind(C, name='gmshOptionSetNumber')
      import :: c_char, c_double, c_int
      character(kind=c_char), intent(in) :: name(*)
      real(c_double), value :: value
      integer(c_int), intent(out) :: ierr
    end subroutine gmshOptionSetNumber
    subroutine gmshOptionGetString(name, value, ierr) bind(C, name='gmshOptionGetString')
      import :: c_char, c_ptr, c_int
      character(kind=c_char), intent(in) :: name(*)
      type(c_ptr), intent(out) :: value
      integer(c_int), intent(out) :: ierr
    end subroutine gmshOptionGetString
    integer(c_int) function gmshModelGeoAddPoint(x, y, z, meshSize, tag, ierr) &
      bind(C, name='gmshModelGeoAddPoint')
      import :: c_double, c_int
      real(c_double), value :: x, y, z, meshSize
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddPoint
    integer(c_int) function gmshModelGeoAddLine(startTag, endTag, tag, ierr) &
      bind(C, name='gmshModelGeoAddLine')
      import :: c_int
      integer(c_int), value :: startTag, endTag, tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddLine
    integer(c_int) function gmshModelGeoAddCircleArc(startTag, centerTag, endTag, tag, nx, &
      ny, nz, ierr) bind(C, name='gmshModelGeoAddCircleArc')
      import :: c_int, c_double
      integer(c_int), value :: startTag, centerTag, endTag, tag
      real(c_double), value :: nx, ny, nz
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddCircleArc
    integer(c_int) function gmshModelGeoAddEllipseArc(startTag, centerTag, majorTag, endTag, &
      tag, nx, ny, nz, ierr) bind(C, name='gmshModelGeoAddEllipseArc')
      import :: c_int, c_double
      integer(c_int), value :: startTag, centerTag, majorTag, endTag, tag
      real(c_double), value :: nx, ny, nz
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddEllipseArc
    !> gmshModelGeoAddSpline, AddBSpline, AddPlaneSurface, AddSurfaceLoop and AddVolume
    !! share this form (a tag list, a tag), bound one by one below.
    integer(c_int) function gmshModelGeoAddSpline(tags, n, tag, ierr) &
      bind(C, name='gmshModelGeoAddSpline')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddSpline
    integer(c_int) function gmshModelGeoAddBSpline(tags, n, tag, ierr) &
      bind(C, name='gmshModelGeoAddBSpline')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddBSpline
    integer(c_int) function gmshModelGeoAddPlaneSurface(tags, n, tag, ierr) &
      bind(C, name='gmshModelGeoAddPlaneSurface')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddPlaneSurface
    integer(c_int) function gmshModelGeoAddSurfaceLoop(tags, n, tag, ierr) &
      bind(C, name='gmshModelGeoAddSurfaceLoop')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddSurfaceLoop
    integer(c_int) function gmshModelGeoAddVolume(tags, n, tag, ierr) &
      bind(C, name='gmshModelGeoAddVolume')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddVolume
    integer(c_int) function gmshModelGeoAddCurveLoop(tags, n, tag, reorient, ierr) &
      bind(C, name='gmshModelGeoAddCurveLoop')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag, reorient
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddCurveLoop
    integer(c_int) function gmshModelGeoAddSurfaceFilling(tags, n, tag, sphereCenterTag, &
      ierr) bind(C, name='gmshModelGeoAddSurfaceFilling')
      import :: c_int, c_size_t
      integer(c_int), intent(in) :: tags(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: tag, sphereCenterTag
      integer(c_int), intent(out) :: ierr
    end function gmshModelGeoAddSurfaceFilling
    subroutine gmshModelGeoSynchronize(ierr) bind(C, name='gmshModelGeoSynchronize')
      import :: c_int
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelGeoSynchronize
    integer(c_int) function gmshModelMeshFieldAdd(fieldType, tag, ierr) &
      bind(C, name='gmshModelMeshFieldAdd')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: fieldType(*)
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end function gmshModelMeshFieldAdd
    subroutine gmshModelMeshFieldSetNumber(tag, option, value, ierr) &
      bind(C, name='gmshModelMeshFieldSetNumber')
      import :: c_char, c_int, c_double
      integer(c_int), value :: tag
      character(kind=c_char), intent(in) :: option(*)
      real(c_double), value :: value
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelMeshFieldSetNumber
    subroutine gmshModelMeshFieldSetNumbers(tag, option, values, n, ierr) &
      bind(C, name='gmshModelMeshFieldSetNumbers')
      import :: c_char, c_int, c_double, c_size_t
      integer(c_int), value :: tag
      character(kind=c_char), intent(in) :: option(*)
      real(c_double), intent(in) :: values(*)
      integer(c_size_t), value :: n
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelMeshFieldSetNumbers
    subroutine gmshModelMeshFieldSetAsBackgroundMesh(tag, ierr) &
      bind(C, name='gmshModelMeshFieldSetAsBackgroundMesh')
      import :: c_int
      integer(c_int), value :: tag
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelMeshFieldSetAsBackgroundMesh
    subroutine gmshModelMeshGenerate(dim, ierr) bind(C, name='gmshModelMeshGenerate')
      import :: c_int
      integer(c_int), value :: dim
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelMeshGenerate
    subroutine gmshModelMeshGetNodes(nodeTags, nodeTags_n, coord, coord_n, parametricCoord, &
      parametricCoord_n, dim, tag, includeBoundary, returnParametricCoord, ierr) &
      bind(C, name='gmshModelMeshGetNodes')
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), intent(out) :: nodeTags, coord, parametricCoord
      integer(c_size_t), intent(out) :: nodeTags_n, coord_n, parametricCoord_n
      integer(c_int), value :: dim, tag, includeBoundary, returnParametricCoord
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelMeshGetNodes
    subroutine gmshModelMeshGetElements(elementTypes, elementTypes_n, elementTags, &
      elementTags_n, elementTags_nn, nodeTags, nodeTags_n, nodeTags_nn, dim, tag, ierr) &
      bind(C, name='gmshModelMeshGetElements')
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), intent(out) :: elementTypes, elementTags, elementTags_n, nodeTags, &
        nodeTags_n
      integer(c_size_t), intent(out) :: elementTypes_n, elementTags_nn, nodeTags_nn
      integer(c_int), value :: dim, tag
      integer(c_int), intent(out) :: ierr
    end subroutine gmshModelMeshGetElements
    subroutine gmshLoggerGetLastError(error, ierr) bind(C, name='gmshLoggerGetLastError')
      import :: c_ptr, c_int
      type(c_ptr), intent(out) :: error
      integer(c_int), intent(out) :: ierr
    end subroutine gmshLoggerGetLastError
    pure integer(c_size_t) function c_strlen(s) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value, intent(in) :: s
    end function c_strlen
  end interface

  !> What the confined task gets and gives back: the model to build (none: only gmsh's
  !! version), the mesh's dimension (2: triangles, 3: tetrahedra), the mesh's raw arrays,
  !! gmsh's version, and msg, '' or what went wrong (with the script line of the call gmsh
  !! refused).
  type :: mesh_job_t
    type(geo_model_t), pointer :: model => null()
    integer :: dim = 2
    integer(i64), allocatable :: tags(:), tri_tags(:)
    real(wp), allocatable :: xyz(:)
    character(len=:), allocatable :: version, msg
  end type mesh_job_t

contains

  !> gmsh's version (its option General.Version), e.g. '4.15.2'; '' when it cannot say.
  !! gmsh starts in the confined thread, as for meshing (within a minute).
  function gmsh_version() result(v)
    character(len=:), allocatable :: v
    type(mesh_job_t), target :: job
    type(confine_limits_t) :: limits
    character(len=:), allocatable :: failure
    type(c_funptr) :: task
    limits%seconds = 60.0_wp
    limits%msg_time = 'gmsh did not start within a minute'
    limits%msg_crash = 'gmsh crashed when it started'
    job%version = ''
    job%msg = ''
    ! through a variable: gfortran 12 would put the constant c_funloc(mesh_task) in
    ! .rodata with an absolute relocation (a text relocation in a PIE)
    task = c_funloc(mesh_task)
    call confined_run(task, c_loc(job), limits, failure)
    v = job%version
  end function gmsh_version

  !> Build the model in gmsh and mesh it in dim = 2 (linear triangles of its surfaces) or
  !! dim = 3 (linear tetrahedra of its volumes) dimensions, within limits: the node tags
  !! tags(n), their coordinates xyz(3*n) and the node tags of the elements, tri_tags(3*ne)
  !! of the 3-node triangles or tri_tags(4*ne) of the 4-node tetrahedra, as gmsh returns
  !! them (mesh_cells_m makes the body of them); version is gmsh's. err says what went
  !! wrong: gmsh's own message, with the line of the script whose call it refused, or why
  !! gmsh could not be started confined.
  subroutine gmsh_mesh_model(model, dim, limits, tags, xyz, tri_tags, version, err)
    type(geo_model_t), target, intent(in) :: model
    integer, intent(in) :: dim
    type(confine_limits_t), intent(in) :: limits
    integer(i64), allocatable, intent(out) :: tags(:), tri_tags(:)
    real(wp), allocatable, intent(out) :: xyz(:)
    character(len=:), allocatable, intent(out) :: version
    type(error_t), allocatable, intent(inout) :: err
    type(mesh_job_t), target :: job
    character(len=:), allocatable :: failure
    type(c_funptr) :: task
    job%model => model
    job%dim = dim
    job%version = ''
    job%msg = ''
    task = c_funloc(mesh_task)
    call confined_run(task, c_loc(job), limits, failure)
    version = job%version
    if (len(failure) > 0) then
      call set_error(err, "gmsh cannot be run confined on this system ("//failure//"): "// &
        "mfcd runs gmsh only in a thread that can write no file and start no process "// &
        "(Linux seccomp, x86-64 or AArch64); mesh the script elsewhere and give the mesh "// &
        "as shape = 'file'")
      return
    end if
    if (len(job%msg) > 0) then
      call set_error(err, job%msg)
      return
    end if
    call move_alloc(job%tags, tags)
    call move_alloc(job%xyz, xyz)
    call move_alloc(job%tri_tags, tri_tags)
  end subroutine gmsh_mesh_model

  !> The confined task: gmsh started without configuration files and with its terminal
  !! output off, the model's calls, the mesh, gmsh finalized.
  subroutine mesh_task(arg) bind(C)
    type(c_ptr), value, intent(in) :: arg
    type(mesh_job_t), pointer :: job
    integer(c_int) :: ierr, ierr2
    call c_f_pointer(arg, job)
    call ieee_set_halting_mode(ieee_all, .false.)
    call gmshInitialize(0_c_int, c_null_ptr, 0_c_int, 0_c_int, ierr)
    if (ierr /= 0) then
      job%msg = 'gmsh failed to start'
      return
    end if
    call gmshOptionSetNumber('General.Terminal'//c_null_char, 0.0_c_double, ierr)
    call option_string('General.Version', job%version)
    if (associated(job%model)) then
      call build(job%model, job%msg)
      if (len(job%msg) == 0) then
        call gmshOptionSetNumber('Mesh.ElementOrder'//c_null_char, 1.0_c_double, ierr)
        call gmshModelMeshGenerate(int(job%dim, c_int), ierr)
        if (ierr == 0) call get_nodes(job%tags, job%xyz, ierr)
        if (ierr == 0) call get_elements(job%dim, job%tri_tags, ierr)
        if (ierr /= 0) job%msg = 'gmsh cannot mesh the script: '//last_error()
      end if
    end if
    call gmshFinalize(ierr2)
  end subroutine mesh_task

  !> The model's calls in order, then synchronize. msg: gmsh's message and the script line
  !! of the first call it refused.
  subroutine build(m, msg)
    type(geo_model_t), intent(in) :: m
    character(len=:), allocatable, intent(inout) :: msg
    integer :: k, a, z
    integer(c_int) :: ierr, t
    integer(c_int), allocatable :: ids(:)
    integer(c_size_t) :: n
    do k = 1, m%nops
      ierr = 0
      t = int(m%tag(k), c_int)
      ids = int(m%ints(m%i0(k):m%i0(k) + m%ni(k) - 1), c_int)
      n = int(size(ids), c_size_t)
      a = m%r0(k)
      z = m%r0(k) + m%nr(k) - 1
      select case (m%kind(k))
      case (op_point)
        t = gmshModelGeoAddPoint(m%reals(a), m%reals(a + 1), m%reals(a + 2), m%reals(a + 3), &
          t, ierr)
      case (op_line)
        t = gmshModelGeoAddLine(ids(1), ids(2), t, ierr)
      case (op_circle)
        t = gmshModelGeoAddCircleArc(ids(1), ids(2), ids(3), t, 0.0_c_double, &
          0.0_c_double, 0.0_c_double, ierr)
      case (op_ellipse)
        t = gmshModelGeoAddEllipseArc(ids(1), ids(2), ids(3), ids(4), t, 0.0_c_double, &
          0.0_c_double, 0.0_c_double, ierr)
      case (op_spline)
        t = gmshModelGeoAddSpline(ids, n, t, ierr)
      case (op_bspline)
        t = gmshModelGeoAddBSpline(ids, n, t, ierr)
      case (op_curve_loop)
        t = gmshModelGeoAddCurveLoop(ids, n, t, 0_c_int, ierr)
      case (op_plane_surface)
        t = gmshModelGeoAddPlaneSurface(ids, n, t, ierr)
      case (op_surface)
        t = gmshModelGeoAddSurfaceFilling(ids, n, t, -1_c_int, ierr)
      case (op_surface_loop)
        t = gmshModelGeoAddSurfaceLoop(ids, n, t, ierr)
      case (op_volume)
        t = gmshModelGeoAddVolume(ids, n, t, ierr)
      case (op_field)
        t = gmshModelMeshFieldAdd(geo_field_type(m%sub(k))//c_null_char, t, ierr)
      case (op_field_number)
        call gmshModelMeshFieldSetNumber(t, geo_field_option(m%sub(k))//c_null_char, &
          real(m%reals(a), c_double), ierr)
      case (op_field_list)
        call gmshModelMeshFieldSetNumbers(t, geo_field_option(m%sub(k))//c_null_char, &
          real(m%reals(a:z), c_double), int(z - a + 1, c_size_t), ierr)
      case (op_background)
        call gmshModelMeshFieldSetAsBackgroundMesh(t, ierr)
      case (op_mesh_option)
        call gmshOptionSetNumber('Mesh.'//geo_mesh_option(m%sub(k))//c_null_char, &
          real(m%reals(a), c_double), ierr)
      end select
      if (ierr /= 0) then
        msg = 'gmsh refuses line '//itoa(m%line(k))//' of the script: '//last_error()
        return
      end if
    end do
    call gmshModelGeoSynchronize(ierr)
    if (ierr /= 0) msg = 'gmsh cannot build the geometry: '//last_error()
  end subroutine build

  subroutine option_string(name, v)
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(inout) :: v
    type(c_ptr) :: p
    integer(c_int) :: ierr
    call gmshOptionGetString(name//c_null_char, p, ierr)
    if (ierr == 0) v = c_text(p)
  end subroutine option_string

  !> gmsh's last error message ('(no message)' if none).
  function last_error() result(msg)
    character(len=:), allocatable :: msg
    type(c_ptr) :: p
    integer(c_int) :: ierr
    msg = ''
    call gmshLoggerGetLastError(p, ierr)
    if (ierr == 0) msg = c_text(p)
    if (len(msg) == 0) msg = '(no message)'
  end function last_error

  !> A C string that gmsh allocated, as Fortran text; the string is freed.
  function c_text(p) result(t)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: t
    character(kind=c_char), pointer :: chars(:)
    integer :: n, i
    if (.not. c_associated(p)) then
      t = ''
      return
    end if
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: t)
    do i = 1, n
      t(i:i) = chars(i)
    end do
    call gmshFree(p)
  end function c_text

  !> Every mesh node (getNodes with its defaults: all entities): tags and x, y, z.
  subroutine get_nodes(tags, xyz, ierr)
    integer(i64), allocatable, intent(out) :: tags(:)
    real(wp), allocatable, intent(out) :: xyz(:)
    integer(c_int), intent(out) :: ierr
    type(c_ptr) :: ptags, pcoord, pparam
    integer(c_size_t) :: ntags, ncoord, nparam
    integer(c_size_t), pointer :: t(:)
    real(c_double), pointer :: c(:)
    call gmshModelMeshGetNodes(ptags, ntags, pcoord, ncoord, pparam, nparam, -1_c_int, &
      -1_c_int, 0_c_int, 0_c_int, ierr)
    if (ierr /= 0) return
    allocate(tags(ntags), xyz(ncoord))
    if (ntags > 0) then
      call c_f_pointer(ptags, t, [ntags])
      tags = int(t, i64)
    end if
    if (ncoord > 0) then
      call c_f_pointer(pcoord, c, [ncoord])
      xyz = real(c, wp)
    end if
    call free_if(ptags)
    call free_if(pcoord)
    call free_if(pparam)
  end subroutine get_nodes

  !> The node tags of the 3-node triangles among the 2D elements (getElements(2)), or of
  !! the 4-node tetrahedra among the 3D elements (getElements(3)), in the order gmsh gives
  !! them.
  subroutine get_elements(dim, tri_tags, ierr)
    integer, intent(in) :: dim
    integer(i64), allocatable, intent(out) :: tri_tags(:)
    integer(c_int), intent(out) :: ierr
    type(c_ptr) :: ptypes, petags, petags_n, pntags, pntags_n
    integer(c_size_t) :: ntypes, netags_nn, nntags_nn
    integer(c_int), pointer :: types(:)
    type(c_ptr), pointer :: etags(:), ntags(:)
    integer(c_size_t), pointer :: etags_n(:), ntags_n(:), nodes(:)
    integer(i64), allocatable :: part(:)
    integer :: k
    integer(c_int) :: want
    want = triangle_3
    if (dim == 3) want = tetrahedron_4
    call gmshModelMeshGetElements(ptypes, ntypes, petags, petags_n, netags_nn, pntags, &
      pntags_n, nntags_nn, int(dim, c_int), -1_c_int, ierr)
    allocate(tri_tags(0))
    if (ierr /= 0) return
    if (ntypes > 0) then
      call c_f_pointer(ptypes, types, [ntypes])
      call c_f_pointer(petags, etags, [netags_nn])
      call c_f_pointer(petags_n, etags_n, [netags_nn])
      call c_f_pointer(pntags, ntags, [nntags_nn])
      call c_f_pointer(pntags_n, ntags_n, [nntags_nn])
      do k = 1, int(ntypes)
        if (types(k) == want .and. ntags_n(k) > 0) then
          call c_f_pointer(ntags(k), nodes, [ntags_n(k)])
          part = int(nodes, i64)
          tri_tags = [tri_tags, part]
        end if
        call free_if(etags(k))
        call free_if(ntags(k))
      end do
    end if
    call free_if(ptypes)
    call free_if(petags)
    call free_if(petags_n)
    call free_if(pntags)
    call free_if(pntags_n)
  end subroutine get_elements

  subroutine free_if(p)
    type(c_ptr), intent(in) :: p
    if (c_associated(p)) call gmshFree(p)
  end subroutine free_if
end module gmsh_mesh_m
