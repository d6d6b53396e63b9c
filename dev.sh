#!/usr/bin/env bash
# swba developer entry point: installs missing Debian packages, configures, builds, then
#   ./dev.sh run [swba run options]   run the main job (swba run on the default rawlog)
#   ./dev.sh test                     the whole suite (what CI runs): test-release, test-asan, fuzz-smoke
#   ./dev.sh test-release             the suite through ctest on the Release build (build/)
#   ./dev.sh test-asan                the suite under -fsanitize=address,undefined with leak detection
#                                     (build-asan/; suppressions: tests/lsan.supp)
#   ./dev.sh fuzz-smoke               every libFuzzer harness for SWBA_FUZZ_SMOKE_SECONDS (default 10)
#                                     (build-fuzz/, clang; doc/fuzzing.md)
#   ./dev.sh build                    only install dependencies and build
#   ./dev.sh swba <command> [...]     build, then run any swba subcommand
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-run}
[ $# -gt 0 ] && shift

./scripts/install-deps.sh

jobs=$(nproc 2>/dev/null || echo 2)
build() {  # build <dir> [--target T] <extra cmake args...>
	local dir=$1
	shift
	local target=()
	if [ "${1:-}" = "--target" ]; then
		target=(--target "$2")
		shift 2
	fi
	cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DSWBA_WERROR=ON "$@" >/dev/null
	cmake --build "$dir" -j "$jobs" "${target[@]}"
}

# Extra arguments of `test` go to ctest in both suites.
test_release() {
	build build
	ctest --test-dir build --output-on-failure -j "$jobs" "$@"
}
test_asan() {
	build build-asan -DSWBA_SANITIZE=ON -DSWBA_BUILD_BENCH=OFF
	ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0" \
		ctest --test-dir build-asan --output-on-failure -j "$jobs" "$@"
}
fuzz_smoke() {
	FUZZ_BUILD_JOBS=$jobs scripts/fuzz-campaign.sh "${SWBA_FUZZ_SMOKE_SECONDS:-10}"
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
	stage "release suite" test_release "$@"
	stage "sanitizer suite" test_asan "$@"
	stage "fuzz smoke" fuzz_smoke
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
build)
	build build
	;;
swba)
	build build --target swba
	exec ./build/apps/swba/swba "$@"
	;;
*)
	echo "usage: ./dev.sh run|test|test-release|test-asan|fuzz-smoke|build|swba <command> [...]" >&2
	exit 2
	;;
esac
