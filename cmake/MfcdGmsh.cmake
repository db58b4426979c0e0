# MFCD_GMSH: mesh .geo bodies in memory through gmsh's C API (&body shape = 'geo',
# src/setup/gmsh_mesh_m.f90), or not (src/setup/gmsh_mesh_stub_m.f90, which refuses such a body with a
# message saying how to get gmsh).
#
#   AUTO (default)  on when gmsh's library and its C header gmshc.h are found and a program
#                   links against them; off otherwise, and the build is what it was before
#   ON              gmsh is required: configuring stops when it is not found or does not link
#   OFF             never
#
# Where it looks (cmake/MfcdFindGmsh.cmake): MFCD_GMSH_ROOT, gmsh_ROOT, CMAKE_PREFIX_PATH, the
# project's .venv (where `bash tools/setup.sh --gmsh` installs the PyPI wheel) and the system.
# Sets MFCD_GMSH_ENABLED (TRUE/FALSE), and with it the target mfcd::gmsh,
# MFCD_GMSH_LIBRARY_DIR (the program's run path to the library, build and install) and
# MFCD_GMSH_PREFIX (the directory above it, which the package test gives its consumer).
set(MFCD_GMSH AUTO CACHE STRING
  "Mesh &body shape = 'geo' bodies with gmsh's API: AUTO (when found), ON (required) or OFF")
set_property(CACHE MFCD_GMSH PROPERTY STRINGS AUTO ON OFF)
set(MFCD_GMSH_ROOT "" CACHE PATH "Prefix of a gmsh install (lib/libgmsh.so*, include/gmshc.h)")
string(TOUPPER "${MFCD_GMSH}" _mfcd_gmsh_mode)
if(NOT _mfcd_gmsh_mode MATCHES "^(AUTO|ON|OFF|TRUE|FALSE|YES|NO|1|0)$")
  message(FATAL_ERROR "MFCD_GMSH = '${MFCD_GMSH}': use AUTO, ON or OFF")
endif()
if(_mfcd_gmsh_mode MATCHES "^(TRUE|YES|1)$")
  set(_mfcd_gmsh_mode ON)
elseif(_mfcd_gmsh_mode MATCHES "^(FALSE|NO|0)$")
  set(_mfcd_gmsh_mode OFF)
endif()

set(MFCD_GMSH_ENABLED FALSE)
if(NOT _mfcd_gmsh_mode STREQUAL "OFF")
  include(MfcdFindGmsh)
  mfcd_find_gmsh(HINTS "${PROJECT_SOURCE_DIR}/.venv")
  set(_mfcd_gmsh_why "")
  if(NOT MFCD_GMSH_FOUND)
    set(_mfcd_gmsh_why "gmsh's library (libgmsh.so*) was not found")
  elseif(NOT MFCD_GMSH_INCLUDE_DIR)
    set(_mfcd_gmsh_why "gmsh's C API header gmshc.h was not found (${MFCD_GMSH_LIBRARY})")
  elseif(NOT MFCD_GMSH_VERSION MATCHES "^4\\.")
    set(_mfcd_gmsh_why "gmsh ${MFCD_GMSH_VERSION} is not 4.x, whose C API mfcd binds")
  elseif(NOT MFCD_GMSH_LINKED STREQUAL MFCD_GMSH_LIBRARY)
    # a program that initialises and finalises gmsh must link: the wheel's library needs
    # X11/OpenGL libraries (tools/setup.sh --gmsh installs them). Only success is cached,
    # so a later configure tries again.
    set(_dir "${CMAKE_BINARY_DIR}/CMakeFiles/mfcd_gmsh_check")
    file(WRITE "${_dir}/gmsh_check.f90" [=[
program gmsh_check
  use, intrinsic :: iso_c_binding, only: c_int, c_ptr, c_null_ptr
  implicit none
  interface
    subroutine gmshInitialize(argc, argv, readConfigFiles, run, ierr) &
      bind(C, name="gmshInitialize")
      import :: c_int, c_ptr
      integer(c_int), value :: argc
      type(c_ptr), value :: argv
      integer(c_int), value :: readConfigFiles, run
      integer(c_int) :: ierr
    end subroutine gmshInitialize
    subroutine gmshFinalize(ierr) bind(C, name="gmshFinalize")
      import :: c_int
      integer(c_int) :: ierr
    end subroutine gmshFinalize
  end interface
  integer(c_int) :: ierr
  call gmshInitialize(0_c_int, c_null_ptr, 0_c_int, 0_c_int, ierr)
  call gmshFinalize(ierr)
end program gmsh_check
]=])
    try_compile(_mfcd_gmsh_links "${_dir}/build" "${_dir}/gmsh_check.f90"
      LINK_LIBRARIES "${MFCD_GMSH_LIBRARY}" OUTPUT_VARIABLE _mfcd_gmsh_log)
    if(_mfcd_gmsh_links)
      set(MFCD_GMSH_LINKED "${MFCD_GMSH_LIBRARY}" CACHE INTERNAL "gmsh library that linked")
    else()
      string(REGEX MATCHALL "[^\n]*(not found|undefined reference)[^\n]*" _lines
        "${_mfcd_gmsh_log}")
      list(SUBLIST _lines 0 3 _lines)
      string(REPLACE ";" "\n  " _lines "${_lines}")
      set(_mfcd_gmsh_why "a program does not link against ${MFCD_GMSH_LIBRARY} (missing "
        "libraries it needs? bash tools/setup.sh --gmsh installs them):\n  ${_lines}")
      string(CONCAT _mfcd_gmsh_why ${_mfcd_gmsh_why})
    endif()
    unset(_mfcd_gmsh_links CACHE)
  endif()
  if(_mfcd_gmsh_why STREQUAL "")
    set(MFCD_GMSH_ENABLED TRUE)
    get_filename_component(MFCD_GMSH_PREFIX "${MFCD_GMSH_LIBRARY_DIR}" DIRECTORY)
    message(STATUS "mfcd: gmsh ${MFCD_GMSH_VERSION} (${MFCD_GMSH_LIBRARY}): &body shape = "
      "'geo' meshes .geo files in memory")
  elseif(_mfcd_gmsh_mode STREQUAL "ON")
    message(FATAL_ERROR "MFCD_GMSH = ON, but ${_mfcd_gmsh_why}. Run `bash tools/setup.sh "
      "--gmsh` (gmsh into .venv), give gmsh's prefix in MFCD_GMSH_ROOT, or set MFCD_GMSH "
      "to AUTO or OFF.")
  else()
    message(STATUS "mfcd: without gmsh (MFCD_GMSH = AUTO: ${_mfcd_gmsh_why}): &body shape = "
      "'geo' is refused; `bash tools/setup.sh --gmsh` and a new configure turn it on")
  endif()
else()
  message(STATUS "mfcd: without gmsh (MFCD_GMSH = OFF): &body shape = 'geo' is refused")
endif()
