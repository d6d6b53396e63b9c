#!/usr/bin/env bash
# swba developer entry point: installs missing Debian packages, configures, builds, then
#   ./dev.sh run [swba run options]   run the main job (swba run on the default rawlog)
#   ./dev.sh test                     the whole suite (what CI runs): test-asan, fuzz-smoke, test-budget
#   ./dev.sh test-release             the suite through ctest on the Release build (build/)
#   ./dev.sh test-asan                the suite under -fsanitize=address,undefined with leak detection
#                                     (build-asan/: clang, unity build, also the libFuzzer harnesses;
#                                     suppressions: tests/lsan.supp)
#   ./dev.sh fuzz-smoke               every libFuzzer harness of build-asan/ for SWBA_FUZZ_SMOKE_SECONDS
#                                     (default 5; doc/fuzzing.md)
#   ./dev.sh test-budget              the memory-budget tests, which need a build without ASan (build-budget/)
#   ./dev.sh build                    only install dependencies and build
#   ./dev.sh swba <command> [...]     build, then run any swba subcommand
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-run}
[ $# -gt 0 ] && shift

./scripts/install-deps.sh

jobs=$(nproc 2>/dev/null || echo 2)
build() {  # build <dir> [--target T]... [extra cmake args...]
	local dir=$1
	shift
	local targets=()
	while [ "${1:-}" = "--target" ]; do
		targets+=(--target "$2")
		shift 2
	done
	cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DSWBA_WERROR=ON "$@" >/dev/null
	cmake --build "$dir" -j "$jobs" "${targets[@]}"
}

# The sanitizer build: clang (UBSan's checks differ from GCC's; it compiles the sanitized code about
# twice as fast), a unity build (the MRPT/Eigen headers parsed once per batch of sources), line tables
# for the reports, the libFuzzer harnesses with coverage of the readers' modules (the smoke's), and the
# system headers precompiled (SWBA_PCH: about 3.5 s of each unity source's parse).
# UBSan checks swba's own code, not the system headers (cmake/ubsan-ignorelist.txt); ASan checks all.
# Ninja starts a module's sources while the modules it links are still compiling (make waits for them, and
# one core idles behind the largest unity source of each module), and lld links in 60 % of ld's time.
build_clang() {  # build_clang <dir> [--target T]... [extra cmake args...]: the clang trees' common flags
	CC=clang-14 CXX=clang++-14 build "$@" -G Ninja -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DCMAKE_UNITY_BUILD=ON
}
build_asan() {
	if [ -f build-asan/CMakeCache.txt ] && ! { grep -q "^CMAKE_CXX_COMPILER:.*clang" build-asan/CMakeCache.txt &&
		grep -q "^CMAKE_GENERATOR:INTERNAL=Ninja" build-asan/CMakeCache.txt; }; then
		rm -rf build-asan  # configured with another compiler or generator by an older dev.sh
	fi
	build_clang build-asan -DCMAKE_CXX_FLAGS=-gline-tables-only -DSWBA_SANITIZE=ON -DSWBA_FUZZ=ON \
		"-DSWBA_FUZZ_COVERAGE=core;io;eval;apps" -DSWBA_BUILD_BENCH=OFF -DSWBA_PCH=ON
}

# ctest runs one test per core, so an OpenMP worker that spins while it waits takes its core from the
# other test; in the sanitizer build (clang's libomp beside MRPT's libgomp) the idle workers' spinning
# was a third of a window run's CPU time (doc/benchmarks/ci.md). Idle workers sleep: the suites gain, one
# run's wall time does not change (measured on mrclam6_r5).
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}

# Extra arguments of `test` go to ctest in the sanitizer suite.
test_release() {
	build build
	ctest --test-dir build --output-on-failure -j "$jobs" "$@"
}
# ASan keeps freed blocks in a quarantine (256 MB by default) before reusing them, so that a use after
# free finds poisoned memory; with it the allocator keeps touching fresh pages, which cost a sanitized
# `swba run` a quarter of its time (page faults, memsets). 32 MB still catches a use after free unless
# more than 32 MB of other blocks were freed in between (doc/benchmarks/ci.md); scripts/fuzz-campaign.sh
# keeps the default.
test_asan() {
	build_asan
	ASAN_OPTIONS=detect_leaks=1:quarantine_size_mb=32 LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0" \
		ctest --test-dir build-asan --output-on-failure -j "$jobs" "$@"
}
# Every libFuzzer harness build-asan/ has, in two halves side by side (each harness runs on one core).
fuzz_smoke() {
	[ -x build-asan/fuzz/swba_fuzz_rawlog ] || build_asan
	local s=${SWBA_FUZZ_SMOKE_SECONDS:-5} rc1=0 rc2=0 f r
	local halves=("" "")
	for f in build-asan/fuzz/swba_fuzz_*; do
		r=${f##*/swba_fuzz_}
		[[ -f $f && -x $f && $r != replay_* ]] || continue  # executables only, not the replays
		halves[0]+=" $r"
		halves=("${halves[1]}" "${halves[0]}")  # alternate
	done
	if [ -z "${halves[0]}${halves[1]}" ]; then
		echo "dev.sh: no libFuzzer harness in build-asan/fuzz/" >&2
		return 1
	fi
	# fuzz-campaign.sh with no reader named runs them all: a half with none is not started.
	local p1=""
	# shellcheck disable=SC2086  # the halves are word lists of reader names
	[ -n "${halves[0]}" ] && { FUZZ_NO_BUILD=1 FUZZ_BUILD_DIR=build-asan scripts/fuzz-campaign.sh "$s" ${halves[0]} & p1=$!; }
	# shellcheck disable=SC2086
	[ -n "${halves[1]}" ] && { FUZZ_NO_BUILD=1 FUZZ_BUILD_DIR=build-asan scripts/fuzz-campaign.sh "$s" ${halves[1]} || rc2=$?; }
	[ -z "$p1" ] || wait "$p1" || rc1=$?
	[ "$rc1" -eq 0 ] && [ "$rc2" -eq 0 ]
}
# ASan reserves terabytes of address space, so read_rawlog's memory budget (an RLIMIT_AS cap) cannot be
# tested in build-asan/, where those tests skip themselves; they run in build-budget/, without
# sanitizers (clang, unity build and precompiled headers: the stage's two modules build in half of
# GCC's time; `./dev.sh test-release` runs them with GCC in build/ too).
test_budget() {
	build_clang build-budget --target swba_test_core_budget --target swba_test_io_budget -DSWBA_BUILD_BENCH=OFF \
		-DSWBA_PCH=ON
	ctest --test-dir build-budget --output-on-failure -j "$jobs" -R 'MemoryBudget'
}
stage() {  # stage <name> <function> [args...]: runs it and prints its wall time
	local name=$1 t0
	shift
	t0=$(date +%s)
	echo "== dev.sh: $name" >&2
	"$@"
	echo "== dev.sh: $name passed in $(($(date +%s) - t0)) s" >&2
}

case "$mode" in
run)
	build build --target swba
	exec ./build/apps/swba/swba run "$@"
	;;
test)
	t_all=$(date +%s)
	stage "sanitizer suite" test_asan "$@"
	stage "fuzz smoke" fuzz_smoke
	stage "memory-budget tests (no sanitizers)" test_budget
	echo "== dev.sh: all passed in $(($(date +%s) - t_all)) s" >&2
	;;
test-release)
	test_release "$@"
	;;
test-asan)
	test_asan "$@"
	;;
fuzz-smoke)
	fuzz_smoke
	;;
test-budget)
	test_budget
	;;
build)
	build build
	;;
swba)
	build build --target swba
	exec ./build/apps/swba/swba "$@"
	;;
*)
	echo "usage: ./dev.sh run|test|test-release|test-asan|fuzz-smoke|test-budget|build|swba <command> [...]" >&2
	exit 2
	;;
esac
