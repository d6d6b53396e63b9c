#!/usr/bin/env bash
# The inputs of golden.compare: two real logs (mrclam6_r1, mrclam6_r5) run with the default Cauchy loss and
# with the Huber loss, W = 5 and 30, no EKF, no batch, into WORK_DIR/cauchy/rR and WORK_DIR/huber/rR.
#   compare_runs.sh SWBA WORK_DIR DATA_DIR
set -euo pipefail
swba=$1 work=$2 data=$3
rm -rf "$work"
for r in 1 5; do
	for c in cauchy huber; do
		"$swba" run "$data/mrclam/mrclam6_r$r.rawlog" --windows 5,30 --robust-loss $c --no-ekf --no-batch --no-plots \
			--no-progress --out "$work/$c/r$r" >/dev/null
	done
done
