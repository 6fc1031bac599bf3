#!/usr/bin/env bash
# Fits the sample meshes with the paper's settings and prints per-round,
# per-stage times (build first: scripts/setup.sh). Not run by the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target fit_bench >/dev/null
bench=./build/bench/fit_bench
m=data/meshes
$bench $m/bunny00.off 4 0.067 100 30        # paper's Bunny: degree 4, rms 0.067 %
$bench $m/fandisk_large.off 3 0.028 100 30  # paper's Fandisk: degree 3, rms 0.028 %
for k in 3 4 5; do
  $bench $m/cow.off $k 0.1 100 30
  $bench $m/blobby.off $k 0.1 100 30
done
