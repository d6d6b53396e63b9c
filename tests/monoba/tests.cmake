# End-to-end tests of `swba monoba`.
add_test(NAME monoba.cli_demo COMMAND $<TARGET_FILE:swba> monoba)
set_tests_properties(monoba.cli_demo PROPERTIES
  PASS_REGULAR_EXPRESSION "Gauge: fixed \\(first 2 poses constant\\).*Initial cost: .*Final cost: .*Camera translations.*Point inverse depths.*camera 0 drift")
add_test(NAME monoba.cli_free_gauge COMMAND $<TARGET_FILE:swba> monoba --gauge free --seed 3)
set_tests_properties(monoba.cli_free_gauge PROPERTIES PASS_REGULAR_EXPRESSION "Gauge: free.*Final cost: ")
add_test(NAME monoba.cli_prior_gauge COMMAND $<TARGET_FILE:swba> monoba --gauge prior --prior-weight 1e6 --fix 1)
set_tests_properties(monoba.cli_prior_gauge PROPERTIES
  PASS_REGULAR_EXPRESSION "information 1e\\+06 \\* I on the first 1 pose\\).*Final cost: ")
add_test(NAME monoba.cli_sweep
  COMMAND $<TARGET_FILE:swba> monoba --sweep-prior-weights --points 10 --out ${CMAKE_CURRENT_BINARY_DIR}/monoba_sweep.txt)
set_tests_properties(monoba.cli_sweep PROPERTIES
  PASS_REGULAR_EXPRESSION "free .*fixed .*prior +0e\\+00.*prior +1e\\+10.*Wrote .*monoba_sweep.txt")

# Bad input: non-zero exit code and a one-line reason.
set(_monoba_errors
  "bad_gauge|--gauge|loose|unknown gauge 'loose'"
  "negative_weight|--gauge|prior|--prior-weight|-1|prior weight must be"
  "zero_cameras|--cameras|0|number of cameras must be"
  "zero_points|--points|0|number of points must be"
  "non_numeric_cameras|--cameras|three|cameras"
  "non_numeric_noise|--noise|abc|noise"
  "non_numeric_weight|--gauge|prior|--prior-weight|1e4x|prior-weight"
  "fix_too_large|--fix|4|--fix 4 is out of range .1, 3."
  "fix_zero|--fix|0|--fix 0 is out of range"
  "negative_noise|--noise|-0.1|noise must be"
  "fix_with_free|--gauge|free|--fix|2|--fix has no effect"
  "weight_without_prior|--prior-weight|10|--prior-weight needs --gauge prior")
foreach(_case ${_monoba_errors})
  string(REPLACE "|" ";" _parts "${_case}")
  list(GET _parts 0 _name)
  list(GET _parts -1 _regex)
  list(REMOVE_AT _parts 0 -1)
  string(REPLACE ";" "|" _args "${_parts}")
  add_test(NAME monoba.cli_error_${_name}
    COMMAND ${CMAKE_COMMAND} "-DCMD=$<TARGET_FILE:swba>|monoba|${_args}" "-DREGEX=${_regex}"
            -P ${CMAKE_CURRENT_LIST_DIR}/expect_error.cmake)
endforeach()
