# The floors hold (doc/design.md): a module of a higher floor is not visible to a lower one.
# Compiles a probe that uses one module of each floor against the module directories of the
# floors below it (must fail: the module file cannot be found) and of its own floor (must
# compile). Run by the test floors_enforced:
#   cmake -DFC=<gfortran> -DMODULES=<build>/modules -DWORK=<dir> -P MfcdFloorsCheck.cmake
set(floors mfcd_numerics mfcd_solid mfcd_coupling mfcd_core)
# a module that lives on each floor
set(probe_mfcd_numerics rk_cloud_m)
set(probe_mfcd_solid solid_m)
set(probe_mfcd_coupling contact_pair_m)
set(probe_mfcd_core deck_m)
file(MAKE_DIRECTORY "${WORK}")
set(below "")
set(failures "")
foreach(floor IN LISTS floors)
  set(mod ${probe_${floor}})
  set(src "${WORK}/probe_${mod}.f90")
  file(WRITE "${src}" "program probe\n  use ${mod}\n  implicit none\nend program probe\n")
  if(below)
    execute_process(COMMAND ${FC} -fsyntax-only ${below} "${src}"
      WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(rc EQUAL 0)
      list(APPEND failures "${mod} (${floor}) compiles with only the floors below it")
    elseif(NOT out MATCHES "[Cc]annot open module file")
      list(APPEND failures "${mod} below ${floor}: not the missing module: ${out}")
    else()
      message(STATUS "${mod}: not visible below ${floor} (as it must be)")
    endif()
  endif()
  list(APPEND below "-I${MODULES}/${floor}")
  execute_process(COMMAND ${FC} -fsyntax-only ${below} "${src}"
    WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    list(APPEND failures "${mod} does not compile with its own floor ${floor}: ${out}")
  else()
    message(STATUS "${mod}: visible from ${floor}")
  endif()
endforeach()
if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "${text}")
endif()
