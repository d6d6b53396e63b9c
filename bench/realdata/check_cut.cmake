# Cuts steps 300..499 of a real log and runs swba on the segment: 200 steps, its ground truth found next
# to it and starting at the identity, and the window's APE of the same order as on the whole log (a
# ground truth paired with the wrong rows, or not re-expressed, gives metres).
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${TOOL} ${RAWLOG} ${OUT}/seg --from 300 --steps 200 OUTPUT_VARIABLE log RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT log MATCHES "steps 300..499 of")
  message(FATAL_ERROR "cut failed (${rc}): ${log}")
endif()
file(STRINGS ${OUT}/seg_ground_truth_robot_path.txt rows)
list(GET rows 1 first)
if(NOT first MATCHES "^-?0\\.0000000000 -?0\\.0000000000 -?0\\.0000000000 -?0\\.0000000000")
  message(FATAL_ERROR "the segment's ground truth does not start at the identity: ${first}")
endif()
execute_process(COMMAND ${SWBA} run ${OUT}/seg.rawlog --windows 5 --no-batch --no-ekf --no-plots --no-progress --out ${OUT}/run
                ERROR_VARIABLE err OUTPUT_VARIABLE out RESULT_VARIABLE rc)
string(REGEX MATCH "window W=5 +5 +online +([0-9.]+)" m "${out}")
set(ape "${CMAKE_MATCH_1}")  # before the next MATCHES, which resets it
if(NOT rc EQUAL 0 OR NOT err MATCHES "seg.rawlog: 200 steps" OR ape STREQUAL "" OR ape GREATER 0.5)
  message(FATAL_ERROR "swba run on the segment (${rc}, APE '${ape}'):\n${err}\n${out}")
endif()
