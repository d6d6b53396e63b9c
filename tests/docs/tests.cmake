# Documentation checks (no build needed): links and anchors, no references to tickets or outside paths, C++
# blocks that are excerpts of the compiled examples, and
# every figure of a golden block (a fenced block after "<!-- golden: NAME -->") is in tests/golden/ref/NAME.txt
# and its command is golden.NAME's. check_docs.cmake says what is checked.
set(_docs_check ${CMAKE_CURRENT_LIST_DIR}/check_docs.cmake)
add_test(NAME docs.check COMMAND ${CMAKE_COMMAND} -DSRC=${CMAKE_SOURCE_DIR} -P ${_docs_check})
set_tests_properties(docs.check PROPERTIES LABELS docs)
# The check itself can fail: each page of selfcheck/ holds one fault it must find.
foreach(fault drifted_figure wrong_command dead_link dead_anchor ticket_reference outside_path no_worked_example
    code_not_in_example code_without_excerpt)
  add_test(NAME docs.self_check_${fault}
    COMMAND ${CMAKE_COMMAND} -DSRC=${CMAKE_SOURCE_DIR} -DDOCS=${CMAKE_CURRENT_LIST_DIR}/selfcheck/${fault}.md
            "-DWORKED_EXAMPLES=tests/docs/selfcheck/no_worked_example.md" -P ${_docs_check})
  set_tests_properties(docs.self_check_${fault} PROPERTIES LABELS docs WILL_FAIL TRUE)
endforeach()
# ... and passes a page with none (the faulty pages differ from it by their fault only).
add_test(NAME docs.self_check_clean
  COMMAND ${CMAKE_COMMAND} -DSRC=${CMAKE_SOURCE_DIR} -DDOCS=${CMAKE_CURRENT_LIST_DIR}/selfcheck/clean.md
          "-DWORKED_EXAMPLES=tests/docs/selfcheck/clean.md" -P ${_docs_check})
set_tests_properties(docs.self_check_clean PROPERTIES LABELS docs)
