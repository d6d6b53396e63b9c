# Packaging tests: the build tree installs into a temporary prefix, the stand-alone project
# examples/ is configured and built against that prefix with find_package(swba), and its program
# (the window estimator fed CActionCollection/CSensoryFrame pairs through swba/estimators/mrpt_adapter.h)
# must give exactly `swba run`'s trajectory on kf-slam_6D_demo at the same settings.
# Plus: every public header compiles on its own (one generated translation unit per header, built
# with the module's own usage requirements and -Werror flags) and exposes no internal header.
#
#   install.install_package          cmake --install <build> --prefix <tmp>; exported targets carry no
#                                      build-only flags (-W*, -Werror, sanitizers, swba_build_flags)
#   install.public_headers           installed header tree == modules/*/include; includes only swba/,
#                                      MRPT, Eigen and standard headers (no src/, CHOLMOD, OpenMP)
#   install.build_example            configure + build examples/ against the prefix
#   install.swba_run_reference       swba run --windows W --no-ekf --no-batch on kf-slam_6D_demo
#   install.example_matches_swba_run the example at the same W: final pose and whole online and lagged
#                                      trajectories equal swba run's (TUM text, 9 decimals)
set(SWBA_INSTALL_TEST_DIR ${CMAKE_CURRENT_BINARY_DIR}/install_test)
set(SWBA_INSTALL_TEST_WINDOW 5 CACHE STRING "Window size of install.example_matches_swba_run")
set(SWBA_INSTALL_TEST_STEPS 0 CACHE STRING "Steps of install.example_matches_swba_run (0 = the whole rawlog)")

add_test(NAME install.install_package
  COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${CMAKE_BINARY_DIR} -DPREFIX=${SWBA_INSTALL_TEST_DIR}/prefix
    "-DMODULES=${SWBA_MODULES}" -DSANITIZE=${SWBA_SANITIZE} -P ${CMAKE_CURRENT_LIST_DIR}/install_package.cmake)
set_tests_properties(install.install_package PROPERTIES FIXTURES_SETUP swba_installed TIMEOUT 120)

add_test(NAME install.public_headers
  COMMAND ${CMAKE_COMMAND} -DPREFIX=${SWBA_INSTALL_TEST_DIR}/prefix -DSOURCE_DIR=${CMAKE_SOURCE_DIR}
    -P ${CMAKE_CURRENT_LIST_DIR}/check_public_headers.cmake)
set_tests_properties(install.public_headers PROPERTIES FIXTURES_REQUIRED swba_installed TIMEOUT 60)

add_test(NAME install.build_example
  COMMAND ${CMAKE_COMMAND} -DPREFIX=${SWBA_INSTALL_TEST_DIR}/prefix -DSOURCE=${CMAKE_SOURCE_DIR}/examples
    -DBINARY=${SWBA_INSTALL_TEST_DIR}/examples-build -DGENERATOR=${CMAKE_GENERATOR}
    -DCXX=${CMAKE_CXX_COMPILER} -DBUILD_TYPE=${CMAKE_BUILD_TYPE}
    -P ${CMAKE_CURRENT_LIST_DIR}/build_example.cmake)
set_tests_properties(install.build_example PROPERTIES FIXTURES_REQUIRED swba_installed
  FIXTURES_SETUP swba_example_built TIMEOUT 300)

# swba run at the same settings, independent of the install: runs while the example is installed and built.
add_test(NAME install.swba_run_reference
  COMMAND ${CMAKE_COMMAND} -DMODE=swba_run -DSWBA=$<TARGET_FILE:swba>
    -DRAWLOG=${SWBA_MRPT_DATASETS}/kf-slam_6D_demo.rawlog -DWINDOW=${SWBA_INSTALL_TEST_WINDOW}
    -DSTEPS=${SWBA_INSTALL_TEST_STEPS} -DOUT=${SWBA_INSTALL_TEST_DIR}/compare
    -P ${CMAKE_CURRENT_LIST_DIR}/compare_with_swba_run.cmake)
set_tests_properties(install.swba_run_reference PROPERTIES FIXTURES_SETUP swba_run_reference TIMEOUT 300)

add_test(NAME install.example_matches_swba_run
  COMMAND ${CMAKE_COMMAND} -DMODE=example -DEXAMPLE=${SWBA_INSTALL_TEST_DIR}/examples-build/swba_online_slam
    -DRAWLOG=${SWBA_MRPT_DATASETS}/kf-slam_6D_demo.rawlog -DWINDOW=${SWBA_INSTALL_TEST_WINDOW}
    -DSTEPS=${SWBA_INSTALL_TEST_STEPS} -DOUT=${SWBA_INSTALL_TEST_DIR}/compare
    -P ${CMAKE_CURRENT_LIST_DIR}/compare_with_swba_run.cmake)
set_tests_properties(install.example_matches_swba_run PROPERTIES
  FIXTURES_REQUIRED "swba_example_built;swba_run_reference" TIMEOUT 300)

# One translation unit per public header, generated at configure time: `#include <swba/m/h.h>` twice
# (include guard) and nothing else, compiled against swba::<m> only (so a header that needs a
# private dependency of its module, or another module's header its module does not depend on,
# fails) with the project's warning flags. Part of the normal build (target swba_header_check).
# With SWBA_PCH (the sanitizer build) they parse the precompiled system headers of their own host: a
# header's missing system include is then the plain build's to report (`./dev.sh run`), a missing swba
# include or module dependency still fails here.
add_custom_target(swba_header_check ALL)
swba_add_pch_host(swba_pch_header_checks)
get_property(_swba_module_dirs GLOBAL PROPERTY SWBA_MODULE_INCLUDE_DIRS)
foreach(_entry ${_swba_module_dirs})
  string(REPLACE "=" ";" _pair "${_entry}")
  list(GET _pair 0 _module)
  list(GET _pair 1 _incdir)
  file(GLOB_RECURSE _headers CONFIGURE_DEPENDS ${_incdir}/swba/*.h)
  set(_tus "")
  foreach(_h ${_headers})
    file(RELATIVE_PATH _rel ${_incdir} ${_h})
    string(MAKE_C_IDENTIFIER "${_rel}" _id)
    set(_tu ${CMAKE_CURRENT_BINARY_DIR}/header_check/${_id}.cpp)
    file(CONFIGURE OUTPUT ${_tu} CONTENT
      "// Generated by tests/install/tests.cmake: <${_rel}> must compile on its own.\n#include <${_rel}>\n#include <${_rel}>\n")
    list(APPEND _tus ${_tu})
  endforeach()
  if(_tus)
    add_library(swba_header_check_${_module} OBJECT ${_tus})
    set_target_properties(swba_header_check_${_module} PROPERTIES UNITY_BUILD OFF)  # one header per TU
    target_link_libraries(swba_header_check_${_module} PRIVATE swba::${_module} swba_build_flags)
    swba_target_pch(swba_header_check_${_module} REUSE_FROM swba_pch_header_checks)
    add_dependencies(swba_header_check swba_header_check_${_module})
  endif()
endforeach()

# The example shows what an online application needs beyond the poses: the landmark each reading was
# associated with (here on readings without IDs) and the landmarks' marginal covariances.
add_test(NAME install.example_shows_association_and_covariances
  COMMAND ${SWBA_INSTALL_TEST_DIR}/examples-build/swba_online_slam ${SWBA_MRPT_DATASETS}/kf-slam_6D_demo_DA.rawlog
          --window 10 --print-every 100)
set_tests_properties(install.example_shows_association_and_covariances PROPERTIES FIXTURES_REQUIRED swba_example_built
  PASS_REGULAR_EXPRESSION "step   99: [^\n]*\n +readings -> landmarks: 0->[0-9]+ 1->[0-9]+.*landmark covariances: 20 landmarks, the least certain is [0-9]+ \\(largest std 0\\.0[0-9]+ m\\)"
  TIMEOUT 120)
# The evaluation example on evo's reference trajectories: evo's block (the golden figure of swba ape) and its files.
add_test(NAME install.example_evaluate
  COMMAND ${SWBA_INSTALL_TEST_DIR}/examples-build/swba_evaluate ${SWBA_DATA_DIR}/evo_reference/gt_kf-slam_6D_demo.tum
          ${SWBA_DATA_DIR}/evo_reference/ekf_kf-slam_6D_demo.tum ${SWBA_INSTALL_TEST_DIR}/evaluate)
set_tests_properties(install.example_evaluate PROPERTIES FIXTURES_REQUIRED swba_example_built
  PASS_REGULAR_EXPRESSION "APE w.r.t. translation part \\(m\\)\n\\(not aligned\\)\n.*rmse\t0\\.016[0-9]*\n.*RPE w.r.t. translation part"
  TIMEOUT 120)
