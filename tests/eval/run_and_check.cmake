# Runs one swba command and checks its exit code and output (used by tests.cmake).
#   -DCMD="<swba>|arg|arg..."    the command, arguments separated by "|"
#   -DEXPECT_RC=<n>              required exit code (a crash never matches a number)
#   -DREGEX=<regex>              must match stdout+stderr (optional)
#   -DJSON_FILE=<path> -DJSON_KEY=<key> -DEXPECTED=<decimal> -DREL_TOL_INV=<n>
#                                optional: |json[key] − EXPECTED| ≤ EXPECTED / REL_TOL_INV, compared in
#                                fixed point (15 decimals) since CMake has integer arithmetic only.
#   -DCLEAN_DIR=<dir>            optional: removed before running
if(CLEAN_DIR)
  file(REMOVE_RECURSE "${CLEAN_DIR}")
endif()
string(REPLACE "|" ";" CMD "${CMD}")
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(all "${out}${err}")
if(NOT "${rc}" STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "exit code '${rc}', expected ${EXPECT_RC}; output:\n${all}")
endif()
if(DEFINED REGEX AND NOT "${all}" MATCHES "${REGEX}")
  message(FATAL_ERROR "output does not match '${REGEX}':\n${all}")
endif()

# "0.0160637612904" → integer in units of 1e-15.
function(to_fixed15 text outvar)
  if(NOT text MATCHES "^([0-9]+)\\.([0-9]*)$")
    message(FATAL_ERROR "cannot compare '${text}' (expected a plain decimal)")
  endif()
  set(int_part "${CMAKE_MATCH_1}")
  set(frac "${CMAKE_MATCH_2}000000000000000")
  string(SUBSTRING "${frac}" 0 15 frac)
  string(REGEX REPLACE "^0+([0-9])" "\\1" frac "${frac}")
  math(EXPR v "${int_part} * 1000000000000000 + ${frac}")
  set(${outvar} ${v} PARENT_SCOPE)
endfunction()

if(JSON_FILE)
  file(READ "${JSON_FILE}" json)
  string(JSON value GET "${json}" "${JSON_KEY}")
  to_fixed15("${value}" got)
  to_fixed15("${EXPECTED}" want)
  math(EXPR diff "${got} - ${want}")
  if(diff LESS 0)
    math(EXPR diff "0 - ${diff}")
  endif()
  math(EXPR tol "${want} / ${REL_TOL_INV}")
  if(diff GREATER tol)
    message(FATAL_ERROR "${JSON_KEY} = ${value}, expected ${EXPECTED} within 1/${REL_TOL_INV} relative")
  endif()
  message(STATUS "${JSON_KEY} = ${value} (expected ${EXPECTED}, |diff| = ${diff}e-15 <= ${tol}e-15)")
endif()
