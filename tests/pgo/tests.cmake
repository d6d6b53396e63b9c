# End-to-end tests of `swba pgo` on shipped data.
set(_pgo_data ${SWBA_DATA_DIR}/posegraph)
add_test(NAME pgo.cli_smallGrid3D
  COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o -o ${CMAKE_CURRENT_BINARY_DIR}/pgo_smallGrid3D_out.g2o)
set_tests_properties(pgo.cli_smallGrid3D PROPERTIES
  PASS_REGULAR_EXPRESSION "Initial cost: .*Final cost: .*Wrote ")
add_test(NAME pgo.cli_intel_2d
  COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/intel.g2o --threads 2 -q)
set_tests_properties(pgo.cli_intel_2d PROPERTIES PASS_REGULAR_EXPRESSION "2D SE2.*Final cost: ")
add_test(NAME pgo.cli_bad_robust COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o --robust tukey)
set_tests_properties(pgo.cli_bad_robust PROPERTIES WILL_FAIL TRUE)
add_test(NAME pgo.cli_missing_file COMMAND $<TARGET_FILE:swba> pgo /nonexistent.g2o)
set_tests_properties(pgo.cli_missing_file PROPERTIES WILL_FAIL TRUE)
add_test(NAME pgo.cli_schur_rejected
  COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o --linear sparse-schur)
set_tests_properties(pgo.cli_schur_rejected PROPERTIES WILL_FAIL TRUE)
