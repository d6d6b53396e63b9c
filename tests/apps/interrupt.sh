#!/usr/bin/env bash
# swba run stopped by a signal mid-run: exit code 128 + signal, a one-line message, the complete rows'
# files kept and summary.json marking the others interrupted. With "twice", the signal is sent twice back
# to back (0.1 s apart), as GNU timeout and GNU parallel deliver it (to the process and to its group): one
# request.
#   interrupt.sh <swba> <out dir> <INT|TERM> <expected exit code> [twice]
set -u
swba=$1 out=$2 sig=$3 want=$4 twice=${5:-}
rm -rf "$out" "$out.stdout" "$out.stderr"
# The full demo with the causal optimum runs for minutes: the signal arrives mid-run.
"$swba" run --causal --no-plots --no-progress --out "$out" >"$out.stdout" 2>"$out.stderr" &
pid=$!
sleep 3
kill -s "$sig" "$pid"
[ "$twice" = twice ] && sleep 0.1 && kill -s "$sig" "$pid"
wait "$pid"
rc=$?
fail() { echo "$1"; cat "$out.stderr"; exit 1; }
[ "$rc" = "$want" ] || fail "exit code $rc, expected $want"
grep -q "swba run: interrupted by SIG$sig" "$out.stderr" || fail "no 'interrupted by SIG$sig' on stderr"
grep -q '"interrupted": true' "$out/summary.json" || fail "no interrupted estimator in $out/summary.json"
grep -q 'INTERRUPTED after' "$out.stdout" || fail "no INTERRUPTED row in the table"
ls "$out"/*.tum >/dev/null 2>&1 || fail "no TUM file kept"
ls "$out" | grep -q '\.tmp\.' && fail "a temporary file was left"
echo "OK: exit $rc"
