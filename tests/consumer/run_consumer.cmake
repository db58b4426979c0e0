# The test package_consumer (tests/CMakeLists.txt): install the current build, move the
# prefix (the install must not depend on where it was put), check that no installed CMake
# file names the source or build tree, then configure, build and run tests/consumer against
# the moved prefix, and run the installed program. Run with cmake -P and:
#   BUILD_DIR       the mfcd build tree to install
#   WORK_DIR        scratch directory (emptied first): prefix and consumer build go there
#   CONSUMER_DIR    tests/consumer
#   SOURCE_DIR      mfcd's source tree (must not appear in the installed files)
#   CONFIG          build type (Release, Debug)
#   GENERATOR, MAKE_PROGRAM, Fortran_COMPILER   the same as mfcd's build
#   VERSION         mfcd's version, as `mfcd --version` must print it
#   GMSH_ROOT       gmsh's prefix when mfcd is built with gmsh (empty otherwise): the consumer
#                   links libgmsh through mfcd's config, which finds it there (MFCD_GMSH_ROOT)
cmake_minimum_required(VERSION 3.20)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "package_consumer: ${what} failed (${rc}):\n  ${cmd}\n${out}")
  endif()
  set(run_out "${out}" PARENT_SCOPE)
endfunction()

set(staged ${WORK_DIR}/staged)
set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${staged} --config ${CONFIG})
file(RENAME ${staged} ${prefix})

file(GLOB_RECURSE cmake_files ${prefix}/*.cmake)
if(NOT cmake_files)
  message(FATAL_ERROR "package_consumer: no CMake package files installed under ${prefix}")
endif()
foreach(f IN LISTS cmake_files)
  file(READ ${f} text)
  foreach(tree ${SOURCE_DIR} ${BUILD_DIR} ${staged})
    string(FIND "${text}" "${tree}" at)
    if(at GREATER -1)
      message(FATAL_ERROR "package_consumer: ${f} names '${tree}': the install is not relocatable")
    endif()
  endforeach()
endforeach()

set(gmsh_hint "")
if(GMSH_ROOT)
  set(gmsh_hint "-DMFCD_GMSH_ROOT=${GMSH_ROOT}")
endif()
run("configuring the consumer" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/build
  -G ${GENERATOR} -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM} -DCMAKE_Fortran_COMPILER=${Fortran_COMPILER}
  -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_PREFIX_PATH=${prefix} ${gmsh_hint})
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build --config ${CONFIG})
run("running the consumer" ${WORK_DIR}/build/mfcd_consumer)
message("${run_out}")
if(NOT run_out MATCHES "mfcd_consumer: ok")
  message(FATAL_ERROR "package_consumer: the consumer did not report ok")
endif()

run("running the installed program" ${prefix}/bin/mfcd --version)
message("${run_out}")
if(NOT run_out MATCHES "^mfcd ${VERSION} ")
  message(FATAL_ERROR "package_consumer: '${prefix}/bin/mfcd --version' does not say mfcd ${VERSION}")
endif()
message("package_consumer: ok (installed, moved, found, built and run)")
