!> gmsh_mesh_m of a build without gmsh (MFCD_GMSH off or gmsh not found): the same
!! interface as gmsh_mesh_m.f90, and meshing a model is an error that says how to get gmsh.
!! The deck's script is still read and checked (geo_script_m) before this refuses it.
module gmsh_mesh_m
  use kinds_m, only: wp, i64
  use errors_m, only: error_t, set_error
  use confine_m, only: confine_limits_t
  use geo_script_m, only: geo_model_t
  implicit none
  private
  public :: gmsh_built_in, gmsh_version, gmsh_mesh_model

  !> This build does not mesh .geo files.
  logical, parameter :: gmsh_built_in = .false.

contains

  !> '' (no gmsh).
  function gmsh_version() result(v)
    character(len=:), allocatable :: v
    v = ''
  end function gmsh_version

  !> Always an error: this mfcd was built without gmsh.
  subroutine gmsh_mesh_model(model, dim, limits, tags, xyz, tri_tags, version, err)
    type(geo_model_t), target, intent(in) :: model
    integer, intent(in) :: dim
    type(confine_limits_t), intent(in) :: limits
    integer(i64), allocatable, intent(out) :: tags(:), tri_tags(:)
    real(wp), allocatable, intent(out) :: xyz(:)
    character(len=:), allocatable, intent(out) :: version
    type(error_t), allocatable, intent(inout) :: err
    allocate(tags(0), tri_tags(0), xyz(0))
    version = ''
    ! the arguments are those of gmsh_mesh_m.f90; refusing needs none of them
    if (model%nops < 0 .or. dim < 0 .or. limits%seconds < 0.0_wp) continue
    call set_error(err, "this mfcd was built without gmsh: run `bash tools/setup.sh "// &
      "--gmsh` and rebuild (bash tools/build.sh), or mesh the script elsewhere and give "// &
      "the mesh as shape = 'file'")
  end subroutine gmsh_mesh_model
end module gmsh_mesh_m
