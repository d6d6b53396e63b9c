#!/usr/bin/env bash
# Rewrites the golden-output references (tests/golden/ref/) from the current build, then shows what
# moved. Commit the new references together with the change that moved them, and say why.
#   scripts/update-golden.sh [build dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
SWBA_UPDATE_GOLDEN=1 ctest --test-dir "$build" -L golden --output-on-failure
git --no-pager diff --stat -- tests/golden/ref
