# Declares the range noise of a real log per reading and runs swba on the copy: every reading is read
# with its own covariance (the run's input line counts them) and the run finishes.
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${TOOL} declare ${RAWLOG} ${OUT}/declared.rawlog --a 0.01 --b 0.05
                OUTPUT_VARIABLE log RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT log MATCHES "1534 readings declared with range σ = 0.01 \\+ 0.05 · r")
  message(FATAL_ERROR "declare failed (${rc}): ${log}")
endif()
execute_process(COMMAND ${SWBA} run ${OUT}/declared.rawlog --gt ${GT} --windows 5 --no-batch --no-ekf --no-plots
                        --no-progress --max-steps 200 --out ${OUT}/run
                ERROR_VARIABLE err OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT err MATCHES "188 readings, 188 with their own covariance")
  message(FATAL_ERROR "swba run on the declared copy (${rc}):\n${err}\n${out}")
endif()
