#!/usr/bin/env bash
# Installs the Debian packages swba needs, only those missing (idempotent, non-interactive).
set -euo pipefail
pkgs=(cmake g++ make libeigen3-dev libsuitesparse-dev libgtest-dev
	libboost-math-dev  # header-only: Boost.Math's chi-square distribution (gates, loss scales)
	nlohmann-json3-dev # header-only: JSON reports (summary.json, <m>_stats.json, <m>_result.json)
	zlib1g-dev       # gzip member scan of the rawlog readers (truncated files, trailing bytes)
	libmrpt-slam-dev libmrpt-tclap-dev mrpt-common
	libmrpt-graphslam-dev  # optional: MRPT graph-SLAM peer of the pose-graph benchmark
	libceres-dev     # optional: benchmark peer only
	gnuplot-nox      # optional: headless plots
	clang libclang-rt-14-dev  # the fuzz smoke of ./dev.sh test (libFuzzer, sanitizer runtimes)
	ninja-build lld  # the sanitizer build of ./dev.sh test: ninja's scheduling, lld's faster links
	mrpt-apps        # simul-landmarks: simulated rawlogs (swba simulate, swba nees, scripts/make-rawlogs.sh)
	parallel)        # GNU parallel: runs the job lists of swba jobs / swba nees (doc/sweeps.md)
missing=()
for p in "${pkgs[@]}"; do
	dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "install-deps: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
