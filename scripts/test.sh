#!/usr/bin/env bash
# Setup, build, and run every test (in parallel), then a
# 10-second smoke run of every fuzzer (clang, ASan + UBSan: scripts/fuzz.sh),
# then the tree's house-keeping limits (scripts/house_check.sh),
# and print how long each part took. Long end-to-end checks that are not part
# of this run live in tests/long (built with -DSDCB_LONG_TESTS=ON) and bench/.
# SDCB_SANITIZE=1 also runs the whole suite under AddressSanitizer + UBSan
# (scripts/sanitize.sh); it is not on by default because it rebuilds
# everything and took 34 min to build plus 16 min to run on the shared
# 2-core machine (docs/INTAKE.md).
set -euo pipefail
cd "$(dirname "$0")/.."

start=$SECONDS
times=()
report() {
  local total=$((SECONDS - start)) parts="" t
  for t in "${times[@]}"; do parts+="$t, "; done
  echo "test.sh: ${parts}total $((total / 60)) min $((total % 60)) s"
}
trap report EXIT
timed() {  # timed NAME COMMAND...: runs COMMAND and records its seconds
  local name=$1 began=$SECONDS rc=0
  shift
  "$@" || rc=$?
  times+=("$name $((SECONDS - began)) s")
  return $rc
}

timed "setup and build" bash scripts/setup.sh
timed "tests" ctest --test-dir build -j "$(nproc)" --output-on-failure \
  --timeout 1200
timed "fuzzing" bash scripts/fuzz.sh 10
timed "house check" bash scripts/house_check.sh
if [ "${SDCB_SANITIZE:-0}" = 1 ]; then
  timed "sanitizers" bash scripts/sanitize.sh
fi
