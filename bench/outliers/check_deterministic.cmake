# Runs the tool twice with one seed (same bytes expected) and once with a larger fraction, and checks
# the counts it prints: 1 % of kf-slam_6D_demo's readings are about 58.
file(MAKE_DIRECTORY ${OUT})
foreach(run a b)
  execute_process(COMMAND ${TOOL} ${RAWLOG} ${OUT}/${run}.rawlog --fraction 0.01 --seed 7
                  OUTPUT_VARIABLE log_${run} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "tool failed: ${rc}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/a.rawlog ${OUT}/b.rawlog RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "same seed, different files")
endif()
string(REGEX MATCH "([0-9]+) of ([0-9]+) readings" m "${log_a}")
if(CMAKE_MATCH_1 LESS 30 OR CMAKE_MATCH_1 GREATER 90 OR NOT CMAKE_MATCH_2 EQUAL 5824)
  message(FATAL_ERROR "unexpected counts: ${log_a}")
endif()
