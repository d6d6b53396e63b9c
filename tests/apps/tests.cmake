# End-to-end tests of `swba run` (included from tests/CMakeLists.txt). Short runs only (≤ 60 steps).
set(_check ${CMAKE_CURRENT_LIST_DIR}/check_run.cmake)
set(_data ${CMAKE_CURRENT_LIST_DIR}/data)
set(_out ${CMAKE_CURRENT_BINARY_DIR}/runapp_e2e)
set(_demo ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo.rawlog)

# swba_run_case(<name> <exit code> REGEX <regex> [NOT_REGEX <regex>] [FILES <a|b>] [JSON <steps> <rows>] ARGS <args...>)
function(swba_run_case name rc)
  cmake_parse_arguments(C "" "REGEX;NOT_REGEX;FILES" "JSON;ARGS" ${ARGN})
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;run;${C_ARGS}")
  set(_extra)
  if(C_NOT_REGEX)
    list(APPEND _extra "-DNOT_REGEX=${C_NOT_REGEX}")
  endif()
  if(C_FILES)
    list(APPEND _extra "-DFILES=${C_FILES}")
  endif()
  if(C_JSON)
    list(GET C_JSON 0 _steps)
    list(GET C_JSON 1 _rows)
    list(APPEND _extra -DJSON_STEPS=${_steps} -DJSON_ROWS=${_rows})
  endif()
  add_test(NAME runapp.e2e.${name}
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DEXPECT_RC=${rc} "-DREGEX=${C_REGEX}" ${_extra}
            -DOUT_DIR=${_out}/${name} -DCLEAN_DIR=${_out}/${name} -P ${_check})
endfunction()

# The default rawlog (no RAWLOG argument), 60 steps, W = 5 and 10: table, every file, JSON shape.
swba_run_case(short_default 0
  REGEX "\\(60 steps\\).*\nekf kfEKFAlaDavison +- +online +0\\.[0-9][0-9][0-9][0-9][0-9][0-9] .*\nekf kfEKFNaive .*\nwindow W=5 +5 +online +0\\.[0-9][0-9][0-9][0-9][0-9][0-9] .*\nwindow W=5 lagged +5 +lagged +0\\.[0-9][0-9][0-9][0-9][0-9][0-9] .*\nwindow W=10 +10 +online .*\nwindow W=10 lagged .*\nbatch \\((DR|W=10) start\\) +- +smoothed +0\\.[0-9][0-9][0-9][0-9][0-9][0-9] .*\nbatch alt \\((DR|W=10) start\\) +- +smoothed +0\\.[0-9]"
  NOT_REGEX "FAILED|DIVERGED"
  FILES "gt.tum|ekf_kfEKFAlaDavison.tum|ekf_kfEKFNaive.tum|window_5.tum|window_5_lagged.tum|window_10.tum|window_10_lagged.tum|batch.tum|batch_alt.tum|ape.txt|ape.csv|summary.json|config.ini"
  JSON 60 8
  ARGS --max-steps 60 --windows 5,10 --out ${_out}/short_default)
# One EKF method: ekf.tum; policy × FEJ combinations: one row pair per combination.
swba_run_case(policy_fej_both 0
  REGEX "\nwindow W=5 slam fej +5 +online .*\nwindow W=5 slam nofej +5 .*\nwindow W=5 constant-time fej +5 .*\nwindow W=5 constant-time nofej lagged +5 +lagged "
  FILES "ekf.tum|window_5_slam_fej.tum|window_5_slam_nofej_lagged.tum|window_5_constant-time_fej.tum|window_5_constant-time_nofej_lagged.tum"
  JSON 30 9
  ARGS ${_demo} --max-steps 30 --windows 5 --policy both --fej both --ekf-method kfEKFNaive --no-batch --no-plots --out ${_out}/policy_fej_both)
# Precedence: defaults < --config < command line.
swba_run_case(config_applied 0 REGEX "\\(20 steps\\).*\nwindow W=7 +7 +online" NOT_REGEX "\nekf|\nbatch"
  ARGS ${_demo} --config ${_data}/override.ini --no-plots --out ${_out}/config_applied)
swba_run_case(command_line_overrides_config 0 REGEX "\\(20 steps\\).*\nwindow W=5 +5 +online" NOT_REGEX "W=7<OR>\nbatch"
  ARGS ${_demo} --config ${_data}/override.ini --windows 5 --no-plots --out ${_out}/command_line_overrides_config)
# --help lists every option.
swba_run_case(help 0 REGEX "--windows.*--no-ekf.*--no-batch.*--causal.*--ekf-method.*--policy.*--fej.*--landmarks.*--gauge.*--association.*--sensor-std-range.*--max-steps.*--threads.*--out"
  ARGS --help)

# Bad input: one line naming the file/option; exit 2 for a bad command line, 1 for a bad input file.
swba_run_case(window_1 2 REGEX "swba run: error: --windows: window size must be in \\[2, 1000000\\], got 1 \\(see --help\\)\n"
  ARGS --windows 5,1 --max-steps 10 --out ${_out}/window_1)
swba_run_case(window_overflow 2
  REGEX "swba run: error: --windows: window size must be in \\[2, 1000000\\], got 99999999999999999999 \\(see --help\\)\n"
  ARGS --windows 99999999999999999999 --out ${_out}/window_overflow)
swba_run_case(gate_probability_one 2 REGEX "swba run: error: --gate-probability must be in \\(0, 1\\), got 1 \\(see --help\\)\n"
  ARGS --gate-probability 1 --out ${_out}/gate_probability_one)
swba_run_case(robust_probability_zero 2 REGEX "swba run: error: --robust-probability must be in \\(0, 1\\), got 0 \\(see --help\\)\n"
  ARGS --robust-probability 0 --out ${_out}/robust_probability_zero)
# An output directory given with a trailing slash is printed with one.
swba_run_case(out_dir_trailing_slash 0 REGEX "swba run: wrote [0-9]+ files into [^\n]*/out_dir_trailing_slash/\n" NOT_REGEX "//\n"
  ARGS ${_demo} --max-steps 10 --windows 5 --no-ekf --no-batch --no-plots --out ${_out}/out_dir_trailing_slash/)
swba_run_case(missing_rawlog 1 REGEX "swba run: error: rawlog '/nonexistent/none.rawlog': file does not exist"
  ARGS /nonexistent/none.rawlog --out ${_out}/missing_rawlog)
swba_run_case(gt_5_columns 1 REGEX "swba run: error: [^\n]*gt_5_columns.txt[^\n]*4[^\n]*6"
  ARGS ${_demo} --gt ${_data}/gt_5_columns.txt --max-steps 60 --out ${_out}/gt_5_columns)
swba_run_case(gt_too_short 1
  REGEX "swba run: error: ground truth '[^']*gt_30_rows.txt': 30 rows, but the rawlog has 60 steps and needs 61 rows"
  ARGS ${_demo} --gt ${_data}/gt_30_rows.txt --max-steps 60 --out ${_out}/gt_too_short)
swba_run_case(missing_gt 1 REGEX "swba run: error: [^\n]*/nonexistent/gt.txt"
  ARGS ${_demo} --gt /nonexistent/gt.txt --max-steps 10 --out ${_out}/missing_gt)
swba_run_case(map_free_gauge 2 REGEX "swba run: error: the map landmark policy needs the fixed or the prior gauge"
  ARGS --policy slam,map --gauge free --out ${_out}/map_free_gauge)
swba_run_case(bad_policy 2 REGEX "swba run: error: unknown policy 'fast' \\(expected slam, constant-time, map, a comma-separated list of them, both or all\\)"
  ARGS --policy fast --out ${_out}/bad_policy)
swba_run_case(bad_fej 2 REGEX "swba run: error: unknown fej value 'sometimes'" ARGS --fej sometimes --out ${_out}/bad_fej)
swba_run_case(bad_gauge 2 REGEX "swba run: error: unknown gauge 'loose'" ARGS --gauge loose --out ${_out}/bad_gauge)
swba_run_case(bad_landmarks 2 REGEX "swba run: error: unknown landmark parameteri[sz]ation 'uvw'" ARGS --landmarks uvw --out ${_out}/bad_landmarks)
swba_run_case(bad_ekf_method 2 REGEX "swba run: error: unknown EKF method 'kfUKF'" ARGS --ekf-method kfUKF --out ${_out}/bad_ekf_method)
swba_run_case(bad_sensor_std 2 REGEX "swba run: error: --sensor-std-range must be a number > 0" ARGS --sensor-std-range 0 --out ${_out}/bad_sensor_std)
swba_run_case(misspelt_config_key 1
  REGEX "swba run: error: config '[^']*misspelt_key.ini': unknown key 'size' in section \\[window\\] \\(known keys: sizes, "
  ARGS --config ${_data}/misspelt_key.ini --out ${_out}/misspelt_config_key)
swba_run_case(missing_config 1 REGEX "swba run: error: config '/nonexistent/x.ini': file does not exist"
  ARGS --config /nonexistent/x.ini --out ${_out}/missing_config)

# Least squares with a sensor noise declared a thousand times too small: the readings are far outside what
# every row's own covariance predicts, so the rows are marked DIVERGED (no figures in the table, a note) and
# the run exits 3 after writing its files. (With the Cauchy loss the same readings are down-weighted, the
# covariance grows with them and the estimate stays sound: not marked.)
swba_run_case(diverged_rows_exit_3 3
  REGEX "\nwindow W=5 +5 +online +- +- .*DIVERGED \\(see the note\\).*note: window W=5: DIVERGED: the median squared innovation"
  FILES "window_5.tum|summary.json|ape.csv"
  ARGS --sensor-std-range 0.00001 --sensor-std-yaw-deg 0.0001 --sensor-std-pitch-deg 0.0001 --robust-loss none
       --windows 5 --no-ekf
       --no-batch --max-steps 40 --no-plots --out ${_out}/diverged_rows_exit_3)
# Association measured against a rawlog holding the same readings with their IDs (the real log r1,
# without and with IDs, 150 steps).
swba_run_case(association_truth_rawlog 0
  REGEX "association quality against [^\n]*mrclam6_r1.rawlog \\(its landmark IDs\\).*note: window W=10: association [0-9.]+ % correct"
  ARGS ${SWBA_DATA_DIR}/mrclam/mrclam6_r1_noids.rawlog --association-truth ${SWBA_DATA_DIR}/mrclam/mrclam6_r1.rawlog
       --windows 10 --no-ekf --no-batch --max-steps 150 --no-plots --out ${_out}/association_truth_rawlog)
swba_run_case(association_truth_other_readings 1
  REGEX "association truth '[^']*mrclam6_r2.rawlog': step 0 does not hold the rawlog's readings"
  ARGS ${SWBA_DATA_DIR}/mrclam/mrclam6_r1_noids.rawlog --association-truth ${SWBA_DATA_DIR}/mrclam/mrclam6_r2.rawlog
       --windows 10 --no-ekf --no-batch --max-steps 150 --no-plots --out ${_out}/association_truth_other_readings)

# MRPT's EKF diverges and throws on kf-slam_6D_demo_noncentered: a row with the step and the message,
# the other estimators still run, exit 3 (a row failed) after writing everything.
swba_run_case(ekf_failure_is_a_row 3
  REGEX "\nekf kfEKFAlaDavison +- +online +- +- +- +- +- +- +- +[0-9.]+  FAILED at step [0-9]+: [^\n]*quaternion[^\n]*\nwindow W=2 +2 +online +0\\.[0-9]"
  FILES "ekf.tum|window_2.tum|summary.json"
  JSON 100 3
  ARGS ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_noncentered.rawlog --ekf-method kfEKFAlaDavison --windows 2 --no-batch
       --no-plots --max-steps 100 --out ${_out}/ekf_failure_is_a_row)

# A 2D rawlog (mrpt-common's kf-slam_demo: 2D odometry, readings without pitch) with no model flags
# (100 of its 249 steps; golden.run_planar pins the whole run): the planar model and MRPT's 2D EKF, every
# row with figures.
set(_demo2d ${SWBA_MRPT_DATASETS}/kf-slam_demo.rawlog)
swba_run_case(planar_no_flags 0
  REGEX "\nekf kfEKFAlaDavison +- +online +0\\.00[0-9]+ .*\nwindow W=5 +5 +online +0\\.00[0-9]+ .*\nwindow W=30 lagged +30 +lagged +0\\.00[0-9]+ .*\nbatch \\((DR|W=30) start\\) +- +smoothed +0\\.00[0-9]+ .*planar rawlog[^\n]*2D model.*note: ekf kfEKFAlaDavison: MRPT's 2D filter CRangeBearingKFSLAM2D"
  NOT_REGEX "FAILED|DIVERGED"
  JSON 100 12
  ARGS ${_demo2d} --max-steps 100 --no-plots --out ${_out}/planar_no_flags)
# Every estimator failed (the 6D model on 2D data: no pitch noise): each row reported with the real
# failing step (the batch's too), then exit 1.
swba_run_case(every_estimator_failed 1
  REGEX "\nwindow W=5 +5 +online [^\n]*FAILED at step 0: step 0: sensor noise is not positive[^\n]*\n.*\nbatch +- +smoothed [^\n]*FAILED at step 0: step 0: sensor noise[^\n]*\n.*swba run: error: every estimator failed"
  ARGS ${_demo2d} --config ${_data}/model_6d.ini --no-ekf --windows 5 --no-plots --out ${_out}/every_estimator_failed)

# Command-line conventions of every subcommand (apps/swba/cli.cpp, main.cpp; doc/cli.md).
# swba_cli_case(<name> <exit code> REGEX <regex> ARGS <args...>): any subcommand, no output checks.
function(swba_cli_case name rc)
  cmake_parse_arguments(C "" "REGEX" "ARGS" ${ARGN})
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;${C_ARGS}")
  add_test(NAME apps.cli.${name}
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DEXPECT_RC=${rc} "-DREGEX=${C_REGEX}" -P ${_check})
endfunction()
swba_cli_case(version_option 0 REGEX "^swba [0-9]+\\.[0-9]+\\.[0-9]+ \\(MRPT [0-9.]+, Eigen [0-9.]+; rank-update kernel [a-z0-9]+\\)" ARGS --version)
swba_cli_case(command_version_option 0 REGEX "^swba [0-9]+\\.[0-9]+\\.[0-9]+ \\(MRPT [0-9.]+, Eigen" ARGS run --version)
swba_cli_case(help_command 0 REGEX "swba run +\\[<RAWLOG>\\] \\[--gt <FILE>\\]" ARGS help run)
# A binary file (a rawlog) where a text file is expected is named as such, never parsed; an MRPT path given as TUM.
set(_binary ${SWBA_DATA_DIR}/mrclam/mrclam6_r1.rawlog)
set(_tum_ref ${SWBA_DATA_DIR}/evo_reference/gt_kf-slam_6D_demo.tum)
swba_cli_case(ape_binary_estimate 1 REGEX "mrclam6_r1.rawlog: not a text file \\(a NUL byte at byte [0-9]+" ARGS ape ${_tum_ref} ${_binary})
swba_cli_case(pgo_binary_input 1 REGEX "g2o file '[^']*mrclam6_r1.rawlog': not a text file" ARGS pgo ${_binary} -q)
swba_cli_case(bal_binary_input 1 REGEX "BAL file '[^']*mrclam6_r1.rawlog': not a text file" ARGS bal ${_binary} -q)
swba_cli_case(ape_mrpt_path_as_tum 1 REGEX "robot_path.txt:1: '%' starts a comment in MRPT's files, not in TUM's"
  ARGS ape ${SWBA_DATA_DIR}/mrclam/mrclam6_r1_ground_truth_robot_path.txt ${_tum_ref})
swba_cli_case(run_config_options_exclude_each_other 1
  REGEX "^swba run: error: config '[^']*map_free_gauge.ini': the map landmark policy needs the fixed or the prior gauge"
  ARGS run --config ${_data}/map_free_gauge.ini --out ${_out}/map_free_gauge_ini)
swba_cli_case(jobs_names_itself 0 REGEX "swba jobs: wrote 4 jobs into [^\n]*/jobs_names_itself/jobs.txt"
  ARGS jobs ${_binary} --out ${_out}/jobs_names_itself)
swba_cli_case(jobs_not_a_rawlog 1 REGEX "^swba jobs: error: rawlog '[^']*misspelt_key.ini': not an MRPT rawlog"
  ARGS jobs ${_data}/misspelt_key.ini --out ${_out}/jobs_not_a_rawlog)
swba_cli_case(jobs_simulate_not_a_simulator_ini 1
  REGEX "^swba jobs: error: simul-landmarks INI '[^']*misspelt_key.ini': no \\[Params\\] random_seed"
  ARGS jobs --simulate ${_data}/misspelt_key.ini --seeds 1-2 --out ${_out}/jobs_simulate_not_ini)
swba_cli_case(nees_not_a_simulator_ini 1
  REGEX "^swba nees: error: simul-landmarks INI '[^']*misspelt_key.ini': no \\[Params\\] random_seed"
  ARGS nees --ini ${_data}/misspelt_key.ini --runs 1 --out ${_out}/nees_not_ini)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/ekf_ini_binary.ini "[ekf]\nini_file = ${_binary}\n")
swba_cli_case(run_ekf_ini_binary 1 REGEX "EKF INI file '[^']*mrclam6_r1.rawlog': not a text file"
  ARGS run ${_binary} --config ${CMAKE_CURRENT_BINARY_DIR}/ekf_ini_binary.ini --windows 5 --no-batch --no-plots
  --max-steps 5 --out ${_out}/run_ekf_ini_binary)
swba_cli_case(bal_loss_scale_not_positive 2 REGEX "^swba bal: error: --loss-scale must be > 0 \\(see --help\\)"
  ARGS bal ${_binary} --loss cauchy --loss-scale -1)
swba_cli_case(directba_synthetic_writes_no_files 2 REGEX "^swba directba: error: --synthetic writes no files"
  ARGS directba --synthetic -q --out ${_out}/directba_synthetic_out)
swba_cli_case(simulate_imu_too_long 2 REGEX "^swba simulate-imu: error: duration x imu_rate = 1e\\+11 IMU readings, more than 1e7"
  ARGS simulate-imu --duration 1e9 --out ${_out}/simulate_imu_too_long)
swba_cli_case(help_lists_commands_in_one_column 0 REGEX "\n  ape           absolute pose error.*\n  simulate-imu  an inertial rawlog"
  ARGS --help)
swba_cli_case(bal_missing_problem 2 REGEX "^swba bal: error: missing argument\\(s\\): PROBLEM \\(see --help\\)" ARGS bal)
swba_cli_case(option_given_twice 2 REGEX "^swba run: error: option --max-steps given twice \\(see --help\\)"
  ARGS run --max-steps 3 --max-steps 4)
swba_cli_case(unknown_option 2 REGEX "^swba run: error: unknown option '--bogus' \\(see --help\\)" ARGS run --bogus)
swba_cli_case(unknown_short_option 2 REGEX "^swba ape: error: unknown option '-x'" ARGS ape -x a b)
swba_cli_case(switch_given_a_value 2 REGEX "error: option '--no-ekf' takes no value" ARGS run --no-ekf=1)
swba_cli_case(missing_value 2 REGEX "error: Missing a value for this argument! \\[Argument: \\(--windows\\)\\]"
  ARGS run --windows)
swba_cli_case(missing_positional 2 REGEX "^swba ape: error: missing argument\\(s\\): REF, EST \\(see --help\\)" ARGS ape)
swba_cli_case(equals_form 0 REGEX "\\(3 steps\\)\nAPE not aligned"
  ARGS run --max-steps=3 --windows=5 --no-ekf --no-batch --no-plots --no-progress --out=${_out}/cli_equals_form)
# A value that starts with '-' is the option's value, not an unknown option.
swba_cli_case(negative_value 1 REGEX "^swba ape: error: /nonexistent/ref.tum: cannot open file"
  ARGS ape --t-offset -0.5 /nonexistent/ref.tum /nonexistent/est.tum)
swba_cli_case(switch_run 1 REGEX "^swba ape: error: /nonexistent/ref.tum: cannot open file"
  ARGS ape -as /nonexistent/ref.tum /nonexistent/est.tum)

# Data association after a long stretch of dead reckoning: on da_6D_600 (seed 2) no landmark is in
# view over steps ≈ 40–85 and the pose drifts 0.6 m; the first 120 steps hold the readings after it
# that nearest neighbour cannot place (from step ≈ 111, below). The landmarks seen again are matched to
# themselves (the window's joint covariance of the pose and the landmarks) and their readings enter at
# once: no duplicate landmark, none held by the gate. The causal row takes the window's associations
# as known IDs: there the gate's odometry-only test holds them and the re-test against the window's
# covariance lets them in (retest_held), so it too holds none. The gate is on (without the robust loss
# that replaces it by default): these are the gate's mechanisms, and with the gate off nothing is held.
swba_cli_case(simulate_da_drift 0 REGEX "da_6D_600_seed2\\.rawlog"
  ARGS simulate ${CMAKE_SOURCE_DIR}/share/rawlogs/da_6D_600.ini --seed 2 --out ${_out}/da_drift)
set_tests_properties(apps.cli.simulate_da_drift PROPERTIES FIXTURES_SETUP da_drift)
swba_cli_case(association_after_drift 0
  REGEX "window W=10: 782 readings, 0 gated .*causal \\(online W=inf\\): 782 readings, 0 gated .*window W=10: association 100\\.00 % correct .* 20 landmarks for 20 true, 0 duplicate, 0 spurious"
  ARGS run ${_out}/da_drift/da_6D_600_seed2.rawlog --max-steps 120 --windows 10 --causal --no-ekf --no-batch --no-plots
       --gate on --robust-loss none --no-progress --out ${_out}/da_drift/run)
set_tests_properties(apps.cli.association_after_drift PROPERTIES FIXTURES_REQUIRED da_drift)
# Nearest neighbour on the same run: the reading after the drift that falls outside every gate is matched
# by the second test with the pose's covariance inflated, so no duplicate is created (1 such match).
swba_cli_case(association_nn_no_duplicate_after_drift 0
  REGEX "window W=10: association 100\\.00 % correct .* 20 landmarks for 20 true, 0 duplicate, 0 spurious, 0 re-associated in the window, 0 ambiguous on arrival, 1 matched with the pose's covariance inflated"
  ARGS run ${_out}/da_drift/da_6D_600_seed2.rawlog --max-steps 120 --windows 10 --association nn --no-ekf --no-batch
       --gate on --robust-loss none --no-plots --no-progress --out ${_out}/da_drift/run_nn_inflated)
# Without that test (association_pose_inflation = 1) the reading starts a duplicate landmark, then
# confirmed; re-association inside the window merges it back (2 readings moved), or keeps it when off.
swba_cli_case(association_nn_merges_duplicate 0
  REGEX "window W=10: association 100\\.00 % correct .* 20 landmarks for 20 true, 0 duplicate, 0 spurious, 2 re-associated in the window"
  ARGS run ${_out}/da_drift/da_6D_600_seed2.rawlog --max-steps 120 --windows 10 --association nn --no-ekf --no-batch
       --config ${_data}/no_pose_inflation.ini
       --gate on --robust-loss none --no-plots --no-progress --out ${_out}/da_drift/run_nn)
swba_cli_case(association_nn_keeps_duplicate 0
  REGEX "window W=10: association 99\\.49 % correct .* 21 landmarks for 20 true, 1 duplicate, 0 spurious, 0 re-associated in the window"
  ARGS run ${_out}/da_drift/da_6D_600_seed2.rawlog --max-steps 120 --windows 10 --association nn --no-ekf --no-batch
       --config ${_data}/no_reassociate.ini --gate on --robust-loss none --no-plots --no-progress --out ${_out}/da_drift/run_nn_kept)
set_tests_properties(apps.cli.association_nn_no_duplicate_after_drift apps.cli.association_nn_merges_duplicate
  apps.cli.association_nn_keeps_duplicate PROPERTIES FIXTURES_REQUIRED da_drift)

# The output directory is created and checked before any estimator runs: the full demo with the
# causal optimum (minutes of estimation) must fail at once (TIMEOUT), naming the directory and why.
swba_run_case(out_dir_not_creatable 1
  REGEX "swba run: error: cannot create output directory '/proc/swba_out': "
  ARGS --causal --windows 5,10,20,30 --no-plots --no-progress --out /proc/swba_out)
set_tests_properties(runapp.e2e.out_dir_not_creatable PROPERTIES TIMEOUT 60)
swba_run_case(out_dir_is_a_file 1
  REGEX "swba run: error: output directory '[^']*/tests/CMakeLists.txt' exists and is not a directory"
  ARGS --causal --windows 5,10,20,30 --no-plots --no-progress --out ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt)
set_tests_properties(runapp.e2e.out_dir_is_a_file PROPERTIES TIMEOUT 60)

# --verbose: a line per window step, then the batch's full solver report (stderr).
swba_run_case(verbose 0
  REGEX "window W=3 step 0: LM [0-9]+ it, cost [^\n]*\n.*window W=3 step 4: LM [0-9]+ it, cost [0-9.e+-]+ -> [0-9.e+-]+, (NO_)?CONVERGENCE \\([a-z ]+\\); 3 poses, [0-9]+ landmarks, prior rank [0-9]+; solve [0-9.]+ ms, marginalisation [0-9.]+ ms, covariance [0-9.]+ ms, step [0-9.]+ ms\n.*batch: [0-9]+ solve round\\(s\\); the last:\n.*Final cost: +[0-9.e+]+\n.*Termination: CONVERGENCE"
  ARGS --max-steps 5 --windows 3 --no-ekf --verbose --no-plots --no-progress --out ${_out}/verbose)

# SIGINT / SIGTERM mid-run (tests/apps/interrupt.sh): exit 130 / 143, complete rows kept, the rest
# marked interrupted in summary.json and the table.
foreach(_sig_rc INT:130 TERM:143)
  string(REPLACE ":" ";" _pair "${_sig_rc}")
  list(GET _pair 0 _sig)
  list(GET _pair 1 _rc)
  add_test(NAME runapp.e2e.interrupted_by_sig${_sig}
    COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/interrupt.sh $<TARGET_FILE:swba> ${_out}/interrupted_${_sig} ${_sig} ${_rc})
  set_tests_properties(runapp.e2e.interrupted_by_sig${_sig} PROPERTIES PASS_REGULAR_EXPRESSION "OK: exit ${_rc}"
    TIMEOUT 120)
endforeach()
add_test(NAME runapp.e2e.config_reload_elsewhere
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/config_reload_elsewhere.sh $<TARGET_FILE:swba>
  ${SWBA_DATA_DIR}/mrclam/mrclam6_r1.rawlog ${_out}/config_reload_elsewhere)
set_tests_properties(runapp.e2e.config_reload_elsewhere PROPERTIES PASS_REGULAR_EXPRESSION "OK: config.ini" TIMEOUT 120)
add_test(NAME runapp.e2e.interrupted_by_sigTERM_twice
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/interrupt.sh $<TARGET_FILE:swba> ${_out}/interrupted_twice TERM 143 twice)
set_tests_properties(runapp.e2e.interrupted_by_sigTERM_twice PROPERTIES PASS_REGULAR_EXPRESSION "OK: exit 143"
  TIMEOUT 120)
# -q is --quiet in every solver command that documents it (doc/cli.md).
# swba compare: a missing path, a directory without summaries, an unknown metric.
swba_cli_case(compare_missing_path 1 REGEX "swba compare: error: /nonexistent/base: does not exist" ARGS compare /nonexistent/base /nonexistent/other)
swba_cli_case(compare_no_summaries 1 REGEX "swba compare: error: [^\n]*posegraph: no summary.json below it" ARGS compare ${SWBA_DATA_DIR}/posegraph ${SWBA_DATA_DIR}/posegraph)
swba_cli_case(compare_bad_metric 2 REGEX "unknown metric 'rmse' \\(expected ape_trans, ape_rot or rpe_trans\\)" ARGS compare a b --metric rmse)
foreach(_c bal pgo directba)
  swba_cli_case(quiet_short_form_${_c} 0 REGEX "-q, +--quiet" ARGS ${_c} --help)
endforeach()

# --help of every subcommand lists the positional arguments, then the options in a logical order: input, main
# choices, tuning, output, verbosity (apps/swba/cli.cpp, help_order); every default reads "(Default: X)".
set(_help_order_run "Where:.*<RAWLOG>.*--gt.*--config.*--windows.*--no-ekf.*--no-batch.*--causal.*--ekf-method.*--policy.*--fej.*--landmarks.*--gauge.*--association.*--sensor-std-range.*--gate .*--gate-probability.*--robust-loss.*--robust-probability.*--max-steps.*--threads.*--out.*--no-plots.*--no-progress.*--verbose.*--version.*--help")
set(_help_order_ape "Where:.*<REF>.*<EST>.*--ref-format.*--pose-relation.*--align.*--correct-scale.*--align-origin.*--t-max-diff.*--t-offset.*--save-results.*--plot.*--version.*--help")
set(_help_order_rpe "Where:.*<REF>.*<EST>.*--ref-format.*--pose-relation.*--align.*--correct-scale.*--align-origin.*--delta.*--all-pairs.*--t-max-diff.*--t-offset.*--save-results.*--plot.*--version.*--help")
set(_help_order_monoba "Where:.*--cameras.*--points.*--noise.*--depth-noise.*--pose-noise-m.*--pose-noise-rad.*--seed .*--gauge.*--fix .*--prior-weight.*--sweep-prior-weights.*--seeds.*--repetitions.*--max-iterations.*--threads.*--out.*--progress.*--version.*--help")
set(_help_order_bal "Where:.*<PROBLEM>.*--linear.*--loss .*--loss-scale.*--max-iterations.*--function-tolerance.*--gradient-tolerance.*--parameter-tolerance.*--threads.*--ply-initial.*--ply-final.*--write-problem.*--quiet.*--version.*--help")
set(_help_order_pgo "Where:.*<IN.g2o>.*--information.*--init .*--gauge.*--prior-sigma.*--robust .*--robust-scale.*--rotation-error.*--linear.*--max-iterations.*--function-tolerance.*--initial-trust-region.*--threads.*--output.*--quiet.*--version.*--help")
set(_help_order_compare "Where:.*<BASE>.*<OTHER>.*--metric.*--per-rawlog.*--json.*--version.*--help")
set(_help_order_directba "Where:.*<DIR>.*--synthetic.*--sigma.*--huber-delta.*--fixed-cameras.*--border.*--iterations.*--threads.*--ply-initial.*--ply-final.*--out .*--quiet.*--version.*--help")
foreach(_c run ape rpe monoba bal pgo directba compare)
  add_test(NAME apps.cli.help_order_${_c} COMMAND $<TARGET_FILE:swba> ${_c} --help)
  set_tests_properties(apps.cli.help_order_${_c} PROPERTIES PASS_REGULAR_EXPRESSION "${_help_order_${_c}}"
    FAIL_REGULAR_EXPRESSION "\\.[ \n]+\\(Default|\\([Dd]efault [^:]|\\(default|[^ \n]\\(Default")
endforeach()

# Data on stdout; notes and the files written on stderr (doc/cli.md): the "Wrote <file>" lines of the solver
# commands go to stderr, and nothing of them to stdout.
set(_streams ${_out}/streams)
file(MAKE_DIRECTORY ${_streams})
# swba_stream_case(<name> <stderr regex> <swba arguments...>)
function(swba_stream_case name stderr_regex)
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;${ARGN}")
  add_test(NAME apps.cli.streams_${name}
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DEXPECT_RC=0 "-DSTDERR_REGEX=${stderr_regex}"
            "-DSTDOUT_NOT_REGEX=Wrote |saved |plot " -P ${_check})
endfunction()
swba_stream_case(bal "Wrote ${_streams}/bal_initial.ply .*Wrote ${_streams}/bal_final.ply .*Wrote ${_streams}/bal_solution.txt "
  bal ${SWBA_DATA_DIR}/bal/problem-49-7776-pre.txt --max-iterations 1 --ply-initial ${_streams}/bal_initial.ply
  --ply-final ${_streams}/bal_final.ply --write-problem ${_streams}/bal_solution.txt)
swba_stream_case(pgo "Wrote ${_streams}/pgo.g2o" pgo ${SWBA_DATA_DIR}/posegraph/smallGrid3D.g2o -o ${_streams}/pgo.g2o)
swba_stream_case(monoba "Wrote ${_streams}/monoba.txt" monoba --out ${_streams}/monoba.txt)
swba_stream_case(directba "Wrote ${_streams}/directba_initial.ply.*Wrote ${_streams}/directba_final.ply.*Wrote ${_streams}/directba/poses_initial.tum"
  directba ${SWBA_DATA_DIR}/directba --iterations 1 --ply-initial ${_streams}/directba_initial.ply
  --ply-final ${_streams}/directba_final.ply --out ${_streams}/directba)
swba_stream_case(ape "saved ${_streams}/ape/ape_stats.json" ape ${SWBA_DATA_DIR}/evo_reference/gt_kf-slam_6D_demo.tum
  ${SWBA_DATA_DIR}/evo_reference/ekf_kf-slam_6D_demo.tum --save-results ${_streams}/ape)
# Sweeps as jobs (doc/sweeps.md): swba jobs -> GNU parallel -j 2 -> swba merge equals one sequential
# swba run (tests/apps/sweep_parallel.sh); the Slurm script runs line K; a missing job is named.
add_test(NAME apps.sweep.parallel_merge_equals_sequential
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/sweep_parallel.sh $<TARGET_FILE:swba> ${_out}/sweep_parallel ${_demo})
set_tests_properties(apps.sweep.parallel_merge_equals_sequential PROPERTIES PASS_REGULAR_EXPRESSION "OK: sweep"
  TIMEOUT 300)
# Inertial rawlogs in a sweep: one job each, merged report = sequential run, table across rawlogs.
add_test(NAME apps.sweep.inertial_jobs_equal_sequential
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/sweep_inertial.sh $<TARGET_FILE:swba> ${_out}/sweep_inertial)
set_tests_properties(apps.sweep.inertial_jobs_equal_sequential PROPERTIES PASS_REGULAR_EXPRESSION "OK: inertial sweep"
  TIMEOUT 300)
# swba nees sequential vs its jobs on GNU parallel -j 2 + swba merge (2 simulated runs).
add_test(NAME apps.sweep.nees_parallel_equals_sequential
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/nees_sweep.sh $<TARGET_FILE:swba> ${_out}/nees_sweep)
set_tests_properties(apps.sweep.nees_parallel_equals_sequential PROPERTIES PASS_REGULAR_EXPRESSION "OK: " TIMEOUT 300)
# The same output whatever the thread count (with and without landmark IDs; the batch of 250 steps of the
# demo is the one above the solver's parallel threshold, tests/apps/threads_identical.sh).
add_test(NAME apps.cli.threads_give_identical_output
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/threads_identical.sh $<TARGET_FILE:swba> ${_out}/threads ${_demo} 250
          ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_DA.rawlog 60)
set_tests_properties(apps.cli.threads_give_identical_output PROPERTIES PASS_REGULAR_EXPRESSION "OK: " TIMEOUT 300)
# Command-line conventions of the new commands.
swba_cli_case(jobs_help 0 REGEX "--simulate.*--seeds.*--windows.*--config.*--out.*--swba" ARGS jobs --help)
swba_cli_case(merge_help 0 REGEX "--out.*--no-plots" ARGS merge --help)
swba_cli_case(nees_help 0 REGEX "--runs.*--first-seed.*--ini.*--windows.*--fej.*--jobs-only" ARGS nees --help)
swba_cli_case(simulate_help 0 REGEX "--seed.*--out.*--keep-declared-noise" ARGS simulate --help)
# simul-landmarks' four motionless first steps (zero odometry written without noise) are declared exact.
swba_cli_case(simulate_declares_motionless_exact 0
  REGEX "swba simulate: 4 motionless odometry increments \\(written without noise by simul-landmarks\\) declared exact"
  ARGS simulate ${CMAKE_SOURCE_DIR}/share/rawlogs/kf-slam_6D_noisy.ini --seed 2 --out ${_out}/simulate_exact)
swba_cli_case(jobs_bad_seeds 2 REGEX "^swba jobs: error: --seeds: range '5-2' is reversed \\(see --help\\)"
  ARGS jobs --simulate ${CMAKE_SOURCE_DIR}/share/rawlogs/kf-slam_6D_noisy.ini --seeds 5-2 --out ${_out}/jobs_bad_seeds)
swba_cli_case(jobs_no_rawlog 2 REGEX "^swba jobs: error: no rawlog given" ARGS jobs --out ${_out}/jobs_no_rawlog)
swba_cli_case(nees_bad_runs 2 REGEX "^swba nees: error: --runs must be >= 1" ARGS nees --runs 0 --out ${_out}/nees_bad_runs)
swba_cli_case(merge_not_a_sweep 1 REGEX "^swba merge: error: sweep manifest '/nonexistent/sweep.json': file does not exist"
  ARGS merge /nonexistent)
swba_cli_case(simulate_bad_ini 1 REGEX "^swba simulate: error: simul-landmarks INI '[^']*swba_run.ini': no \\[Params\\] random_seed"
  ARGS simulate ${CMAKE_SOURCE_DIR}/share/config/swba_run.ini --out ${_out}/simulate_bad_ini)

# SWBA_SIMD (swba/linear/rank_update.h): the version names the kernel; a level that does not exist, or
# that this machine lacks, fails before any work with one line; the baseline is always there.
add_test(NAME runapp.e2e.version_names_kernel
  COMMAND ${CMAKE_COMMAND} "-DCMD=$<TARGET_FILE:swba>|version" -DEXPECT_RC=0
          "-DREGEX=^swba [0-9.]+ \\(MRPT [0-9.]+, Eigen [0-9.]+; rank-update kernel (baseline<OR>avx2<OR>avx512)\\)\n$" -P ${_check})
add_test(NAME runapp.e2e.simd_baseline
  COMMAND ${CMAKE_COMMAND} "-DCMD=${CMAKE_COMMAND}|-E|env|SWBA_SIMD=baseline|$<TARGET_FILE:swba>|version" -DEXPECT_RC=0
          "-DREGEX=rank-update kernel baseline\\)" -P ${_check})
add_test(NAME runapp.e2e.simd_unknown
  COMMAND ${CMAKE_COMMAND} "-DCMD=${CMAKE_COMMAND}|-E|env|SWBA_SIMD=sse9|$<TARGET_FILE:swba>|run|--max-steps|5|--out|${_out}/simd_unknown"
          -DEXPECT_RC=1 "-DREGEX=^swba run: error: unknown SWBA_SIMD level 'sse9' \\(expected baseline, avx2 or avx512\\)\n$"
          -DCLEAN_DIR=${_out}/simd_unknown -P ${_check})
# A reused output directory: the earlier run's files are removed, never mixed with this run's.
add_test(NAME runapp.e2e.reused_out_dir
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/reused_out_dir.sh $<TARGET_FILE:swba> ${_out}/reused_out_dir)
set_tests_properties(runapp.e2e.reused_out_dir PROPERTIES PASS_REGULAR_EXPRESSION "OK: reused" TIMEOUT 120)

# evo users' inputs (doc/evaluation.md, "Coming from evo"): a TUM ground truth for swba run (the same
# figures as MRPT's path: the evo reference gt.tum holds its rows), evo's `ape tum REF EST` form and its
# underscore spellings; --save-results NAME.zip is refused with what to give instead; evo's other formats
# are named.
set(_evo_ref ${SWBA_DATA_DIR}/evo_reference)
swba_run_case(gt_tum 0 REGEX "\nwindow W=5 +5 +online +0\\.009153 +0\\.008715 +0\\.008263 +0\\.015426 +0\\.009713 "
  ARGS ${_demo} --gt ${_evo_ref}/gt_kf-slam_6D_demo.tum --max-steps 60 --windows 5 --no-ekf --no-batch --no-plots
       --out ${_out}/gt_tum)
swba_cli_case(evo_tum_form 0 REGEX "APE w.r.t. translation part \\(m\\)\n\\(not aligned\\)\n.*rmse\t0\\.016064\n"
  ARGS ape tum ${_evo_ref}/gt_kf-slam_6D_demo.tum ${_evo_ref}/ekf_kf-slam_6D_demo.tum)
swba_cli_case(evo_underscore_options 0 REGEX "RPE w.r.t. translation part \\(m\\)\nfor delta = 10 \\(frames\\) using all pairs"
  ARGS rpe tum ${_evo_ref}/gt_kf-slam_6D_demo.tum ${_evo_ref}/ekf_kf-slam_6D_demo.tum --t_max_diff 0.01 --delta 10 --all_pairs)
swba_cli_case(save_results_zip 2
  REGEX "^swba ape: error: --save-results writes a directory of plain files \\(JSON, CSV, TUM\\), not evo's \\.zip: give a directory \\('[^']*/results'\\)"
  ARGS ape ${_evo_ref}/gt_kf-slam_6D_demo.tum ${_evo_ref}/ekf_kf-slam_6D_demo.tum --save-results ${_out}/results.zip)
swba_cli_case(evo_kitti_form 2 REGEX "^swba ape: error: evo's 'kitti' format is not read: convert the trajectories to TUM first"
  ARGS ape kitti a.txt b.txt)
# A new user's whole walkthrough (tests/apps/new_user_walkthrough.sh): every subcommand on the shipped data, then
# malformed inputs, each with doc/cli.md's exit code (0, 2 a bad command line, 1 a bad input or failure)
# and the message naming what was wrong.
add_test(NAME apps.cli.new_user_walkthrough
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/new_user_walkthrough.sh $<TARGET_FILE:swba> ${_out}/new_user_walkthrough
          ${SWBA_MRPT_DATASETS} ${CMAKE_SOURCE_DIR})
set_tests_properties(apps.cli.new_user_walkthrough PROPERTIES PASS_REGULAR_EXPRESSION "OK: new-user walkthrough"
  FAIL_REGULAR_EXPRESSION "FAIL " TIMEOUT 300)

# test_run_nees.cpp tests swba run's consistency figures through the private header of modules/apps/src/run.
target_include_directories(swba_test_apps PRIVATE ${CMAKE_SOURCE_DIR}/modules/apps/src/run)

# swba simulate-imu refuses keyframe rates that leave no IMU reading between keyframes (swba run's IMU
# factors need two integration steps), naming the flags; fast odometry between pose priors is composed.
swba_cli_case(simulate_imu_pose_rate_at_imu_rate 2
  REGEX "^swba simulate-imu: error: --pose-rate 100 with --imu-rate 100 leaves fewer than two IMU intervals between keyframes, [^\n]*give at most --imu-rate / 2 = 50, or 0 for none"
  ARGS simulate-imu --duration 3 --pose-rate 100 --odometry-rate 100 --out ${_out}/simulate_imu_pose_rate_at_imu_rate)
swba_cli_case(simulate_imu_odometry_keyframes_at_imu_rate 2
  REGEX "^swba simulate-imu: error: --odometry-rate 100 with --imu-rate 100 leaves fewer than two IMU intervals"
  ARGS simulate-imu --duration 3 --pose-rate 0 --odometry-rate 100 --out ${_out}/simulate_imu_odometry_at_imu_rate)

# Solver commands (bal, pgo, directba, monoba): a bad value of an option is a usage error naming the flag
# (exit 2), never an internal field; a failed solve, or one with nothing to fit, exits 1 with one error line
# after the report; a result that is not finite is never written or reported as a success.
set(_solver_inputs ${CMAKE_CURRENT_BINARY_DIR}/solver_inputs)
file(MAKE_DIRECTORY ${_solver_inputs})
swba_cli_case(bal_unknown_loss 2
  REGEX "^swba bal: error: unknown loss 'bogus' \\(expected none, huber or cauchy\\) \\(see --help\\)\n$"
  ARGS bal ${_binary} --loss bogus)
swba_cli_case(bal_function_tolerance_negative 2 REGEX "^swba bal: error: --function-tolerance must be >= 0 \\(see --help\\)"
  ARGS bal ${_binary} --function-tolerance -1)
swba_cli_case(pgo_max_iterations_negative 2 REGEX "^swba pgo: error: --max-iterations must be >= 0 \\(see --help\\)"
  ARGS pgo ${_binary} --max-iterations -1)
swba_cli_case(pgo_threads_zero 2 REGEX "^swba pgo: error: --threads must be >= 1 \\(see --help\\)"
  ARGS pgo ${_binary} --threads 0)
swba_cli_case(pgo_initial_trust_region_zero 2
  REGEX "^swba pgo: error: --initial-trust-region must be in \\(0, 1e\\+16. \\(the maximum trust-region radius\\) \\(see --help\\)"
  ARGS pgo ${_binary} --initial-trust-region 0)
swba_cli_case(directba_sigma_zero 2 REGEX "^swba directba: error: --sigma must be a number > 0 \\(see --help\\)"
  ARGS directba ${SWBA_DATA_DIR}/directba --sigma 0)
swba_cli_case(directba_more_fixed_cameras_than_cameras 2
  REGEX "swba directba: error: --fixed-cameras 8 is more than the 7 cameras of '[^']*directba' \\(see --help\\)\n$"
  ARGS directba ${SWBA_DATA_DIR}/directba --fixed-cameras 8 -q)
swba_cli_case(monoba_max_iterations_negative 2 REGEX "^swba monoba: error: --max-iterations must be >= 0 \\(see --help\\)"
  ARGS monoba --max-iterations -1)
swba_cli_case(monoba_fix_zero 2 REGEX "^swba monoba: error: --fix 0 is out of range \\[1, 3\\] \\(number of cameras\\) \\(see --help\\)"
  ARGS monoba --fix 0)
# f = 1e300: the initial cost is not finite (FAILURE): the line on stderr (BalSolve.EveryFactorDropped… checks
# that a failed solve writes no solution).
file(WRITE ${_solver_inputs}/bal_huge_focal.txt "1 2 2\n0 0 1 1\n0 1 2 2\n0 0 0 0 0 -5 1e300 0 0\n0.1 0 0\n0 0.1 0\n")
swba_cli_case(bal_solver_failure_has_error_line 1
  REGEX "Change: +- \\(a cost is not finite\\)\n.*Termination: FAILURE \\(initial cost is not finite\\)\n.*swba bal: error: optimisation failed: initial cost is not finite\n$"
  ARGS bal ${_solver_inputs}/bal_huge_focal.txt -q)
# Every point on its camera's plane, every patch outside its image: no factor evaluable, nothing fitted.
file(WRITE ${_solver_inputs}/bal_points_on_camera_plane.txt "1 1 1\n0 0 1 1\n0 0 0 0 0 -5 500 0 0\n0 0 5\n")
swba_cli_case(bal_every_factor_dropped 1
  REGEX "Termination: FAILURE \\(every factor dropped at the initial values: nothing to fit\\)\n.*swba bal: error: optimisation failed: every factor dropped at the initial values: nothing to fit\n$"
  ARGS bal ${_solver_inputs}/bal_points_on_camera_plane.txt -q)
swba_cli_case(directba_every_factor_dropped 1
  REGEX "Factors +28826 \\(28826 dropped at the solution\\).*Termination: FAILURE \\(every factor dropped at the initial values: nothing to fit\\).*swba directba: error: optimisation failed: every factor dropped at the initial values: nothing to fit\n$"
  ARGS directba ${SWBA_DATA_DIR}/directba -q --border 300)
swba_cli_case(directba_synthetic_fail_has_error_line 1
  REGEX "Synthetic check: FAIL .*swba directba: error: synthetic check failed: the recovery misses its bounds"
  ARGS directba --synthetic -q --iterations 0)
# An empty or comment-only g2o file: the file named.
file(WRITE ${_solver_inputs}/pgo_empty.g2o "")
file(WRITE ${_solver_inputs}/pgo_comment_only.g2o "# only a comment\n")
foreach(_g empty comment_only)
  swba_cli_case(pgo_${_g}_file_named 1
    REGEX "^swba pgo: error: g2o file '[^']*pgo_${_g}.g2o': no vertices \\(no VERTEX_SE3:QUAT or VERTEX_SE2 line\\): nothing to optimise\n$"
    ARGS pgo ${_solver_inputs}/pgo_${_g}.g2o -q)
endforeach()
# A finite positive-definite information of 1e308 overflows the chordal initialisation: an error naming the
# method and the vertex before anything is written (G2oWriter.RefusesNonFiniteVertexValues: never a NaN graph).
file(WRITE ${_solver_inputs}/pgo_huge_information.g2o
  "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 2 0 0 1e308 0 0 1e308 0 1e308\n")
swba_cli_case(pgo_non_finite_initial_values 1
  REGEX "swba pgo: error: chordal initialisation gave a non-finite value to vertex 1 \\(x y theta = [-]?nan [-]?nan 0\\)"
  ARGS pgo ${_solver_inputs}/pgo_huge_information.g2o -q)
