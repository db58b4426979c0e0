!> gmsh_mesh_m of a build without gmsh (MFCD_GMSH off or gmsh not found): the same
!! interface as gmsh_mesh_m.f90, and meshing a .geo is an error that says how to get gmsh.
module gmsh_mesh_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  implicit none
  private
  public :: gmsh_built_in, gmsh_version, gmsh_mesh_geo

  !> This build does not mesh .geo files.
  logical, parameter :: gmsh_built_in = .false.

contains

  !> '' (no gmsh).
  function gmsh_version() result(v)
    character(len=:), allocatable :: v
    v = ''
  end function gmsh_version

  !> Always an error: this mfcd was built without gmsh.
  subroutine gmsh_mesh_geo(path, names, values, tags, xyz, tri_tags, version, err)
    character(len=*), intent(in) :: path, names(:)
    real(wp), intent(in) :: values(:)
    integer(i64), allocatable, intent(out) :: tags(:), tri_tags(:)
    real(wp), allocatable, intent(out) :: xyz(:)
    character(len=:), allocatable, intent(out) :: version
    type(error_t), allocatable, intent(inout) :: err
    allocate(tags(0), tri_tags(0), xyz(0))
    version = ''
    ! the arguments are those of gmsh_mesh_m.f90; refusing needs only the path
    if (size(names) /= size(values)) continue
    call set_error(err, "cannot mesh '"//trim(path)//"': this mfcd was built without "// &
      "gmsh: run `bash tools/setup.sh "// &
      "--gmsh` and rebuild (bash tools/build.sh), or mesh with tools/mesh_body.py and use "// &
      "shape = 'file'")
  end subroutine gmsh_mesh_geo
end module gmsh_mesh_m
