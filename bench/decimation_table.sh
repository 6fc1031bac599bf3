#!/usr/bin/env bash
# The spline against the mesh a user would otherwise keep: for each mesh, fit
# (degree 4, --rmse RMSE), then decimate the input with CGAL's Garland-Heckbert
# policy to as many vertices as the spline has control points, and measure
# both against the input the same way (build/bench/decimation_bench).
#   bench/decimation_table.sh [RMSE [OUT_DIR]] [MESH ...]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target decimation_bench >/dev/null
rmse=${1:-0.1}
out=${2:-/tmp/sdcb_decimation}
shift $(( $# > 2 ? 2 : $# )) || true
meshes=("$@")
[ ${#meshes[@]} -gt 0 ] || meshes=(bunny00 fandisk_large bear homer)
mkdir -p "$out"
for m in "${meshes[@]}"; do
  ./build/sdcb fit "data/meshes/$m.off" -o "$out/$m.sdcb" --rmse "$rmse" --quiet \
    --json "$out/$m.json" 2> /dev/null || true
  ./build/bench/decimation_bench "data/meshes/$m.off" "$out/$m.sdcb" 200000
done
