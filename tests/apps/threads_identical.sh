#!/usr/bin/env bash
# swba run gives the same output whatever the solver's thread count: every TUM and covariance file and
# ape.txt byte for byte with --threads 1 and --threads 2, on a rawlog with landmark IDs and on one
# without (data association). The solver evaluates factors and builds the normal equations and the
# Schur complement in parallel above 2000 factors (kParallelMin): the batch of the first 250 steps of
# kf-slam_6D_demo (2299 factors) does, a window does not. No run of kf-slam_6D_demo_DA reaches it (the
# whole log's batch has 1756 factors), so its first 60 steps check what does not depend on the log's
# length: the association's decisions and everything after them stay the same with --threads 2.
#   threads_identical.sh SWBA OUT_DIR RAWLOG STEPS [RAWLOG STEPS]...   (STEPS: --max-steps, or all)
set -euo pipefail
swba=$1 out=$2
shift 2
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out"
n=0
while [ $# -ge 2 ]; do
	rawlog=$1 steps=$2
	shift 2
	name=$(basename "$rawlog" .rawlog)
	mkdir -p "$out/$name"
	limit=()
	[ "$steps" = all ] || limit=(--max-steps "$steps")
	for t in 1 2; do
		"$swba" run "$rawlog" "${limit[@]}" --windows 5 --no-ekf --no-plots --no-progress --threads "$t" \
			--out "$out/$name/t$t" >"$out/$name/t$t.txt" 2>&1 || fail "$name --threads $t: $(tail -3 "$out/$name/t$t.txt")"
	done
	for f in "$out/$name/t1"/*.tum "$out/$name/t1"/*.cov "$out/$name/t1/ape.txt"; do
		[ -f "$f" ] || fail "$name: expected file missing: $f"
		cmp -s "$f" "$out/$name/t2/$(basename "$f")" || fail "$name: $(basename "$f") differs between --threads 1 and 2"
		n=$((n + 1))
	done
done
[ $# -eq 0 ] || fail "arguments: RAWLOG STEPS pairs expected"
echo "OK: $n files identical with --threads 1 and 2"
