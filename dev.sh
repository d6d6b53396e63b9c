#!/usr/bin/env bash
# swba developer entry point: installs missing Debian packages, configures, builds, then
#   ./dev.sh run [swba run options]   run the main job (swba run on the default rawlog)
#   ./dev.sh test                     run the whole test suite through ctest (what CI runs)
#   ./dev.sh test-asan                the suite under -fsanitize=address,undefined (build-asan/)
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

case "$mode" in
run)
	build build --target swba
	exec ./build/apps/swba/swba run "$@"
	;;
test)
	build build
	exec ctest --test-dir build --output-on-failure -j "$jobs" "$@"
	;;
test-asan)
	build build-asan -DSWBA_SANITIZE=ON -DSWBA_BUILD_BENCH=OFF
	ASAN_OPTIONS=detect_leaks=0 exec ctest --test-dir build-asan --output-on-failure -j "$jobs" "$@"
	;;
build)
	build build
	;;
swba)
	build build --target swba
	exec ./build/apps/swba/swba "$@"
	;;
*)
	echo "usage: ./dev.sh run|test|test-asan|build|swba <command> [...]" >&2
	exit 2
	;;
esac
