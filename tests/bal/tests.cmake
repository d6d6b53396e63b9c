# End-to-end: `swba bal` on the 1800-point shrink of Ladybug 49-7776 prints the summary and writes
# PLY files whose vertex count is cameras + points (49 + 1800), and a BAL file that reads back.
set(bal_e2e_dir ${CMAKE_CURRENT_BINARY_DIR}/bal_e2e)
file(MAKE_DIRECTORY ${bal_e2e_dir})
add_test(NAME bal.e2e_shrink_solve
  COMMAND $<TARGET_FILE:swba> bal ${SWBA_DATA_DIR}/bal/bal-ladybug-problem-49-7776-pre-shrink-1800.txt
    --threads 2 --max-iterations 20 --linear sparse-schur
    --ply-initial ${bal_e2e_dir}/initial.ply --ply-final ${bal_e2e_dir}/final.ply
    --write-problem ${bal_e2e_dir}/solution.txt)
set_tests_properties(bal.e2e_shrink_solve PROPERTIES
  PASS_REGULAR_EXPRESSION "Initial cost: +[0-9.e+]+.*Final cost: +[0-9.e+]+"
  FIXTURES_SETUP bal_e2e)
add_test(NAME bal.e2e_ply_vertex_counts
  COMMAND ${CMAKE_COMMAND} -DPLY_FILES=${bal_e2e_dir}/initial.ply;${bal_e2e_dir}/final.ply -DEXPECTED=1849
    -P ${CMAKE_CURRENT_LIST_DIR}/check_ply.cmake)
set_tests_properties(bal.e2e_ply_vertex_counts PROPERTIES FIXTURES_REQUIRED bal_e2e)
add_test(NAME bal.e2e_written_problem_solves
  COMMAND $<TARGET_FILE:swba> bal ${bal_e2e_dir}/solution.txt --max-iterations 0 --quiet)
set_tests_properties(bal.e2e_written_problem_solves PROPERTIES
  FIXTURES_REQUIRED bal_e2e PASS_REGULAR_EXPRESSION "49 cameras, 1800 points, 10863 observations")
# Bad input: a truncated file is rejected with its line; a bad option with a one-line reason.
add_test(NAME bal.e2e_rejects_missing_file COMMAND $<TARGET_FILE:swba> bal /nonexistent/problem.txt)
set_tests_properties(bal.e2e_rejects_missing_file PROPERTIES WILL_FAIL TRUE)
add_test(NAME bal.e2e_rejects_bad_linear_solver
  COMMAND $<TARGET_FILE:swba> bal ${SWBA_DATA_DIR}/bal/bal-ladybug-problem-49-7776-pre-shrink-1800.txt --linear qr)
set_tests_properties(bal.e2e_rejects_bad_linear_solver PROPERTIES WILL_FAIL TRUE)
