# End-to-end tests of `swba ape` / `swba rpe` (included from tests/CMakeLists.txt).
set(_evo ${SWBA_DATA_DIR}/evo_reference)
set(_gt ${_evo}/gt_kf-slam_6D_demo.tum)
set(_ekf ${_evo}/ekf_kf-slam_6D_demo.tum)
set(_data ${CMAKE_CURRENT_LIST_DIR}/data)
set(_check ${CMAKE_CURRENT_LIST_DIR}/run_and_check.cmake)
set(_out ${CMAKE_CURRENT_BINARY_DIR}/eval_e2e)

# evo's printed block (6 decimals, as evo prints them) and the saved JSON to 1e-9 relative.
function(swba_eval_evo_case name ref expected_rmse printed_rmse)
  set(args ${ARGN})
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;ape;${ref};${_ekf};${args}")
  add_test(NAME eval.e2e.${name}_printed
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DEXPECT_RC=0 "-DREGEX=\n      rmse\t${printed_rmse}\n" -P ${_check})
  string(REPLACE ";" "|" _cmd_save "$<TARGET_FILE:swba>;ape;${ref};${_ekf};${args};--save-results;${_out}/${name}")
  add_test(NAME eval.e2e.${name}_rmse_1e-9
    COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd_save}" -DEXPECT_RC=0 -DCLEAN_DIR=${_out}/${name}
            -DJSON_FILE=${_out}/${name}/ape_stats.json -DJSON_KEY=rmse -DEXPECTED=${expected_rmse}
            -DREL_TOL_INV=1000000000 -P ${_check})
endfunction()

set(_gt_full ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_ground_truth_robot_path.txt)
swba_eval_evo_case(ape_trans_not_aligned ${_gt} 0.0160637612904 0.016064)
swba_eval_evo_case(ape_trans_se3 ${_gt} 0.0140646580617 0.014065 -a)
swba_eval_evo_case(ape_trans_sim3 ${_gt} 0.0139984045934 0.013998 -a -s)
# The angle reference was computed from full-precision GT rotations: read the GT TUM file's source
# (the shipped gt_*.tum has 9-decimal quaternions, which move the angle rmse by 1.7e-9 relative).
swba_eval_evo_case(ape_angle_deg ${_gt_full} 0.227397461006 0.227397 -r angle_deg --ref-format mrpt-gt)
add_test(NAME eval.e2e.ape_angle_deg_tum_gt COMMAND $<TARGET_FILE:swba> ape ${_gt} ${_ekf} -r angle_deg)
set_tests_properties(eval.e2e.ape_angle_deg_tum_gt PROPERTIES PASS_REGULAR_EXPRESSION
  "^APE w.r.t. rotation angle \\(deg\\)\n\\(not aligned\\)\n\n.*\n      rmse\t0.227397\n")

# The whole layout of evo's block.
add_test(NAME eval.e2e.ape_layout COMMAND $<TARGET_FILE:swba> ape ${_gt} ${_ekf})
set_tests_properties(eval.e2e.ape_layout PROPERTIES PASS_REGULAR_EXPRESSION
  "^APE w.r.t. translation part \\(m\\)\n\\(not aligned\\)\n\n       max\t0.066243\n      mean\t0.013540\n    median\t[0-9.]+\n       min\t[0-9.]+\n      rmse\t0.016064\n       sse\t[0-9.]+\n       std\t[0-9.]+\n")
add_test(NAME eval.e2e.ape_sim3_title COMMAND $<TARGET_FILE:swba> ape ${_gt} ${_ekf} -a -s)
set_tests_properties(eval.e2e.ape_sim3_title PROPERTIES PASS_REGULAR_EXPRESSION "\\(with Sim\\(3\\) Umeyama alignment\\)")
add_test(NAME eval.e2e.rpe_layout COMMAND $<TARGET_FILE:swba> rpe ${_gt} ${_ekf} --delta 10)
set_tests_properties(eval.e2e.rpe_layout PROPERTIES PASS_REGULAR_EXPRESSION
  "^RPE w.r.t. translation part \\(m\\)\nfor delta = 10 \\(frames\\) using consecutive pairs\n\\(not aligned\\)\n\n       max\t")
# The MRPT ground-truth file read directly gives the same APE (to the TUM file's 9 decimals).
add_test(NAME eval.e2e.ape_mrpt_gt COMMAND $<TARGET_FILE:swba> ape
  ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_ground_truth_robot_path.txt ${_ekf} --ref-format mrpt-gt)
set_tests_properties(eval.e2e.ape_mrpt_gt PROPERTIES PASS_REGULAR_EXPRESSION "\n      rmse\t0.016064\n")

# --help documents every option.
add_test(NAME eval.e2e.ape_help COMMAND $<TARGET_FILE:swba> ape --help)
set_tests_properties(eval.e2e.ape_help PROPERTIES PASS_REGULAR_EXPRESSION
  "--ref-format.*--pose-relation.*--align.*--correct-scale.*--align-origin.*--t-max-diff.*--t-offset.*--save-results.*--plot")
add_test(NAME eval.e2e.rpe_help COMMAND $<TARGET_FILE:swba> rpe --help)
set_tests_properties(eval.e2e.rpe_help PROPERTIES PASS_REGULAR_EXPRESSION "--delta.*--all-pairs")

# Plots: images with gnuplot, a one-line note without it (PATH emptied); both exit 0.
add_test(NAME eval.e2e.ape_plot_without_gnuplot
  COMMAND ${CMAKE_COMMAND} -E env PATH=/nonexistent $<TARGET_FILE:swba> ape ${_gt} ${_ekf} --plot ${_out}/noplot)
set_tests_properties(eval.e2e.ape_plot_without_gnuplot PROPERTIES PASS_REGULAR_EXPRESSION "note: gnuplot not found")

# Malformed inputs: exit 1 with "<file>:<line>: <reason>"; empty / one-pose files never crash.
function(swba_eval_bad name regex)
  string(REPLACE ";" "|" _cmd "$<TARGET_FILE:swba>;${ARGN}")
  add_test(NAME eval.e2e.${name} COMMAND ${CMAKE_COMMAND} "-DCMD=${_cmd}" -DEXPECT_RC=1 "-DREGEX=${regex}" -P ${_check})
endfunction()
swba_eval_bad(bad_columns "bad_columns.tum:4: expected 8 columns" ape ${_gt} ${_data}/bad_columns.tum)
swba_eval_bad(bad_columns_as_ref "bad_columns.tum:4: expected 8 columns" ape ${_data}/bad_columns.tum ${_ekf})
swba_eval_bad(non_unit_quaternion "non_unit_quaternion.tum:3: quaternion is not unit" ape ${_gt} ${_data}/non_unit_quaternion.tum)
swba_eval_bad(zero_quaternion "zero_quaternion.tum:2: zero quaternion" ape ${_gt} ${_data}/zero_quaternion.tum)
swba_eval_bad(decreasing_time "decreasing_time.tum:3: time stamp 1 is before" ape ${_gt} ${_data}/decreasing_time.tum)
swba_eval_bad(non_finite "non_finite.tum:2: column 2 \\(x\\) is not finite" ape ${_gt} ${_data}/non_finite.tum)
swba_eval_bad(not_a_number "not_a_number.tum:3: column 2 \\(x\\) is not a number" ape ${_gt} ${_data}/not_a_number.tum)
swba_eval_bad(bad_mrpt_gt "bad_mrpt_gt.txt:3: expected 6 columns" ape ${_data}/bad_mrpt_gt.txt ${_ekf} --ref-format mrpt-gt)
swba_eval_bad(directory_as_file "data: is a directory" ape ${_gt} ${_data})
swba_eval_bad(missing_file "does_not_exist.tum: cannot open" ape ${_gt} ${_data}/does_not_exist.tum)
swba_eval_bad(empty_file "empty.tum: no poses" ape ${_gt} ${_data}/empty.tum)
swba_eval_bad(comments_only_file "comments_only.tum: no poses" ape ${_data}/comments_only.tum ${_ekf})
swba_eval_bad(no_matching_stamps "no matching time stamps" ape ${_gt} ${_data}/one_pose.tum --t-offset 1000)
swba_eval_bad(rpe_one_pose "RPE needs at least" rpe ${_data}/one_pose.tum ${_data}/one_pose.tum)
swba_eval_bad(sim3_one_pose "Degenerate covariance rank, Umeyama alignment is not possible" ape ${_data}/one_pose.tum ${_data}/one_pose.tum -a -s)
swba_eval_bad(se3_one_pose "Degenerate covariance rank, Umeyama alignment is not possible" ape ${_data}/one_pose.tum ${_data}/one_pose.tum -a)
add_test(NAME eval.e2e.ape_one_pose COMMAND $<TARGET_FILE:swba> ape ${_data}/one_pose.tum ${_data}/one_pose.tum)
set_tests_properties(eval.e2e.ape_one_pose PROPERTIES PASS_REGULAR_EXPRESSION "\n      rmse\t0.000000\n")
# Bad arguments: a one-line reason, exit != 0.
add_test(NAME eval.e2e.bad_relation COMMAND $<TARGET_FILE:swba> ape ${_gt} ${_ekf} -r translation)
set_tests_properties(eval.e2e.bad_relation PROPERTIES WILL_FAIL TRUE)
add_test(NAME eval.e2e.bad_delta COMMAND $<TARGET_FILE:swba> rpe ${_gt} ${_ekf} --delta 0)
set_tests_properties(eval.e2e.bad_delta PROPERTIES WILL_FAIL TRUE)
