// Default sanitizer options of swba_test_directba_asan (tests/directba/tests.cmake), compiled only into
// that executable: they apply to every run of it, including gtest_discover_tests' listing run.
// Leak detection needs ptrace, which some CI containers forbid; out-of-bounds detection does not.
extern "C" const char* __asan_default_options() { return "detect_leaks=0:abort_on_error=1"; }
extern "C" const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }
