# Golden-output tests: every subcommand's printed figures on shipped data, compared with the committed
# references in ref/ at the printed precision (golden.cmake says what is masked). A change that moves
# a figure updates the reference in the same commit (scripts/update-golden.sh) and says why.
set(_golden ${CMAKE_CURRENT_LIST_DIR})
set(_golden_out ${CMAKE_CURRENT_BINARY_DIR}/golden)
set(_data ${SWBA_DATA_DIR})

# swba_golden(<name> <swba arguments...>): the command runs in its own work directory <work>.
function(swba_golden name)
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;${ARGN}")
  string(REPLACE "<work>" "${_golden_out}/${name}" _cmd "${_cmd}")
  add_test(NAME golden.${name}
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DREF=${_golden}/ref/${name}.txt
            -DACTUAL=${_golden_out}/${name}.actual.txt -DWORK_DIR=${_golden_out}/${name}
            -P ${_golden}/golden.cmake)
  set_tests_properties(golden.${name} PROPERTIES LABELS golden)
endfunction()

# swba run: the default rawlog with every default, and both policies x FEJ on/off (at two of the
# default window sizes: run_default has the others).
swba_golden(run_default run --out <work>/out)
swba_golden(run_policy_fej run --policy both --fej both --windows 10,30 --max-steps 150 --out <work>/out)
# swba run with the map policy on the default rawlog (6D), on the 2D one and without landmark IDs.
swba_golden(run_map run --policy map --windows 10 --no-ekf --no-batch --no-plots --out <work>/out)
swba_golden(run_map_planar run ${SWBA_MRPT_DATASETS}/kf-slam_demo.rawlog --policy map --windows 10 --no-ekf --no-batch --no-plots --out <work>/out)
swba_golden(run_map_association run ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_DA.rawlog --policy map --windows 10 --no-ekf --no-batch --no-plots --out <work>/out)
# swba run on a 2D rawlog with every default: the planar model and MRPT's 2D EKF.
swba_golden(run_planar run ${SWBA_MRPT_DATASETS}/kf-slam_demo.rawlog --out <work>/out)
# swba run without landmark IDs: data association (JCBB) and its quality against the landmark file.
swba_golden(run_association run ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_DA.rawlog --windows 10,30 --no-plots --out <work>/out)
# swba bal: the shipped BAL problem (threads do not change the figures).
swba_golden(bal bal ${_data}/bal/problem-49-7776-pre.txt)
# swba pgo: a 2D and two 3D pose graphs.
swba_golden(pgo_2d_intel pgo ${_data}/posegraph/intel.g2o -o <work>/intel.g2o)
swba_golden(pgo_3d_smallgrid pgo ${_data}/posegraph/smallGrid3D.g2o -o <work>/smallGrid3D.g2o)
swba_golden(pgo_3d_garage pgo ${_data}/posegraph/parking-garage.g2o -q)
# swba pgo --information repair: a hand-made 2D loop with one indefinite information (test data).
swba_golden(pgo_2d_information_repair pgo ${CMAKE_SOURCE_DIR}/tests/pgo/data/square_indefinite_se2.g2o
  --information repair)
# swba monoba: the default scene and the prior-weight sweep.
swba_golden(monoba monoba)
swba_golden(monoba_sweep monoba --sweep-prior-weights --seeds 3)
# swba directba: the synthetic room and the shipped image set.
swba_golden(directba_synthetic directba --synthetic)
swba_golden(directba_dataset directba ${_data}/directba -q --out <work>/out --ply-final <work>/final.ply)
# swba ape / rpe: evo's reference trajectories.
set(_evo ${_data}/evo_reference)
swba_golden(ape ape ${_evo}/gt_kf-slam_6D_demo.tum ${_evo}/ekf_kf-slam_6D_demo.tum)
swba_golden(ape_aligned ape ${_evo}/gt_kf-slam_6D_demo.tum ${_evo}/ekf_kf-slam_6D_demo.tum --align)
swba_golden(rpe rpe ${_evo}/gt_kf-slam_6D_demo.tum ${_evo}/ekf_kf-slam_6D_demo.tum)
swba_golden(rpe_delta10 rpe ${_evo}/gt_kf-slam_6D_demo.tum ${_evo}/ekf_kf-slam_6D_demo.tum --delta 10 --all-pairs)

# The comparison itself: a figure moved in the last printed digit must fail the test.
add_test(NAME golden.self_check_moved_figure
  COMMAND ${CMAKE_COMMAND} "-DCMD=${CMAKE_COMMAND}|-E|echo|Final cost:  1.000000000002e+00"
          -DREF=${_golden}/selfcheck/moved_figure.txt -DACTUAL=${_golden_out}/self_check.actual.txt
          -DWORK_DIR=${_golden_out}/self_check -P ${_golden}/golden.cmake)
set_tests_properties(golden.self_check_moved_figure PROPERTIES WILL_FAIL TRUE)

# swba jobs -> GNU parallel -j 2 -> swba merge over two rawlogs: the per-rawlog tables (the figures of
# swba run) and the APE rmse of each estimator over the rawlogs.
add_test(NAME golden.merge_sweep
  COMMAND ${CMAKE_COMMAND} "-DCMD=bash|${_golden}/sweep.sh|$<TARGET_FILE:swba>|${_golden_out}/merge_sweep|${SWBA_MRPT_DATASETS}"
          -DREF=${_golden}/ref/merge_sweep.txt -DACTUAL=${_golden_out}/merge_sweep.actual.txt
          -DWORK_DIR=${_golden_out}/merge_sweep -P ${_golden}/golden.cmake)
set_tests_properties(golden.merge_sweep PROPERTIES LABELS golden TIMEOUT 300)

# swba compare: two real logs run with the Cauchy and the Huber loss (tests/golden/compare_runs.sh, a
# fixture), then the paired comparison of the two sets of runs.
add_test(NAME golden.compare_runs_setup
  COMMAND bash ${_golden}/compare_runs.sh $<TARGET_FILE:swba> ${_golden_out}/compare_runs ${_data})
set_tests_properties(golden.compare_runs_setup PROPERTIES FIXTURES_SETUP compare_runs LABELS golden TIMEOUT 300)
swba_golden(compare compare ../compare_runs/cauchy ../compare_runs/huber --per-rawlog)
set_tests_properties(golden.compare PROPERTIES FIXTURES_REQUIRED compare_runs)

# Real robots' logs (share/data/mrclam, UTIAS MRCLAM dataset 6): `swba run` with every default, its
# printed figures pinned, then the bounds the window must keep there (realdata_bounds.cmake): every row
# finite, the online W = 30 row at most 2.5x the batch. MRPT's EKF diverges on robots 3 and 5 (marked
# DIVERGED: exit 3).
foreach(r 1 2 3 4 5)
  set(_rc 0)
  if(r EQUAL 3 OR r EQUAL 5)
    set(_rc 3)
  endif()
  set(_name run_mrclam6_r${r})
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;run;${_data}/mrclam/mrclam6_r${r}.rawlog;--no-plots;--no-progress;--out;${_golden_out}/${_name}/out")
  add_test(NAME golden.${_name}
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DREF=${_golden}/ref/${_name}.txt -DEXPECT_RC=${_rc}
            -DACTUAL=${_golden_out}/${_name}.actual.txt -DWORK_DIR=${_golden_out}/${_name}
            -P ${_golden}/golden.cmake)
  set_tests_properties(golden.${_name} PROPERTIES LABELS golden FIXTURES_SETUP ${_name})
  add_test(NAME realdata.bounds_r${r}
    COMMAND ${CMAKE_COMMAND} -DSUMMARY=${_golden_out}/${_name}/out/summary.json -DONLINE_BOUND=2.5
            -P ${_golden}/realdata_bounds.cmake)
  set_tests_properties(realdata.bounds_r${r} PROPERTIES FIXTURES_REQUIRED ${_name})
endforeach()
# All five without landmark IDs: data association, measured against the log with IDs (r2-r5 without
# the batch, which adds nothing to the association figures and doubles the time; doc/realdata.md's table).
swba_golden(run_mrclam6_r1_noids run ${_data}/mrclam/mrclam6_r1_noids.rawlog --association-truth
  ${_data}/mrclam/mrclam6_r1.rawlog --windows 30 --no-plots --no-progress --out <work>/out)
swba_golden(run_mrclam6_r2_noids run ${_data}/mrclam/mrclam6_r2_noids.rawlog --association-truth
  ${_data}/mrclam/mrclam6_r2.rawlog --windows 30 --no-batch --no-plots --no-progress --out <work>/out)
swba_golden(run_mrclam6_r3_noids run ${_data}/mrclam/mrclam6_r3_noids.rawlog --association-truth
  ${_data}/mrclam/mrclam6_r3.rawlog --windows 30 --no-batch --no-plots --no-progress --out <work>/out)
swba_golden(run_mrclam6_r4_noids run ${_data}/mrclam/mrclam6_r4_noids.rawlog --association-truth
  ${_data}/mrclam/mrclam6_r4.rawlog --windows 30 --no-batch --no-plots --no-progress --out <work>/out)
swba_golden(run_mrclam6_r5_noids run ${_data}/mrclam/mrclam6_r5_noids.rawlog --association-truth
  ${_data}/mrclam/mrclam6_r5.rawlog --windows 30 --no-batch --no-plots --no-progress --out <work>/out)
# The bound check itself must fail on a row over its bound.
add_test(NAME realdata.bounds_self_check
  COMMAND ${CMAKE_COMMAND} -DSUMMARY=${_golden}/selfcheck/realdata_over_bound.json -DONLINE_BOUND=2.5
          -P ${_golden}/realdata_bounds.cmake)
set_tests_properties(realdata.bounds_self_check PROPERTIES WILL_FAIL TRUE)

# swba run on an inertial (observation-format) rawlog that swba simulate-imu makes first: 20 s of the
# figure-eight, consumer IMU at 100 Hz, pose priors and odometry at 10 Hz (doc/inertial.md).
add_test(NAME golden.inertial_log_setup
  COMMAND $<TARGET_FILE:swba> simulate-imu --duration 20 --out ${_golden_out}/inertial_log --name figure8)
set_tests_properties(golden.inertial_log_setup PROPERTIES FIXTURES_SETUP inertial_log LABELS golden)
swba_golden(run_inertial run ../inertial_log/figure8.rawlog --config ../inertial_log/figure8.ini --out <work>/out)
set_tests_properties(golden.run_inertial PROPERTIES FIXTURES_REQUIRED inertial_log)
