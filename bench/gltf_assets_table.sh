#!/usr/bin/env bash
# Textured glTF assets through `sdcb fit` and `sdcb export` (plain and
# Draco): BoxTextured (assimp-testmodels' glTF 2), the Khronos Duck
# (duck.dae converted by `assimp export`, its duckCM.tga beside it) and the
# Cesium Milk Truck (glTF 1 converted by `assimp export -f glb2`). Per asset:
# fit and export seconds, the Khronos validator's errors, then
# gltf_texture_bench's row per primitive (colour differences in /255 at
# output points against the input's closest point, two-sided distance in
# % of the primitive's side). Usage: gltf_assets_table.sh [RMSE [TOL [OUT]]]
set -euo pipefail
cd "$(dirname "$0")/.."
RMSE=${1:-0.1}
TOL=${2:-0.1}
OUT=${3:-/tmp/sdcb_gltf_assets}
cmake --build build --target sdcb gltf_texture_bench >/dev/null
source bench/gltf_assets.sh
for name in BoxTextured Duck CesiumMilkTruck; do
  gltf_asset_input "$name" "$OUT"
  if ! gltf_asset_fit_export "$name" "$RMSE" "$TOL" "$OUT"; then
    echo "== $name: the fit refused the asset (above)"
    continue
  fi
  ./build/sdcb export "$OUT/$name.sdcb" -o "$OUT/$name.draco.glb" \
    --tolerance "$TOL" --draco --quiet
  for kind in out draco; do
    # validate.js exits 1 on a warning too: the count is what this prints
    errors=$(node scripts/gltf_tools/validate.js "$OUT/$name.$kind.glb" |
      sed -n 's/.*"errors":\([0-9]*\).*/\1/p') || true
    printf '== %s (%s): fit %.1f s, export %.1f s, validator errors %s\n' \
      "$name" "$kind" "$FIT_SECONDS" "$EXPORT_SECONDS" "$errors"
    ./build/bench/gltf_texture_bench "$OUT/$name.glb" "$OUT/$name.$kind.glb"
  done
done
