#!/usr/bin/env bash
# Fuzzing campaign over swba's readers (doc/fuzzing.md).
#   scripts/fuzz-campaign.sh [SECONDS] [READER...]
# SECONDS per harness (default 30: a smoke run CI can afford); READERs among
# tum ground_truth g2o bal ini rawlog observation_rawlog directba (default: all, one after the other).
# Configures and builds build-fuzz/ with clang (libFuzzer + ASan/UBSan), then runs each harness
# nice'd on one core in libFuzzer's fork mode (-fork=1: one worker at a time, restarted after an
# out-of-memory or timeout input so that those are counted instead of ending the run; a crash ends it;
# every failing input is triaged after the run — its sanitizer summary and the first frame in MRPT or
# swba — see doc/fuzzing.md).
# Each harness works on build-fuzz/corpus-work/<reader>/ (seeded from fuzz/corpus/<reader>/ and
# fuzz/regressions/<reader>/, which are only read); failing inputs land in build-fuzz/findings/<reader>/.
# Prints per harness: executions, exec/s, coverage, findings; exit status 1 if any harness had a finding.
# Environment: FUZZ_EXTRA_ARGS (more libFuzzer flags), FUZZ_BUILD_JOBS (default 2), FUZZ_NO_BUILD=1
# (run the binaries already built without configuring or building), FUZZ_BUILD_DIR (the build tree, default
# build-fuzz/; ./dev.sh's smoke uses build-asan/, whose harnesses have coverage of the readers' modules
# only), FUZZ_SANITIZERS (default address,undefined; e.g. "undefined" builds build-fuzz-undefined/).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-30}
[ $# -gt 0 ] && shift
readers=("$@")
[ ${#readers[@]} -eq 0 ] && readers=(tum ground_truth g2o bal ini rawlog observation_rawlog directba)

sanitizers=${FUZZ_SANITIZERS:-address,undefined}
build=build-fuzz
[ "$sanitizers" != address,undefined ] && build=build-fuzz-${sanitizers//,/-}
build=${FUZZ_BUILD_DIR:-$build}
if [ -z "${FUZZ_NO_BUILD:-}" ]; then
	CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSWBA_FUZZ=ON -DSWBA_SANITIZE=ON \
		-DSWBA_SANITIZERS="$sanitizers" -DSWBA_WERROR=ON -DSWBA_BUILD_TESTS=OFF -DSWBA_BUILD_BENCH=OFF >/dev/null
	targets=()
	for r in "${readers[@]}"; do targets+=(--target "swba_fuzz_$r"); done
	nice cmake --build "$build" -j "${FUZZ_BUILD_JOBS:-2}" "${targets[@]}"
fi

# Leaks are findings too; MRPT's own one-off allocations are not reported as leaks at exit (no
# suppressions are needed so far: add them to fuzz/lsan.supp, with the reason, if that changes).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

status=0
summary=()
for r in "${readers[@]}"; do
	work=$build/corpus-work/$r
	findings=$build/findings/$r
	mkdir -p "$work" "$findings"
	cp -n fuzz/corpus/"$r"/* "$work"/ 2>/dev/null || true
	extra_dirs=()
	[ -d fuzz/regressions/"$r" ] && extra_dirs+=(fuzz/regressions/"$r")
	log=$build/fuzz-$r.log
	before_list=$(find "$findings" -type f | sort)
	before=$(wc -l <<<"$before_list")
	[ -z "$before_list" ] && before=0
	echo "== $r: ${seconds}s, log $log"
	# shellcheck disable=SC2086
	# timeout: a worker can hang in libFuzzer's own timeout handler (malloc from a signal handler while an
	# input holds the allocator's lock, doc/benchmarks/fuzzing.md); the run then fails instead of hanging.
	timeout -k 10 $((seconds + 120)) nice -n 10 "$build/fuzz/swba_fuzz_$r" "$work" "${extra_dirs[@]}" -fork=1 -ignore_ooms=1 -ignore_timeouts=1 \
		-max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 \
		-artifact_prefix="$findings/" -print_final_stats=1 ${FUZZ_EXTRA_ARGS:-} >"$log" 2>&1 || rc=$?
	rc=${rc:-0}
	# Fork mode's progress lines: "#<execs>: cov: C ft: F corp: N exec/s E oom/timeout/crash: O/T/X time: Ss ..."
	last=$(grep -E '^#[0-9]+: cov: ' "$log" | tail -n 1 || true)
	execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$last")
	cov=$(sed -E 's/.* cov: ([0-9]+).*/\1/' <<<"$last")
	secs=$(sed -E 's/.* time: ([0-9]+)s.*/\1/' <<<"$last")
	eps=$([ -n "$execs" ] && [ "${secs:-0}" -gt 0 ] && echo $((execs / secs)) || echo "?")  # the line's own exec/s is the last job's
	otc=$(sed -E 's/.* oom\/timeout\/crash: ([0-9\/]+).*/\1/' <<<"$last")
	new=$(($(find "$findings" -type f | wc -l) - before))
	# Triage: replay each new input once; print the sanitizer's summary and where it happened. Every
	# new input fails the run (MRPT's own crashes and allocations no longer reach the harness: read_rawlog
	# decodes in a capped probe process first, doc/fuzzing.md).
	for f in $(comm -13 <(echo "$before_list") <(find "$findings" -type f | sort)); do
		out=$(timeout 60 "$build/fuzz/swba_fuzz_$r" -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 "$f" 2>&1 || true)
		what=$(grep -m1 -E '^SUMMARY|ERROR: libFuzzer' <<<"$out" | cut -c1-120 || true)
		frame=$(grep -E '^ +#[0-9]+ ' <<<"$out" | grep -vE 'operator new|__asan|__interceptor|libFuzzer|fuzzer::' |
			grep -m1 -E 'libmrpt|/modules/|/fuzz/fuzz_' || true)
		where=$(sed -E 's/^ +#[0-9]+ 0x[0-9a-f]+ in //' <<<"$frame" | cut -c1-110)
		echo "  finding $f: ${what:-no failure when replayed alone}${frame:+ | $where}"
	done
	if [ "$new" -gt 0 ] || [ "$rc" != 0 ]; then status=1; fi
	unset rc
	summary+=("$(printf '%-13s executions %-10s in %5ss  exec/s %-6s cov %-6s oom/timeout/crash %-7s new files in %s: %s' \
		"$r" "${execs:-?}" "${secs:-?}" "$eps" "${cov:-?}" "${otc:-?}" "$findings" "$new")")
done
echo
printf '%s\n' "${summary[@]}"
exit $status
