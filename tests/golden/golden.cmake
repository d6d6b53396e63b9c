# Runs one command and compares what it prints (stdout, then stderr) with a committed reference.
#   -DCMD="<exe>|arg|arg..."   the command, arguments separated by "|"
#   -DREF=<file>               the reference output (tests/golden/ref/<name>.txt)
#   -DACTUAL=<file>            where the normalised output of this run is written (for diffing)
#   -DWORK_DIR=<dir>           removed and re-created before the run; written as <work> in the output
#   -DEXPECT_RC=<n>            required exit code (default 0)
# Figures are compared at the precision the command prints them. Only what cannot be reproduced is
# masked: wall-clock figures (a number followed by a time unit, or in a column whose header names a
# time) and the build-specific paths. Set the environment variable SWBA_UPDATE_GOLDEN=1 to rewrite the
# reference instead (scripts/update-golden.sh); a commit that changes a reference must say why.
if(NOT DEFINED EXPECT_RC)
  set(EXPECT_RC 0)
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
string(REPLACE "|" ";" CMD "${CMD}")
execute_process(COMMAND ${CMD} WORKING_DIRECTORY "${WORK_DIR}"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}\n--- stderr ---\n${err}")
if(NOT "${rc}" STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "exit code '${rc}', expected ${EXPECT_RC}; output:\n${all}")
endif()

include(${CMAKE_CURRENT_LIST_DIR}/mask.cmake)
swba_golden_mask(all "${WORK_DIR}")
file(WRITE "${ACTUAL}" "${all}")

if("$ENV{SWBA_UPDATE_GOLDEN}" STREQUAL "1")
  file(WRITE "${REF}" "${all}")
  message(STATUS "updated ${REF}")
  return()
endif()
if(NOT EXISTS "${REF}")
  message(FATAL_ERROR "no reference ${REF}; run scripts/update-golden.sh to create it")
endif()
file(READ "${REF}" ref)
if(NOT "${all}" STREQUAL "${ref}")
  find_program(DIFF diff)
  if(DIFF)
    execute_process(COMMAND ${DIFF} -u "${REF}" "${ACTUAL}" OUTPUT_VARIABLE d)
  endif()
  message(FATAL_ERROR "output differs from ${REF} (actual: ${ACTUAL}):\n${d}")
endif()
