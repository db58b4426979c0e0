# Writes version_m.f90 from version_m.f90.in with the current git commit, at build time, and
# only touches the file when the commit changed (so a rebuild after a commit records it).
# Variables: SRC (template), DST (output), VERSION, SOURCE_DIR, GIT.
set(MFCD_GIT_COMMIT "unknown")
if(GIT AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT}" describe --always --dirty --abbrev=12
    WORKING_DIRECTORY "${SOURCE_DIR}" OUTPUT_VARIABLE _commit
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE _rc)
  if(_rc EQUAL 0 AND _commit)
    set(MFCD_GIT_COMMIT "${_commit}")
  endif()
endif()
set(PROJECT_VERSION "${VERSION}")
configure_file("${SRC}" "${DST}.tmp" @ONLY)
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${DST}.tmp" "${DST}")
