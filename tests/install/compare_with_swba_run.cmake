# install.example_matches_swba_run: the example built against the installed package (fed
# CActionCollection/CSensoryFrame pairs one by one) and `swba run` (reads the whole rawlog with
# swba::io::read_rawlog) at the same settings — window W, default INI options, 1 solver thread — must
# give the same final pose and the same online and lagged trajectories, compared as the TUM text both
# write with swba::eval::write_tum (9 decimals).
# Two modes, two ctest tests (so that swba run can run while the example is installed and built):
#   -DMODE=swba_run -DSWBA -DRAWLOG -DWINDOW -DSTEPS (0 = all) -DOUT   writes OUT/swba_run/
#   -DMODE=example  -DEXAMPLE -DRAWLOG -DWINDOW -DSTEPS -DOUT           runs the example, compares
set(steps_args "")
if(STEPS AND NOT STEPS EQUAL 0)
  set(steps_args --max-steps ${STEPS})
endif()

if(MODE STREQUAL "swba_run")
  file(REMOVE_RECURSE ${OUT}/swba_run)
  execute_process(COMMAND ${SWBA} run ${RAWLOG} --windows ${WINDOW} --no-ekf --no-batch --no-plots --no-progress
      --threads 1 --out ${OUT}/swba_run ${steps_args}
    RESULT_VARIABLE rc OUTPUT_VARIABLE run_out ERROR_VARIABLE run_err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "swba run failed (${rc}):\n${run_out}\n${run_err}")
  endif()
  message(STATUS "swba run:\n${run_out}")
  return()
elseif(NOT MODE STREQUAL "example")
  message(FATAL_ERROR "MODE must be swba_run or example")
endif()

file(REMOVE ${OUT}/example_online.tum ${OUT}/example_lagged.tum)
execute_process(COMMAND ${EXAMPLE} ${RAWLOG} --window ${WINDOW} --threads 1 --print-every 0
    --tum ${OUT}/example_online.tum --lagged-tum ${OUT}/example_lagged.tum ${steps_args}
  RESULT_VARIABLE rc OUTPUT_VARIABLE ex_out ERROR_VARIABLE ex_err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the example failed (${rc}):\n${ex_out}\n${ex_err}")
endif()
message(STATUS "example:\n${ex_out}")

# Final pose: the example's "final pose: t x y z qx qy qz qw" line vs the last row of swba run's file.
set(run_online ${OUT}/swba_run/window_${WINDOW}.tum)
set(run_lagged ${OUT}/swba_run/window_${WINDOW}_lagged.tum)
foreach(f ${run_online} ${run_lagged})
  if(NOT EXISTS ${f})
    message(FATAL_ERROR "swba run did not write ${f}")
  endif()
endforeach()
file(STRINGS ${run_online} run_rows)
list(LENGTH run_rows n_run)
if(n_run EQUAL 0)
  message(FATAL_ERROR "${run_online} is empty")
endif()
list(GET run_rows -1 run_final)
string(REGEX MATCH "final pose: ([^\n]*)" m "${ex_out}")
if(NOT m)
  message(FATAL_ERROR "no 'final pose:' line in the example's output")
endif()
set(ex_final "${CMAKE_MATCH_1}")
message(STATUS "final pose, swba run: ${run_final}")
message(STATUS "final pose, example:  ${ex_final}")
if(NOT ex_final STREQUAL run_final)
  message(FATAL_ERROR "final poses differ:\n  swba run: ${run_final}\n  example:  ${ex_final}")
endif()

# Whole trajectories, row by row.
foreach(kind online lagged)
  if(kind STREQUAL "online")
    set(a ${run_online})
  else()
    set(a ${run_lagged})
  endif()
  set(b ${OUT}/example_${kind}.tum)
  file(STRINGS ${a} ra)
  file(STRINGS ${b} rb)
  list(LENGTH ra na)
  list(LENGTH rb nb)
  if(NOT na EQUAL nb)
    message(FATAL_ERROR "${kind} trajectories have ${na} (swba run) and ${nb} (example) rows")
  endif()
  math(EXPR last "${na} - 1")
  foreach(i RANGE ${last})
    list(GET ra ${i} x)
    list(GET rb ${i} y)
    if(NOT x STREQUAL y)
      message(FATAL_ERROR "${kind} trajectories differ first at row ${i}:\n  swba run: ${x}\n  example:  ${y}")
    endif()
  endforeach()
  message(STATUS "${kind} trajectory: ${na} rows, identical")
endforeach()
