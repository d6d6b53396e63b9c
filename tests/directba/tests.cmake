# End-to-end: `swba directba` on the course's 7-image set with the default options (≈ 10 s on a loaded
# 2-core machine): the initial figures, and the final cost below 5.3e5 with a per-pixel residual RMS
# below 24 gray levels (the figures of doc/directba.md; golden.directba_dataset pins them at the
# printed precision); and the synthetic check, which exits 1 unless the ground truth is recovered
# (poses ≤ 1 mm / 0.05°, points ≤ 1 cm).
set(directba_e2e_dir ${CMAKE_CURRENT_BINARY_DIR}/directba_e2e)
file(MAKE_DIRECTORY ${directba_e2e_dir})
add_test(NAME directba.e2e_course_data
  COMMAND $<TARGET_FILE:swba> directba ${SWBA_DATA_DIR}/directba --quiet
    --out ${directba_e2e_dir} --ply-final ${directba_e2e_dir}/final.ply)
set_tests_properties(directba.e2e_course_data PROPERTIES
  PASS_REGULAR_EXPRESSION "Initial cost: +7\\.2065[0-9]*e\\+05.*Final cost: +5\\.[0-2][0-9]*e\\+05.*Before: cost 7\\.20650[0-9]e\\+05, evaluated 24501, dropped 4325.*After: +cost 5\\.[0-2][0-9]*e\\+05, evaluated [0-9]+, dropped [0-9]+, per-pixel residual RMS 2[0-3]\\.[0-9]+ .*Wrote ${directba_e2e_dir}/poses_initial.tum")
add_test(NAME directba.e2e_synthetic_check COMMAND $<TARGET_FILE:swba> directba --synthetic --quiet)
set_tests_properties(directba.e2e_synthetic_check PROPERTIES PASS_REGULAR_EXPRESSION "Synthetic check: PASS")
# Bad input: clear one-line errors, exit != 0.
add_test(NAME directba.e2e_missing_dir COMMAND $<TARGET_FILE:swba> directba /nonexistent/directba)
set_tests_properties(directba.e2e_missing_dir PROPERTIES
  PASS_REGULAR_EXPRESSION "error: /nonexistent/directba/poses.txt: file not found")
add_test(NAME directba.e2e_missing_dir_exit_code COMMAND $<TARGET_FILE:swba> directba /nonexistent/directba)
set_tests_properties(directba.e2e_missing_dir_exit_code PROPERTIES WILL_FAIL TRUE)
add_test(NAME directba.e2e_rejects_bad_sigma COMMAND $<TARGET_FILE:swba> directba ${SWBA_DATA_DIR}/directba --sigma -1)
set_tests_properties(directba.e2e_rejects_bad_sigma PROPERTIES WILL_FAIL TRUE)
add_test(NAME directba.e2e_requires_dir COMMAND $<TARGET_FILE:swba> directba)
set_tests_properties(directba.e2e_requires_dir PROPERTIES PASS_REGULAR_EXPRESSION "missing DIR")

# Out-of-buffer reads under AddressSanitizer in every run of the suite (issue 7: "run under ASan in
# CI"). The normal build is not sanitized, so the photometric factor's tests (bilinear sampling, the
# border rule's never-read-outside sweep, Jacobians) are built a second time together with the code
# they exercise — modules/core and the photometric factor — with -fsanitize=address,undefined. Any
# read outside an image buffer aborts the test. Skipped when the whole build is sanitized already
# (SWBA_SANITIZE=ON runs every test under ASan) or when the compiler has no ASan runtime.
if(NOT SWBA_SANITIZE)
  include(CheckCXXSourceCompiles)
  set(CMAKE_REQUIRED_FLAGS "-fsanitize=address,undefined")
  set(CMAKE_REQUIRED_LINK_OPTIONS "-fsanitize=address,undefined")
  check_cxx_source_compiles("int main() { return 0; }" SWBA_HAVE_ASAN)
  unset(CMAKE_REQUIRED_FLAGS)
  unset(CMAKE_REQUIRED_LINK_OPTIONS)
  if(SWBA_HAVE_ASAN)
    file(GLOB _asan_core_srcs CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/modules/core/src/*.cpp)
    add_executable(swba_test_directba_asan ${CMAKE_CURRENT_LIST_DIR}/test_photometric_factor.cpp ${_asan_core_srcs}
      ${CMAKE_SOURCE_DIR}/modules/factors/src/photometric_patch.cpp ${CMAKE_CURRENT_LIST_DIR}/asan_options.cpp)
    target_include_directories(swba_test_directba_asan PRIVATE ${CMAKE_SOURCE_DIR}/modules/core/include
      ${CMAKE_SOURCE_DIR}/modules/factors/include)
    target_link_libraries(swba_test_directba_asan PRIVATE Eigen3::Eigen mrpt::poses GTest::gtest GTest::gtest_main
      swba_build_flags)
    target_compile_options(swba_test_directba_asan PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
      -fno-sanitize-recover=all)
    target_link_options(swba_test_directba_asan PRIVATE -fsanitize=address,undefined)
    gtest_discover_tests(swba_test_directba_asan TEST_PREFIX "directba_asan." DISCOVERY_TIMEOUT 60)
  endif()
endif()
