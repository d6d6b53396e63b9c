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
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/pgo_bad_number.g2o
  "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\nEDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1x\n")
add_test(NAME pgo.cli_malformed_file_names_line
  COMMAND $<TARGET_FILE:swba> pgo ${CMAKE_CURRENT_BINARY_DIR}/pgo_bad_number.g2o)
set_tests_properties(pgo.cli_malformed_file_names_line PROPERTIES
  PASS_REGULAR_EXPRESSION "error: .*pgo_bad_number.g2o:3: EDGE_SE3:QUAT: field 30 \\('1x'\\) is not a finite number")
add_test(NAME pgo.cli_init_odometry
  COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o --init odometry -q)
set_tests_properties(pgo.cli_init_odometry PROPERTIES
  PASS_REGULAR_EXPRESSION "Initialisation odometry: 1 component.*Final cost: ")
add_test(NAME pgo.cli_init_chordal_default
  COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/intel.g2o -q)
set_tests_properties(pgo.cli_init_chordal_default PROPERTIES
  PASS_REGULAR_EXPRESSION "Initialisation chordal: 1 component.*Final cost: ")
add_test(NAME pgo.cli_bad_init COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o --init spanning)
set_tests_properties(pgo.cli_bad_init PROPERTIES WILL_FAIL TRUE)
add_test(NAME pgo.cli_bad_initial_trust_region
  COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o --initial-trust-region 0)
set_tests_properties(pgo.cli_bad_initial_trust_region PROPERTIES WILL_FAIL TRUE)
# --information: an indefinite loop-closure information (tests/pgo/data/square_indefinite_se2.g2o, line 11)
# is refused by default with file:line and the hint, repaired and counted with `repair`.
set(_indefinite ${CMAKE_CURRENT_LIST_DIR}/data/square_indefinite_se2.g2o)
add_test(NAME pgo.cli_indefinite_information_refused COMMAND $<TARGET_FILE:swba> pgo ${_indefinite} -q)
set_tests_properties(pgo.cli_indefinite_information_refused PROPERTIES PASS_REGULAR_EXPRESSION
  "square_indefinite_se2.g2o:11: EDGE_SE2: information matrix is not positive definite \\(smallest eigenvalue -200\\); use --information repair to replace it by the nearest positive-definite matrix")
add_test(NAME pgo.cli_indefinite_information_repaired
  COMMAND $<TARGET_FILE:swba> pgo ${_indefinite} --information repair -q)
set_tests_properties(pgo.cli_indefinite_information_repaired PROPERTIES PASS_REGULAR_EXPRESSION
  "repaired 1 of 4 edge information matrices.*Termination: CONVERGENCE")
add_test(NAME pgo.cli_bad_information COMMAND $<TARGET_FILE:swba> pgo ${_pgo_data}/smallGrid3D.g2o --information clip)
set_tests_properties(pgo.cli_bad_information PROPERTIES WILL_FAIL TRUE)
