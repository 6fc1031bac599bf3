#!/usr/bin/env bash
# Setup, build, and run every test (in parallel).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir build -j "$(nproc)" --output-on-failure --timeout 1200
