# End-to-end: `swba directba` on the shipped 7-image set (share/data/directba) with the default options is
# golden.directba_dataset (tests/golden/tests.cmake: every printed figure, and the files it writes);
# the synthetic check exits 1 unless the ground truth is recovered (poses ≤ 1 mm / 0.05°, points ≤ 1 cm).
add_test(NAME directba.e2e_synthetic_check COMMAND $<TARGET_FILE:swba> directba --synthetic --quiet)
set_tests_properties(directba.e2e_synthetic_check PROPERTIES PASS_REGULAR_EXPRESSION "Synthetic check: PASS")
# Bad input: clear one-line errors, exit != 0.
add_test(NAME directba.e2e_missing_dir COMMAND $<TARGET_FILE:swba> directba /nonexistent/directba)
set_tests_properties(directba.e2e_missing_dir PROPERTIES
  PASS_REGULAR_EXPRESSION "error: /nonexistent/directba: directory does not exist")
add_test(NAME directba.e2e_file_not_dir COMMAND $<TARGET_FILE:swba> directba ${SWBA_DATA_DIR}/directba/poses.txt)
set_tests_properties(directba.e2e_file_not_dir PROPERTIES
  PASS_REGULAR_EXPRESSION "error: [^\n]*directba/poses.txt: is not a directory")
add_test(NAME directba.e2e_missing_dir_exit_code COMMAND $<TARGET_FILE:swba> directba /nonexistent/directba)
set_tests_properties(directba.e2e_missing_dir_exit_code PROPERTIES WILL_FAIL TRUE)
add_test(NAME directba.e2e_rejects_bad_sigma COMMAND $<TARGET_FILE:swba> directba ${SWBA_DATA_DIR}/directba --sigma -1)
set_tests_properties(directba.e2e_rejects_bad_sigma PROPERTIES WILL_FAIL TRUE)
add_test(NAME directba.e2e_requires_dir COMMAND $<TARGET_FILE:swba> directba)
set_tests_properties(directba.e2e_requires_dir PROPERTIES PASS_REGULAR_EXPRESSION "missing DIR")

# Out-of-buffer reads under AddressSanitizer in every run of the suite, the Release build's too. The
# normal build is not sanitized, so the photometric factor's tests (bilinear sampling, the border
# rule's never-read-outside sweep, Jacobians) are built a second time together with the code
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
