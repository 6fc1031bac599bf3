#!/usr/bin/env bash
# Setup, build, and run every test (in parallel), then a 30-second smoke run
# of every fuzzer (clang, ASan + UBSan: scripts/fuzz.sh).
# SDCB_SANITIZE=1 also runs the whole suite under AddressSanitizer + UBSan
# (scripts/sanitize.sh); it is not on by default because it rebuilds
# everything and took 34 min to build plus 16 min to run on the shared
# 2-core machine (docs/INTAKE.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir build -j "$(nproc)" --output-on-failure --timeout 1200
bash scripts/fuzz.sh 30
if [ "${SDCB_SANITIZE:-0}" = 1 ]; then
  bash scripts/sanitize.sh
fi
