!> gmsh in memory: meshes a .geo script with linear triangles through gmsh's C API
!! (gmshc.h, bound here with ISO_C_BINDING), for &body shape = 'geo'. The calls are those of
!! tools/mesh_body.py, in its order: initialize (without the user's gmsh configuration files),
!! General.Terminal 0, the parser numbers, merge (not open, which would reset them),
!! Mesh.ElementOrder 1, generate 2, the nodes and the 2D elements, finalize. Nothing is
!! written, and no shell or process is started. Compiled when the build finds gmsh
!! (MFCD_GMSH, cmake/MfcdFindGmsh.cmake); gmsh_mesh_stub_m.f90 is this module without it.
!!
!! gmsh is C++: while it runs, floating-point traps are off (a Debug build traps invalid
!! operations, which gmsh's own arithmetic may raise and handle) and mfcd's floating-point
!! state and OpenMP thread count are restored afterwards. HOME is /dev/null meanwhile: the
!! PyPI library's GUI toolkit (FLTK) writes ~/.fltk/fltk.org/fltk.prefs when gmsh starts,
!! and mfcd creates no file outside its output (with HOME a device, that write fails
!! quietly; gmsh reads no configuration file from HOME anyway).
module gmsh_mesh_m
  use, intrinsic :: iso_c_binding, only: c_int, c_double, c_size_t, c_char, c_ptr, &
    c_null_ptr, c_null_char, c_associated, c_f_pointer
  use, intrinsic :: ieee_exceptions, only: ieee_status_type, ieee_get_status, &
    ieee_set_status, ieee_set_halting_mode, ieee_all
  use omp_lib, only: omp_get_max_threads, omp_set_num_threads
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  implicit none
  private
  public :: gmsh_built_in, gmsh_version, gmsh_mesh_geo

  !> This build meshes .geo files (the stub says .false.).
  logical, parameter :: gmsh_built_in = .true.
  !> gmsh's element type of the 3-node triangle.
  integer(c_int), parameter :: triangle_3 = 2

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
    subroutine gmshParserSetNumber(name, value, value_n, ierr) &
      bind(C, name='gmshParserSetNumber')
      import :: c_char, c_double, c_size_t, c_int
      character(kind=c_char), intent(in) :: name(*)
      real(c_double), intent(in) :: value(*)
      integer(c_size_t), value :: value_n
      integer(c_int), intent(out) :: ierr
    end subroutine gmshParserSetNumber
    subroutine gmshMerge(fileName, ierr) bind(C, name='gmshMerge')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: fileName(*)
      integer(c_int), intent(out) :: ierr
    end subroutine gmshMerge
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
    integer(c_int) function c_setenv(name, value, overwrite) bind(C, name='setenv')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value :: overwrite
    end function c_setenv
    integer(c_int) function c_unsetenv(name) bind(C, name='unsetenv')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: name(*)
    end function c_unsetenv
  end interface

  !> What enter saved for leave: the floating-point state, the thread count and HOME.
  type :: saved_t
    type(ieee_status_type) :: fp
    integer :: threads = 0
    logical :: has_home = .false.
    character(len=:), allocatable :: home
  end type saved_t

contains

  !> gmsh's version (its option General.Version), e.g. '4.15.2'; '' when it cannot say.
  function gmsh_version() result(v)
    character(len=:), allocatable :: v
    type(saved_t) :: saved
    integer(c_int) :: ierr
    call enter(saved)
    call gmshInitialize(0_c_int, c_null_ptr, 0_c_int, 0_c_int, ierr)
    v = ''
    if (ierr == 0) then
      call option_string('General.Version', v)
      call gmshFinalize(ierr)
    end if
    call leave(saved)
  end function gmsh_version

  !> Mesh the .geo at path with linear triangles, the parser numbers names(k) = values(k)
  !! set before it is read: the node tags tags(n), their coordinates xyz(3*n) and the node
  !! tags of the 3-node triangles of the 2D mesh, tri_tags(3*ne), as gmsh returns them
  !! (mesh_cells_m makes the body of them); version is gmsh's. err holds gmsh's own message
  !! (e.g. "'x.geo', line 2: syntax error (;)") when it fails.
  subroutine gmsh_mesh_geo(path, names, values, tags, xyz, tri_tags, version, err)
    character(len=*), intent(in) :: path, names(:)
    real(wp), intent(in) :: values(:)
    integer(i64), allocatable, intent(out) :: tags(:), tri_tags(:)
    real(wp), allocatable, intent(out) :: xyz(:)
    character(len=:), allocatable, intent(out) :: version
    type(error_t), allocatable, intent(inout) :: err
    type(saved_t) :: saved
    integer(c_int) :: ierr, ierr2
    integer :: k
    character(len=:), allocatable :: msg
    version = ''
    call enter(saved)
    call gmshInitialize(0_c_int, c_null_ptr, 0_c_int, 0_c_int, ierr)
    if (ierr /= 0) then
      call leave(saved)
      call set_error(err, 'gmsh failed to initialise')
      return
    end if
    call gmshOptionSetNumber('General.Terminal'//c_null_char, 0.0_c_double, ierr)
    call option_string('General.Version', version)
    do k = 1, size(names)
      if (ierr /= 0) exit
      call gmshParserSetNumber(trim(names(k))//c_null_char, [real(values(k), c_double)], &
        1_c_size_t, ierr)
    end do
    if (ierr == 0) call gmshMerge(trim(path)//c_null_char, ierr)
    if (ierr == 0) call gmshOptionSetNumber('Mesh.ElementOrder'//c_null_char, 1.0_c_double, &
      ierr)
    if (ierr == 0) call gmshModelMeshGenerate(2_c_int, ierr)
    if (ierr == 0) call get_nodes(tags, xyz, ierr)
    if (ierr == 0) call get_triangles(tri_tags, ierr)
    if (ierr /= 0) then
      msg = last_error()
      if (len(msg) == 0) msg = 'gmsh failed (no message)'
      call set_error(err, msg)
    end if
    call gmshFinalize(ierr2)
    call leave(saved)
  end subroutine gmsh_mesh_geo

  !> Before gmsh: traps off, HOME /dev/null (the module's header says why); what they were
  !! and the thread count are kept in saved.
  subroutine enter(saved)
    type(saved_t), intent(out) :: saved
    integer :: n, st
    integer(c_int) :: rc
    call ieee_get_status(saved%fp)
    call ieee_set_halting_mode(ieee_all, .false.)
    saved%threads = omp_get_max_threads()
    call get_environment_variable('HOME', length=n, status=st)
    saved%has_home = st == 0
    if (saved%has_home) then
      allocate(character(len=n) :: saved%home)
      call get_environment_variable('HOME', saved%home)
    end if
    rc = c_setenv('HOME'//c_null_char, '/dev/null'//c_null_char, 1_c_int)
  end subroutine enter

  !> After gmsh: mfcd's floating-point state (flags, traps, rounding), thread count and HOME
  !! back.
  subroutine leave(saved)
    type(saved_t), intent(in) :: saved
    integer(c_int) :: rc
    if (saved%has_home) then
      rc = c_setenv('HOME'//c_null_char, saved%home//c_null_char, 1_c_int)
    else
      rc = c_unsetenv('HOME'//c_null_char)
    end if
    call ieee_set_status(saved%fp)
    if (omp_get_max_threads() /= saved%threads) call omp_set_num_threads(saved%threads)
  end subroutine leave

  subroutine option_string(name, v)
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(inout) :: v
    type(c_ptr) :: p
    integer(c_int) :: ierr
    call gmshOptionGetString(name//c_null_char, p, ierr)
    if (ierr == 0) v = c_text(p)
  end subroutine option_string

  !> gmsh's last error message ('' if none).
  function last_error() result(msg)
    character(len=:), allocatable :: msg
    type(c_ptr) :: p
    integer(c_int) :: ierr
    msg = ''
    call gmshLoggerGetLastError(p, ierr)
    if (ierr == 0) msg = c_text(p)
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

  !> The node tags of the 3-node triangles among the 2D elements (getElements(2)), in the
  !! order gmsh gives them.
  subroutine get_triangles(tri_tags, ierr)
    integer(i64), allocatable, intent(out) :: tri_tags(:)
    integer(c_int), intent(out) :: ierr
    type(c_ptr) :: ptypes, petags, petags_n, pntags, pntags_n
    integer(c_size_t) :: ntypes, netags_nn, nntags_nn
    integer(c_int), pointer :: types(:)
    type(c_ptr), pointer :: etags(:), ntags(:)
    integer(c_size_t), pointer :: etags_n(:), ntags_n(:), nodes(:)
    integer(i64), allocatable :: part(:)
    integer :: k
    call gmshModelMeshGetElements(ptypes, ntypes, petags, petags_n, netags_nn, pntags, &
      pntags_n, nntags_nn, 2_c_int, -1_c_int, ierr)
    allocate(tri_tags(0))
    if (ierr /= 0) return
    if (ntypes > 0) then
      call c_f_pointer(ptypes, types, [ntypes])
      call c_f_pointer(petags, etags, [netags_nn])
      call c_f_pointer(petags_n, etags_n, [netags_nn])
      call c_f_pointer(pntags, ntags, [nntags_nn])
      call c_f_pointer(pntags_n, ntags_n, [nntags_nn])
      do k = 1, int(ntypes)
        if (types(k) == triangle_3 .and. ntags_n(k) > 0) then
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
  end subroutine get_triangles

  subroutine free_if(p)
    type(c_ptr), intent(in) :: p
    if (c_associated(p)) call gmshFree(p)
  end subroutine free_if
end module gmsh_mesh_m
