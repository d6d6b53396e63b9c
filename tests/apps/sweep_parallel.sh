#!/usr/bin/env bash
# swba jobs -> GNU parallel -j 2 -> swba merge gives the figures of one sequential swba run of the same
# configuration (doc/sweeps.md): ape.txt and every TUM file byte for byte, summary.json and ape.csv but
# for the wall times, the table but for its ms/step column. Then: the Slurm script runs line K of the
# list when SLURM_ARRAY_TASK_ID=K; swba merge names a job that has not run, and re-running that one
# line alone completes the sweep; a job that failed under GNU parallel is in its joblog and
# `parallel --retry-failed --joblog` re-runs it.
#   sweep_parallel.sh SWBA OUT_DIR RAWLOG
set -euo pipefail
swba=$1 out=$2 rawlog=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
source "$(dirname "$0")/same_files.sh"
rm -rf "$out" && mkdir -p "$out"
command -v parallel >/dev/null || fail "GNU parallel not found (scripts/install-deps.sh installs it)"
parallel --version 2>/dev/null | head -1 | grep -q "GNU parallel" || fail "'parallel' is not GNU parallel"

cat >"$out/run.ini" <<'INI'
[run]
max_steps = 20
[window]
sizes = 3,5
fej = both
[ekf]
methods = kfEKFNaive
INI
"$swba" jobs "$rawlog" --config "$out/run.ini" --out "$out/sweep" >/dev/null
[ "$(wc -l <"$out/sweep/jobs.txt")" -eq 2 ] || fail "expected 2 jobs (W = 3, 5)"
parallel -j 2 --joblog "$out/sweep/joblog" <"$out/sweep/jobs.txt" >"$out/parallel.out" 2>&1 || fail "a job failed: $(cat "$out/parallel.out")"
"$swba" merge "$out/sweep" --no-plots >"$out/merged.txt" 2>"$out/merge.err"
# The sequential reference: one swba run with the sweep's own options (all windows, EKF, batch).
"$swba" run "$rawlog" --config "$out/sweep/config.ini" --out "$out/seq" >"$out/seq.txt" 2>/dev/null

m="$out/sweep/merged/$(basename "$rawlog" .rawlog)"
cmp "$out/seq/ape.txt" "$m/ape.txt" || fail "ape.txt differs"
n=$(same_files "$out/seq" "$m" "*.tum")
[ "$n" -eq 12 ] || fail "expected 12 TUM files (gt, ekf, 2 W x FEJ on/off x online/lagged, batch from two starts), got $n"
# Covariance files (when swba run writes them): copied byte for byte too.
same_files "$out/seq" "$m" "*.cov" >/dev/null
# Wall times are each job's own: every JSON key and CSV column named *seconds or ms_per_step, and the
# table's columns right of "full rmse", are left out of the comparison.
untimed_json() { grep -v -E '"[a-z_]*(seconds|ms_per_step)":' "$1"; }
cmp <(untimed_json "$out/seq/summary.json") <(untimed_json "$m/summary.json") || fail "summary.json differs"
untimed_csv() {
	awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) timed[i] = ($i ~ /seconds|ms_per_step/) }
		{ line = ""; for (i = 1; i <= NF; i++) if (!timed[i]) line = line $i ","; print line }' "$1"
}
cmp <(untimed_csv "$out/seq/ape.csv") <(untimed_csv "$m/ape.csv") || fail "ape.csv differs"
untimed_table() {
	awk '/^$/ { c = 0; next } /full rmse/ { c = index($0, "full rmse") + 8 } { print (c ? substr($0, 1, c) : $0) }' "$1"
}
cmp <(untimed_table "$out/seq.txt") <(untimed_table "$out/merged.txt") || fail "table differs"
grep -q "^window W=5 slam nofej lagged " "$out/merged.txt" || fail "no W=5 nofej lagged row"
echo "merge of 2 parallel jobs = sequential run: ape.txt, $n TUM files, summary.json, ape.csv, table"

# Slurm: an array of 2 tasks; task K runs line K.
sb="$out/sweep/jobs.sbatch"
grep -q '^#SBATCH --array=1-2$' "$sb" || fail "jobs.sbatch has no --array=1-2"
grep -q "^#SBATCH --output=$out/sweep/slurm-%A_%a.out" "$sb" || fail "jobs.sbatch: --output"
j2="$out/sweep/jobs/$(basename "$rawlog" .rawlog)/w5"
mv "$j2/summary.json" "$out/summary_w5.json"
if "$swba" merge "$out/sweep" --no-plots >/dev/null 2>"$out/missing.err"; then fail "merge with a missing job succeeded"; fi
grep -q "job 2 (jobs/[^)]*/w5): no summary.json" "$out/missing.err" || fail "merge does not name job 2: $(cat "$out/missing.err")"
grep -q "sed -n 2p $out/sweep/jobs.txt | bash" "$out/missing.err" || fail "merge does not say how to re-run job 2"
SLURM_ARRAY_TASK_ID=2 bash "$sb" >/dev/null 2>"$out/slurm.err" || fail "jobs.sbatch task 2 failed: $(cat "$out/slurm.err")"
grep -q "task 2: .* --windows 5 " "$out/slurm.err" || fail "task 2 did not run line 2"
cmp <(untimed_json "$out/summary_w5.json") <(untimed_json "$j2/summary.json") || fail "task 2 computed other figures"
if SLURM_ARRAY_TASK_ID=3 bash "$sb" 2>"$out/slurm3.err"; then fail "task 3 of 2 succeeded"; fi
grep -q "no line 3" "$out/slurm3.err" || fail "task 3: no message"
"$swba" merge "$out/sweep" --no-plots >"$out/merged2.txt" 2>/dev/null || fail "merge after re-running job 2"
cmp <(untimed_table "$out/merged.txt") <(untimed_table "$out/merged2.txt") || fail "table differs after the re-run"

# A failed job in GNU parallel's joblog, re-run alone by parallel --retry-failed (doc/sweeps.md).
mv "$out/sweep/config_windows.ini" "$out/config_windows.ini"
rm -f "$j2/summary.json"
if parallel -j 2 --joblog "$out/retry.joblog" <"$out/sweep/jobs.txt" >"$out/retry.out" 2>&1; then
	fail "parallel succeeded with job 2's config missing"
fi
[ "$(awk -F'\t' 'NR > 1 && $7 != 0' "$out/retry.joblog" | wc -l)" -eq 1 ] || fail "joblog does not show 1 failed job"
mv "$out/config_windows.ini" "$out/sweep/config_windows.ini"
parallel --retry-failed --joblog "$out/retry.joblog" >"$out/retry2.out" 2>&1 || fail "parallel --retry-failed: $(cat "$out/retry2.out")"
"$swba" merge "$out/sweep" --no-plots >"$out/merged3.txt" 2>/dev/null || fail "merge after --retry-failed"
cmp <(untimed_table "$out/merged.txt") <(untimed_table "$out/merged3.txt") || fail "table differs after --retry-failed"
echo "OK: sweep on GNU parallel -j 2 merged bit-identical; Slurm task 2 and parallel --retry-failed re-ran job 2"
