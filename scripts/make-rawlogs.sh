#!/usr/bin/env bash
# Generates the simulated rawlogs described by share/rawlogs/*.ini with MRPT's simul-landmarks
# (package mrpt-apps). Deterministic (fixed seeds in the INI files). Rawlogs are never committed.
#
# Usage: scripts/make-rawlogs.sh [DIR] [NAME...]
#   DIR   output directory (default: <repo>/build/rawlogs), created if needed
#   NAME  only these INI names (e.g. kf-slam_6D_noisy); default: every share/rawlogs/*.ini
# For each NAME it writes DIR/NAME.rawlog, DIR/NAME_ground_truth_robot_path.txt and
# DIR/NAME_ground_truth.txt (mrpt-common's naming), skipping a NAME whose rawlog and robot path exist.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$repo/build/rawlogs}"
shift || true

if ! command -v simul-landmarks >/dev/null 2>&1; then
	echo "make-rawlogs: simul-landmarks not found (install the Debian package mrpt-apps)" >&2
	exit 1
fi

names=("$@")
if [ ${#names[@]} -eq 0 ]; then
	for ini in "$repo"/share/rawlogs/*.ini; do names+=("$(basename "$ini" .ini)"); done
fi

mkdir -p "$out"
out="$(cd "$out" && pwd)"
for name in "${names[@]}"; do
	ini="$repo/share/rawlogs/$name.ini"
	if [ ! -f "$ini" ]; then
		echo "make-rawlogs: no INI file $ini" >&2
		exit 1
	fi
	if ! grep -Eq "^[[:space:]]*outFile[[:space:]]*=[[:space:]]*$name\.rawlog" "$ini"; then
		echo "make-rawlogs: $ini must set outFile = $name.rawlog" >&2
		exit 1
	fi
	if [ -f "$out/$name.rawlog" ] && [ -f "$out/${name}_ground_truth_robot_path.txt" ]; then
		echo "make-rawlogs: $out/$name.rawlog exists, skipped"
		continue
	fi
	tmp="$(mktemp -d "$out/.make-$name.XXXXXX")"
	start=$(date +%s)
	# simul-landmarks writes into its working directory (outDir = . in our INI files) and reports
	# errors on stdout with exit code 0: check its outputs instead.
	(cd "$tmp" && simul-landmarks "$ini" >"$out/$name.simul-landmarks.log" 2>&1) || true
	if [ ! -s "$tmp/$name.rawlog" ] || [ ! -s "$tmp/$name.rawlog_ground_truth_robot_path.txt" ]; then
		echo "make-rawlogs: simul-landmarks failed for $name; see $out/$name.simul-landmarks.log" >&2
		rm -rf "$tmp"
		exit 1
	fi
	mv "$tmp/$name.rawlog_ground_truth.txt" "$out/${name}_ground_truth.txt"
	mv "$tmp/$name.rawlog_ground_truth_robot_path.txt" "$out/${name}_ground_truth_robot_path.txt"
	mv "$tmp/$name.rawlog" "$out/$name.rawlog"
	rm -rf "$tmp"
	echo "make-rawlogs: wrote $out/$name.rawlog ($(( $(date +%s) - start )) s)"
done
