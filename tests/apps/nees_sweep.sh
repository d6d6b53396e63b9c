#!/usr/bin/env bash
# swba nees, sequential and as jobs on GNU parallel -j 2 then swba merge, on 2 simulated runs. With the
# covariance files of swba run both print the same table and write the same nees.csv byte for byte;
# without them both must fail naming the missing file (never skip silently).
#   nees_sweep.sh SWBA OUT_DIR
set -euo pipefail
swba=$1 out=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out"
command -v parallel >/dev/null || fail "GNU parallel not found (scripts/install-deps.sh installs it)"
args=(--runs 2 --first-seed 3 --max-steps 25 --windows 5 --no-plots)

set +e
"$swba" nees "${args[@]}" --out "$out/seq" >"$out/seq.txt" 2>"$out/seq.err"
seq_rc=$?
set -e
"$swba" nees "${args[@]}" --jobs-only --out "$out/par" >/dev/null 2>&1 || fail "nees --jobs-only"
[ "$(wc -l <"$out/par/jobs.txt")" -eq 2 ] || fail "expected 2 jobs (one per seed)"
grep -q -- "simulate .* --seed 4 " "$out/par/jobs.txt" || fail "job 2 does not simulate seed 4"
parallel -j 2 --joblog "$out/par/joblog" <"$out/par/jobs.txt" >"$out/parallel.out" 2>&1 || fail "a job failed: $(cat "$out/parallel.out")"
[ "$(awk 'NR > 1 && $7 == 0' "$out/par/joblog" | wc -l)" -eq 2 ] || fail "joblog does not show 2 jobs with exit 0"
set +e
"$swba" merge "$out/par" --no-plots >"$out/par.txt" 2>"$out/par.err"
par_rc=$?
set -e
if ls "$out"/par/jobs/*/all/*.cov >/dev/null 2>&1; then
	[ "$seq_rc" -eq 0 ] || fail "swba nees failed: $(cat "$out/seq.err")"
	[ "$par_rc" -eq 0 ] || fail "swba merge failed: $(cat "$out/par.err")"
	cmp "$out/seq/nees/nees.csv" "$out/par/nees/nees.csv" || fail "nees.csv differs"
	cmp "$out/seq.txt" "$out/par.txt" || fail "table differs"
	grep -q "^window W=5 slam fej lagged " "$out/par.txt" || fail "no lagged FEJ row"
	echo "OK: NEES of 2 runs on GNU parallel -j 2 = sequential (nees.csv byte for byte)"
else
	[ "$seq_rc" -ne 0 ] || fail "swba nees succeeded without covariance files"
	[ "$par_rc" -ne 0 ] || fail "swba merge succeeded without covariance files"
	grep -q "error: no covariance file .*/window_5_slam_fej.cov\|error: no covariance file .*/ekf.cov" "$out/seq.err" ||
		fail "swba nees does not name the missing covariance file: $(cat "$out/seq.err")"
	grep -q "error: no covariance file " "$out/par.err" || fail "swba merge does not name the missing file"
	echo "OK: without covariance files swba nees and swba merge fail naming the file"
fi
