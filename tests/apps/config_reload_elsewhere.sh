#!/usr/bin/env bash
# The config.ini a run writes reloads from any working directory: the paths in it are absolute, even
# when the run was given a relative one.
#   config_reload_elsewhere.sh <swba> <rawlog> <out dir>
set -u
swba=$1 rawlog=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $1"; cat "$out/stderr" 2>/dev/null; exit 1; }
(cd "$(dirname "$rawlog")" && "$swba" run "$(basename "$rawlog")" --max-steps 5 --windows 5 --no-ekf --no-batch \
	--no-plots --no-progress --out "$out/first" >/dev/null 2>"$out/stderr") || fail "first run"
grep -q "^rawlog = /" "$out/first/config.ini" || fail "the rawlog path in config.ini is not absolute"
(cd / && "$swba" run --config "$out/first/config.ini" --out "$out/again" >/dev/null 2>"$out/stderr") ||
	fail "config.ini does not reload from /"
cmp -s "$out/first/window_5.tum" "$out/again/window_5.tum" || fail "the reloaded run differs"
echo "OK: config.ini reloads elsewhere"
