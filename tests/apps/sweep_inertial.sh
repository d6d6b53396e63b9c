#!/usr/bin/env bash
# swba jobs on inertial (observation-format) rawlogs (doc/sweeps.md): one job per rawlog runs every
# window; swba merge copies its report, which equals one sequential swba run's (ape.txt but for the
# ms/step column, every TUM file byte for byte), and tabulates the rows across the rawlogs. A job
# that has not run, or was interrupted, is named.
#   sweep_inertial.sh SWBA OUT_DIR
set -euo pipefail
swba=$1 out=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
source "$(dirname "$0")/same_files.sh"
rm -rf "$out" && mkdir -p "$out"
for s in 1 2; do
	"$swba" simulate-imu --duration 8 --seed $s --out "$out/logs" --name imu$s >/dev/null 2>&1 || fail "simulate-imu seed $s"
done
cat "$out/logs/imu1.ini" - >"$out/run.ini" <<'INI'
[window]
sizes = 5,10
INI
"$swba" jobs "$out/logs/imu1.rawlog" "$out/logs/imu2.rawlog" --config "$out/run.ini" --out "$out/sweep" >/dev/null
[ "$(wc -l <"$out/sweep/jobs.txt")" -eq 2 ] || fail "expected 2 jobs (one per inertial rawlog)"
grep -q -- "--gt $out/logs/imu1_ground_truth.tum " "$out/sweep/jobs.txt" || fail "job 1 does not read the TUM ground truth"
if grep -q -- "--windows" "$out/sweep/jobs.txt"; then fail "an inertial job is split by window"; fi
sed -n 2p "$out/sweep/jobs.txt" | bash >/dev/null 2>&1 || fail "job 2 failed"
if "$swba" merge "$out/sweep" >/dev/null 2>"$out/missing.err"; then fail "merge with a missing job succeeded"; fi
grep -q "job 1 (jobs/imu1/all): no summary.json" "$out/missing.err" || fail "merge does not name job 1: $(cat "$out/missing.err")"
sed -n 1p "$out/sweep/jobs.txt" | bash >/dev/null 2>&1 || fail "job 1 failed"
"$swba" merge "$out/sweep" >"$out/merged.txt" 2>"$out/merge.err" || fail "merge failed: $(cat "$out/merge.err")"

# A job stopped by a signal between its estimators (a row marked interrupted) is not complete.
s2=$out/sweep/jobs/imu2/all/summary.json
cp "$s2" "$out/summary2.json"
sed -i '0,/"interrupted": false/s//"interrupted": true/' "$s2"
if "$swba" merge "$out/sweep" --out "$out/merged_interrupted" >/dev/null 2>"$out/interrupted.err"; then
	fail "merge with an interrupted job succeeded"
fi
grep -q "job 2 (jobs/imu2/all): interrupted" "$out/interrupted.err" || fail "merge does not name job 2: $(cat "$out/interrupted.err")"
cp "$out/summary2.json" "$s2"

"$swba" run "$out/logs/imu1.rawlog" --config "$out/sweep/config.ini" --out "$out/seq" >/dev/null 2>&1
untimed() { awk '{ print substr($0, 1, length($0) - 12) }' "$1"; }  # the last column is ms/step
cmp <(untimed "$out/seq/ape.txt") <(untimed "$out/sweep/merged/imu1/ape.txt") || fail "ape.txt differs"
n=$(same_files "$out/seq" "$out/sweep/merged/imu1" "*.tum")
[ "$n" -eq 8 ] || fail "expected 8 TUM files (eskf, imu only, odometry only, 2 W x online/lagged, batch), got $n"
grep -q "^APE translation rmse (m) over 2 rawlogs" "$out/merged.txt" || fail "no table across the rawlogs"
grep -q -E "^window W=10 lagged +2 +0 " "$out/merged.txt" || fail "no W=10 lagged row over 2 runs"
echo "OK: inertial sweep: 2 jobs, merge = sequential run ($n TUM files), table across rawlogs"
