#!/usr/bin/env bash
# swba run into a directory an earlier run wrote: the earlier run's files are removed first (and said so),
# a file the user put there is kept (and warned about), so the directory never mixes two runs.
#   reused_out_dir.sh <swba> <out dir>
set -u
swba=$1 out=$2
rm -rf "$out" "$out.imu" && mkdir -p "$out"
fail() { echo "FAIL: $1"; cat "$out.stderr" 2>/dev/null; exit 1; }
"$swba" run --max-steps 20 --windows 5,30 --no-progress --out "$out" >/dev/null 2>"$out.stderr" || fail "first run"
for f in window_30.tum batch.tum plots/ape_window_30.dat; do [ -f "$out/$f" ] || fail "first run wrote no $f"; done
echo "mine" >"$out/notes_of_mine.txt"
"$swba" run --max-steps 20 --windows 7 --no-ekf --no-batch --no-progress --out "$out" >/dev/null 2>"$out.stderr" ||
	fail "second run"
grep -Eq "^swba run: removed the [0-9]+ files of an earlier run from $out/\$" "$out.stderr" || fail "no 'removed' line"
grep -q "^swba run: warning: $out/ holds 1 files that swba run did not write" "$out.stderr" || fail "no warning on the kept file"
for f in window_30.tum window_5.tum batch.tum ekf_kfEKFNaive.tum plots/ape_window_30.dat plots/ape_batch.png; do
	[ -e "$out/$f" ] && fail "$f of the first run is still there"
done
[ -f "$out/notes_of_mine.txt" ] || fail "the user's own file was removed"
[ -f "$out/window_7.tum" ] && [ -f "$out/plots/ape_window_7.dat" ] || fail "the second run's files are missing"
# Every file of the directory is the second run's or the user's one.
listed=$(sort "$out/swba_run_files.txt")
actual=$(cd "$out" && find . -type f ! -name swba_run_files.txt ! -name notes_of_mine.txt | sed 's|^\./||' | sort)
[ "$listed" = "$actual" ] || fail "the manifest is not the directory's files: $(diff <(echo "$listed") <(echo "$actual"))"
# An inertial rawlog's run into the same directory removes the range-bearing run's files too (and says that
# --max-steps does not apply to it, while --no-ekf skips its filter).
"$swba" simulate-imu --duration 3 --out "$out.imu" --name imu >/dev/null 2>&1 || fail "simulate-imu"
"$swba" run "$out.imu/imu.rawlog" --config "$out.imu/imu.ini" --windows 5 --no-plots --no-progress --max-steps 9 --no-ekf \
	--out "$out" >/dev/null 2>"$out.stderr" || fail "inertial run"
grep -q "^swba run: warning: not used on an inertial rawlog (doc/inertial.md), ignored: --max-steps$" "$out.stderr" ||
	fail "no warning on --max-steps"
grep -Eq "^swba run: removed the [0-9]+ files of an earlier run from $out/\$" "$out.stderr" || fail "no 'removed' line (inertial)"
[ -e "$out/window_7.tum" ] && fail "window_7.tum of the range-bearing run is still there"
[ -f "$out/window_W_5.tum" ] || fail "the inertial run's files are missing"
[ -e "$out/eskf.tum" ] && fail "--no-ekf ran the ESKF"
listed=$(sort "$out/swba_run_files.txt")
actual=$(cd "$out" && find . -type f ! -name swba_run_files.txt ! -name notes_of_mine.txt | sed 's|^\./||' | sort)
[ "$listed" = "$actual" ] || fail "the inertial manifest is not the directory's files: $(diff <(echo "$listed") <(echo "$actual"))"
echo "OK: reused output directory"
