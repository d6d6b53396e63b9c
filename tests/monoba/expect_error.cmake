# Runs `swba monoba ...` and requires a failure exit code and a one-line reason on stderr.
#   -DCMD="<swba>|arg|arg..."   the command, arguments separated by "|"
#   -DREGEX=<regex>             must match stderr
string(REPLACE "|" ";" CMD "${CMD}")
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc MATCHES "^[1-9][0-9]*$")
  message(FATAL_ERROR "exit code '${rc}', expected a non-zero exit code; stdout:\n${out}\nstderr:\n${err}")
endif()
if(NOT "${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "stderr does not match '${REGEX}':\n${err}")
endif()
string(STRIP "${err}" err_stripped)
if(err_stripped MATCHES "\n")
  message(FATAL_ERROR "the reason is not one line:\n${err}")
endif()
message(STATUS "exit code ${rc}: ${err_stripped}")
