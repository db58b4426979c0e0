# MfcdPfunit.cmake: register mfcd's pFUnit 4 suites (tests/unit/test_<x>.pf) with CTest.
#
# With pFUnit installed (found by find_package(PFUNIT QUIET), e.g. through
# -DCMAKE_PREFIX_PATH=<pfunit prefix>) each suite goes through pFUnit's add_pfunit_ctest.
# Without it, the bundled translator tests/pfunit_lite/pf2f90.py turns the suite into a plain
# Fortran test program linked against tests/pfunit_lite/funit.f90 (see the README there).
#
# Usage, after project(... LANGUAGES Fortran) and enable_testing():
#
#   list(APPEND CMAKE_MODULE_PATH "${PROJECT_SOURCE_DIR}/cmake")
#   include(MfcdPfunit)
#   mfcd_add_pf_test(NAME test_kernels SOURCE test_kernels.pf LINK mfcd_core)
#   mfcd_add_pf_selfcheck()
#
# SOURCE is relative to the calling directory (or absolute); LINK lists the libraries the suite
# uses, whose Fortran module directories must be on their PUBLIC include path. Executables go to
# ${CMAKE_BINARY_DIR}/tests; each test target gets its own module directory.
#
# Cache option MFCD_PFUNIT_LITE (OFF): use the translator even when pFUnit is installed.

include_guard(GLOBAL)

option(MFCD_PFUNIT_LITE "Use the bundled pfunit_lite translator even when pFUnit is found" OFF)

if(NOT MFCD_PFUNIT_LITE)
  find_package(PFUNIT QUIET)
endif()

get_filename_component(_mfcd_pfunit_lite_dir "${CMAKE_CURRENT_LIST_DIR}/../tests/pfunit_lite"
  ABSOLUTE)
set_property(GLOBAL PROPERTY MFCD_PFUNIT_LITE_DIR "${_mfcd_pfunit_lite_dir}")

if(PFUNIT_FOUND AND NOT MFCD_PFUNIT_LITE)
  set_property(GLOBAL PROPERTY MFCD_PF_MODE pfunit)
  message(STATUS "Unit tests: pFUnit ${PFUNIT_VERSION}")
else()
  find_package(Python3 COMPONENTS Interpreter REQUIRED)
  set_property(GLOBAL PROPERTY MFCD_PF_MODE lite)
  set_property(GLOBAL PROPERTY MFCD_PF_PYTHON "${Python3_EXECUTABLE}")
  message(STATUS "Unit tests: pFUnit not used, translating .pf suites with pfunit_lite")
endif()

# The static library mfcd_funit (pfunit_lite's `funit` module), created on first use.
function(_mfcd_pf_funit_library)
  if(TARGET mfcd_funit)
    return()
  endif()
  get_property(lite_dir GLOBAL PROPERTY MFCD_PFUNIT_LITE_DIR)
  set(mod_dir "${CMAKE_BINARY_DIR}/pfunit_lite/mod")
  add_library(mfcd_funit STATIC "${lite_dir}/funit.f90")
  set_target_properties(mfcd_funit PROPERTIES
    Fortran_MODULE_DIRECTORY "${mod_dir}"
    ARCHIVE_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/pfunit_lite")
  target_include_directories(mfcd_funit PUBLIC "$<BUILD_INTERFACE:${mod_dir}>")
  if(CMAKE_Fortran_COMPILER_ID STREQUAL "GNU")
    # funit.f90 uses assumed-rank arrays (Fortran 2018); this overrides a global -std=f2008.
    target_compile_options(mfcd_funit PRIVATE -std=f2018)
  endif()
endfunction()

# mfcd_add_pf_test(NAME <name> SOURCE <file.pf> [LINK <targets...>])
# Defines the executable target <name> and the CTest test <name>.
function(mfcd_add_pf_test)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "NAME;SOURCE" "LINK")
  if(arg_UNPARSED_ARGUMENTS OR NOT arg_NAME OR NOT arg_SOURCE)
    message(FATAL_ERROR
      "usage: mfcd_add_pf_test(NAME <name> SOURCE <file.pf> [LINK <targets...>])")
  endif()
  get_filename_component(source "${arg_SOURCE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  get_property(mode GLOBAL PROPERTY MFCD_PF_MODE)

  if(mode STREQUAL "pfunit")
    add_pfunit_ctest(${arg_NAME} TEST_SOURCES "${arg_SOURCE}" LINK_LIBRARIES ${arg_LINK})
  else()
    _mfcd_pf_funit_library()
    get_property(lite_dir GLOBAL PROPERTY MFCD_PFUNIT_LITE_DIR)
    get_property(python GLOBAL PROPERTY MFCD_PF_PYTHON)
    set(generated "${CMAKE_CURRENT_BINARY_DIR}/${arg_NAME}.f90")
    add_custom_command(
      OUTPUT "${generated}"
      COMMAND "${python}" "${lite_dir}/pf2f90.py" "${source}" -o "${generated}"
      DEPENDS "${source}" "${lite_dir}/pf2f90.py"
      COMMENT "pfunit_lite: translating ${arg_SOURCE}"
      VERBATIM)
    # The output carries #line and #ifdef directives.
    set_source_files_properties("${generated}" PROPERTIES Fortran_PREPROCESS ON)
    add_executable(${arg_NAME} "${generated}")
    target_link_libraries(${arg_NAME} PRIVATE mfcd_funit ${arg_LINK})
    set(mod_dir "${CMAKE_CURRENT_BINARY_DIR}/mod/${arg_NAME}")
    set_target_properties(${arg_NAME} PROPERTIES Fortran_MODULE_DIRECTORY "${mod_dir}")
    target_include_directories(${arg_NAME} PRIVATE "${mod_dir}")
    add_test(NAME ${arg_NAME} COMMAND ${arg_NAME} WORKING_DIRECTORY "${CMAKE_CURRENT_BINARY_DIR}")
  endif()
  set_target_properties(${arg_NAME} PROPERTIES
    RUNTIME_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/tests")
  # A suite's own code (its fixtures, brute-force references and assertions) at -O1 in an
  # optimized build, the library it tests as that build has it: gfortran's -O3 took 29 s
  # on the largest suite, -O1 11 s (test_decomposition, AMD EPYC guest, 2026-12-08), and the
  # suites' compilation was near half of the Release build's CPU time; the last -O wins
  if(CMAKE_Fortran_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${arg_NAME} PRIVATE
      "$<$<OR:$<CONFIG:Release>,$<CONFIG:RelWithDebInfo>>:-O1>")
  endif()
endfunction()

# mfcd_add_pf_selfcheck(): in translator mode only, register the deliberately failing suite
# tests/pfunit_lite/selfcheck/test_must_fail.pf twice: as pfunit_lite_selfcheck with WILL_FAIL
# (a failed assertion must fail the run) and as pfunit_lite_selfcheck_report, which checks the
# report names the failed test and ends with the right counts.
function(mfcd_add_pf_selfcheck)
  get_property(mode GLOBAL PROPERTY MFCD_PF_MODE)
  if(NOT mode STREQUAL "lite")
    return()
  endif()
  get_property(lite_dir GLOBAL PROPERTY MFCD_PFUNIT_LITE_DIR)
  mfcd_add_pf_test(NAME pfunit_lite_selfcheck SOURCE "${lite_dir}/selfcheck/test_must_fail.pf")
  set_tests_properties(pfunit_lite_selfcheck PROPERTIES WILL_FAIL TRUE)
  add_test(NAME pfunit_lite_selfcheck_report COMMAND pfunit_lite_selfcheck)
  set_tests_properties(pfunit_lite_selfcheck_report PROPERTIES PASS_REGULAR_EXPRESSION
    "\\[ FAIL \\] test_must_fail\\.test_fails.*\n1 passed, 1 failed, 0 skipped\n")
endfunction()
