#!/usr/bin/env bash
# A new user's walkthrough: every subcommand on the shipped data, then the malformed inputs a newcomer
# types, each with the exit code of doc/cli.md's convention (0 success; 2 a bad command line; 1 a bad
# input file or a failure while running, and a run whose every estimator failed) and the message that
# says what was wrong. Every check is listed; the script fails if any fails.
#   new_user_walkthrough.sh <swba> <work dir> <mrpt datasets dir> <source dir>
set -u
swba=$1 work=$2 mrpt=$3 src=$4
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
data=$src/share/data evo=$src/share/data/evo_reference demo=$mrpt/kf-slam_6D_demo.rawlog da=$mrpt/kf-slam_6D_demo_DA.rawlog
failures=0 checks=0

# check <name> <exit code> <regex on stdout+stderr> [! <regex that must not match>] -- <swba arguments...>
check() {
	local name=$1 want=$2 regex=$3 not_regex=""
	shift 3
	if [ "$1" = "!" ]; then not_regex=$2; shift 2; fi
	[ "$1" = "--" ] && shift
	local out rc
	out=$("$swba" "$@" 2>&1)
	rc=$?
	checks=$((checks + 1))
	local why=""
	[ "$rc" = "$want" ] || why="exit code $rc, expected $want"
	[ -z "$why" ] && ! grep -Eq -- "$regex" <<<"$out" && why="no match for '$regex'"
	[ -z "$why" ] && [ -n "$not_regex" ] && grep -Eq -- "$not_regex" <<<"$out" && why="matches '$not_regex'"
	# Never a crash, and an error is one line naming the command.
	[ -z "$why" ] && [ "$rc" -gt 2 ] && why="exit code $rc is not 0, 1 or 2"
	if [ -z "$why" ] && [ "$rc" != 0 ] && [ "$(grep -c "^swba [a-z]*: error: " <<<"$out")" != 1 ]; then
		why="not exactly one 'swba <command>: error:' line"
	fi
	if [ -n "$why" ]; then
		failures=$((failures + 1))
		echo "FAIL $name: $why; swba $*"
		head -c 3000 <<<"$out" | sed 's/^/    /'
	else
		echo "ok   $name (exit $rc)"
	fi
}

printf '[run]\nmax_steps = 20\n[window]\nsizes = 5\n[ekf]\nmethods = kfEKFNaive\n' >short.ini

# --- every subcommand on shipped data: exit 0 ---
check version 0 "^swba [0-9.]+ \(MRPT" -- version
check help 0 "Commands:.*" -- --help
check run 0 "window W=5 +5 +online +0\.[0-9]{6} .* rot rmse|rot rmse +rpe rmse" -- run --config short.ini --no-progress --out run
check run_association 0 "association [0-9.]+ % correct" -- run "$da" --max-steps 30 --windows 5 --no-ekf --no-progress --out run_da
check run_gt_tum 0 "window W=5 +5 +online +0\.[0-9]{6}" -- run "$demo" --gt "$evo/gt_kf-slam_6D_demo.tum" --config short.ini --out run_tum
check ape 0 "rmse	0\.016064" -- ape "$evo/gt_kf-slam_6D_demo.tum" "$evo/ekf_kf-slam_6D_demo.tum"
check ape_evo_form 0 "rmse	0\.016064" -- ape tum "$evo/gt_kf-slam_6D_demo.tum" "$evo/ekf_kf-slam_6D_demo.tum" --t_max_diff 0.01
check rpe 0 "RPE w.r.t. translation part" -- rpe "$evo/gt_kf-slam_6D_demo.tum" "$evo/ekf_kf-slam_6D_demo.tum"
check monoba 0 "Final cost:" -- monoba
check bal 0 "Final cost:" -- bal "$data/bal/problem-49-7776-pre.txt" --max-iterations 2 -q
check pgo 0 "Final cost:" -- pgo "$data/posegraph/smallGrid3D.g2o" -q
check directba 0 "Final cost:" -- directba "$data/directba" -q --iterations 2
check simulate 0 "sim_seed1\.rawlog" -- simulate "$src/share/rawlogs/kf-slam_6D_noisy.ini" --seed 1 --name sim_seed1 --out sim
check jobs 0 "sweep/jobs\.txt" -- jobs "$demo" --config short.ini --out sweep
bash sweep/jobs.txt >/dev/null 2>&1
check merge 0 "window W=5 +5 +online +0\.[0-9]{6}" -- merge sweep --no-plots
# A sweep over a rawlog without landmark IDs keeps the association quality: merge prints it.
check jobs_association 0 "sweep_da/jobs\.txt" -- jobs "$da" --config short.ini --out sweep_da
bash sweep_da/jobs.txt >/dev/null 2>&1
check merge_association 0 "note: [^ ]*: window W=5: association [0-9.]+ % correct" -- merge sweep_da --no-plots
check nees 0 "running the 1 jobs of .* here, one after the other" ! "Run them with|parallel -j" -- \
	nees --runs 1 --max-steps 20 --windows 5 --fej on --no-ekf --no-plots --out nees

# --- a bad command line: exit 2, naming the option or the argument ---
for c in run ape rpe monoba bal pgo directba jobs merge simulate nees version; do
	check "${c}_unknown_option" 2 "^swba $c: error: unknown option '--bogus' \(see --help\)" -- "$c" --bogus
done
for c in ape rpe bal pgo merge simulate; do
	check "${c}_missing_argument" 2 "^swba $c: error: missing argument\(s\)" -- "$c"
done
check directba_missing_argument 2 "^swba directba: error: missing DIR \(or use --synthetic\)" -- directba
check run_two_rawlogs 2 "unexpected argument '[^']*b\.rawlog': one rawlog per run; for several, see swba jobs" -- run a.rawlog b.rawlog
check run_huge_window 2 "window size must be in \[2, 1000000\], got 10000000" -- run --windows 10000000 --out bad
check run_bad_policy 2 "unknown policy 'fast'" -- run --policy fast --out bad
check run_map_free_gauge 2 "the map landmark policy needs the fixed or the prior gauge" -- run --policy map --gauge free --out bad
check ape_zip 2 "not evo's \.zip: give a directory" -- ape "$evo/gt_kf-slam_6D_demo.tum" "$evo/ekf_kf-slam_6D_demo.tum" --save-results r.zip
check rpe_delta_0 2 "--delta must be >= 1" -- rpe "$evo/gt_kf-slam_6D_demo.tum" "$evo/ekf_kf-slam_6D_demo.tum" --delta 0
check monoba_bad_noise 2 "noise" -- monoba --noise -1
check bal_bad_linear 2 "--linear" -- bal "$data/bal/problem-49-7776-pre.txt" --linear qr
check pgo_bad_robust 2 "tukey|robust" -- pgo "$data/posegraph/smallGrid3D.g2o" --robust tukey
check directba_bad_sigma 2 "sigma" -- directba "$data/directba" --sigma -1
check jobs_no_rawlog 2 "no rawlog given" -- jobs --out bad_jobs
check simulate_seed_0 2 "--seed must be >= 1" -- simulate "$src/share/rawlogs/kf-slam_6D_noisy.ini" --seed 0 --out bad
check nees_runs_0 2 "--runs must be >= 1" -- nees --runs 0 --out bad_nees

# --- a bad input file or a failure while running: exit 1, naming the file ---
check run_missing_rawlog 1 "rawlog '/nonexistent/x\.rawlog': file does not exist" -- run /nonexistent/x.rawlog --out bad
check run_rawlog_as_config 1 "config '[^']*kf-slam_6D_demo\.rawlog': not a text file \(a NUL byte" -- run --config "$demo" --out bad
check simulate_rawlog_as_ini 1 "simul-landmarks INI '[^']*kf-slam_6D_demo\.rawlog': not a text file" -- simulate "$demo" --out bad
check run_ids_without_ids 1 "no landmark ID \(-1\): use data association \(--association auto, nn or jcbb\) instead of ids" ! \
	"not supported" -- run "$da" --association ids --max-steps 5 --out bad
check run_every_estimator_failed 1 "every estimator failed" -- \
	run "$mrpt/kf-slam_demo.rawlog" --config "$src/tests/apps/data/model_6d.ini" --no-ekf --windows 5 --no-plots --out failed
check ape_missing_file 1 "does_not_exist\.tum" -- ape "$evo/gt_kf-slam_6D_demo.tum" does_not_exist.tum
check ape_one_pose_aligned 1 "Degenerate covariance rank, Umeyama alignment is not possible" -- \
	ape "$src/tests/eval/data/one_pose.tum" "$src/tests/eval/data/one_pose.tum" -a
check bal_missing_file 1 "/nonexistent/problem\.txt" -- bal /nonexistent/problem.txt
check pgo_missing_file 1 "/nonexistent\.g2o" -- pgo /nonexistent.g2o
check directba_missing_dir 1 "/nonexistent/directba" -- directba /nonexistent/directba
check merge_not_a_sweep 1 "sweep manifest '/nonexistent/sweep\.json': file does not exist" -- merge /nonexistent
SWBA_SIMD=sse9 check run_bad_simd_env 1 "unknown SWBA_SIMD level 'sse9'" -- run --max-steps 1 --out bad

# --- messages keep their UTF-8 characters in a UTF-8 locale, escape them in the C locale ---
LC_ALL=C.UTF-8 check utf8_locale 2 "must be a number ≥ 0" -- monoba --noise -1
LC_ALL=C check c_locale 2 'must be a number \\xe2\\x89\\xa5 0' -- monoba --noise -1

echo "$checks checks, $failures failed"
[ "$failures" = 0 ] && echo "OK: new-user walkthrough"
