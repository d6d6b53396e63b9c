#!/usr/bin/env bash
# Golden output of a sweep on shipped data: swba jobs over two rawlogs (mrpt-common's 6D demo and its
# non-centred variant, 60 steps, W = 5, 10), the jobs on GNU parallel -j 2, then what swba merge prints.
#   sweep.sh SWBA WORK_DIR DATASETS
set -euo pipefail
swba=$1 work=$2 data=$3
printf '[run]\nmax_steps = 60\n[window]\nsizes = 5,10\n[ekf]\nmethods = kfEKFNaive\n' >"$work/run.ini"
"$swba" jobs "$data/kf-slam_6D_demo.rawlog" "$data/kf-slam_6D_demo_noncentered.rawlog" --config "$work/run.ini" \
	--out "$work/sweep" >/dev/null 2>&1
# MRPT's EKF fails on the non-centred rawlog, so that job's run exits 3 (a failed row, its results
# written): parallel's status says so; swba merge checks every job's summary itself.
parallel -j 2 --joblog "$work/sweep/joblog" <"$work/sweep/jobs.txt" >"$work/jobs.out" 2>&1 || true
"$swba" merge "$work/sweep" --no-plots
