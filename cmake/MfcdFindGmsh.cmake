# MfcdFindGmsh.cmake: find gmsh's shared library for mfcd (&body shape = 'geo' meshes a .geo
# in memory through gmsh's C API, src/setup/gmsh_mesh_m.f90). Used by mfcd's build
# (cmake/MfcdGmsh.cmake) and, installed beside it, by mfcd's package config, so that a
# project using an mfcd built with gmsh links the same library.
#
#   include(MfcdFindGmsh)
#   mfcd_find_gmsh([HINTS <prefix>...])
#
# Looks under the prefixes MFCD_GMSH_ROOT (a CMake variable or an environment variable),
# gmsh_ROOT, the HINTS, CMAKE_PREFIX_PATH and the system's: lib/libgmsh.so, or, as the PyPI
# wheel ships it (`bash tools/setup.sh --gmsh` puts it in .venv), lib/libgmsh.so.<version>
# without the libgmsh.so link; and include/gmshc.h, the C API's header. Sets in the
# caller's scope:
#   MFCD_GMSH_FOUND        TRUE when the library was found (the header is not needed to link)
#   MFCD_GMSH_LIBRARY      the library file (a cache entry: -DMFCD_GMSH_LIBRARY=... picks one)
#   MFCD_GMSH_LIBRARY_DIR  its directory
#   MFCD_GMSH_INCLUDE_DIR  the directory of gmshc.h (cache; NOTFOUND if absent)
#   MFCD_GMSH_VERSION      the API version gmshc.h declares ('' without the header)
# and defines the imported target mfcd::gmsh (the library, linked by its full path).
# No path is written into any file here: the installed package finds gmsh again.
include_guard(GLOBAL)

function(mfcd_find_gmsh)
  cmake_parse_arguments(arg "" "" "HINTS" ${ARGN})
  set(roots ${MFCD_GMSH_ROOT} $ENV{MFCD_GMSH_ROOT} ${gmsh_ROOT} $ENV{gmsh_ROOT} ${arg_HINTS})
  find_path(MFCD_GMSH_INCLUDE_DIR gmshc.h HINTS ${roots} PATH_SUFFIXES include
    DOC "Directory of gmsh's C API header gmshc.h")
  find_library(MFCD_GMSH_LIBRARY NAMES gmsh HINTS ${roots} PATH_SUFFIXES lib lib64
    DOC "gmsh's shared library (libgmsh.so or libgmsh.so.<version>)")
  set(lib "${MFCD_GMSH_LIBRARY}")
  if(NOT lib)
    # the PyPI wheel: lib/libgmsh.so.4.15 and no libgmsh.so, which find_library looks for
    set(lib "")
    foreach(dir IN LISTS roots CMAKE_PREFIX_PATH)
      file(GLOB cands "${dir}/lib/libgmsh.so.[0-9]*" "${dir}/lib64/libgmsh.so.[0-9]*")
      if(cands)
        list(SORT cands)
        list(GET cands 0 lib)
        break()
      endif()
    endforeach()
  endif()
  set(version "")
  if(MFCD_GMSH_INCLUDE_DIR AND EXISTS "${MFCD_GMSH_INCLUDE_DIR}/gmshc.h")
    file(STRINGS "${MFCD_GMSH_INCLUDE_DIR}/gmshc.h" line
      REGEX "^#define GMSH_API_VERSION \"[0-9.]+\"" LIMIT_COUNT 1)
    if(line MATCHES "\"([0-9.]+)\"")
      set(version "${CMAKE_MATCH_1}")
    endif()
  endif()
  if(lib)
    get_filename_component(libdir "${lib}" DIRECTORY)
    if(NOT TARGET mfcd::gmsh)
      add_library(mfcd::gmsh SHARED IMPORTED)
      set_target_properties(mfcd::gmsh PROPERTIES IMPORTED_LOCATION "${lib}")
    endif()
    set(MFCD_GMSH_FOUND TRUE PARENT_SCOPE)
  else()
    set(libdir "")
    set(MFCD_GMSH_FOUND FALSE PARENT_SCOPE)
  endif()
  set(MFCD_GMSH_LIBRARY "${lib}" PARENT_SCOPE)
  set(MFCD_GMSH_LIBRARY_DIR "${libdir}" PARENT_SCOPE)
  set(MFCD_GMSH_VERSION "${version}" PARENT_SCOPE)
endfunction()
