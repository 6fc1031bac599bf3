#!/usr/bin/env bash
# Textured glTF assets through `sdcb fit` and `sdcb export` (plain, Draco
# and meshopt): BoxTextured (assimp-testmodels' glTF 2), the Khronos Duck
# (duck.dae converted by `assimp export`, its duckCM.tga beside it) and the
# Cesium Milk Truck (glTF 1 converted by `assimp export -f glb2`). Per asset:
# fit and export seconds, the Khronos validator's errors, then
# gltf_texture_bench's row per primitive (colour differences in /255 at
# output points against the input's closest point, two-sided distance in
# % of the primitive's side). Beside them, the tool a pipeline uses today:
# gltfpack -cc on the input (quantized, meshopt-compressed, not simplified),
# with the same rows. Bytes of every file. Usage: gltf_assets_table.sh
# [RMSE [TOL [OUT]]]
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
  for codec in draco meshopt; do
    ./build/sdcb export "$OUT/$name.sdcb" -o "$OUT/$name.$codec.glb" \
      --tolerance "$TOL" --$codec --quiet
  done
  for kind in out draco meshopt; do
    # validate.js exits 1 on a warning too: the count is what this prints
    errors=$(node scripts/gltf_tools/validate.js "$OUT/$name.$kind.glb" |
      sed -n 's/.*"errors":\([0-9]*\).*/\1/p') || true
    printf '== %s (%s): fit %.1f s, export %.1f s, validator errors %s, %s bytes (input %s)\n' \
      "$name" "$kind" "$FIT_SECONDS" "$EXPORT_SECONDS" "$errors" \
      "$(stat -c %s "$OUT/$name.$kind.glb")" "$(stat -c %s "$OUT/$name.glb")"
    ./build/bench/gltf_texture_bench "$OUT/$name.glb" "$OUT/$name.$kind.glb"
  done
  packed="$OUT/$name.gltfpack.glb"
  g0=$(date +%s.%N)
  scripts/gltf_tools/node_modules/.bin/gltfpack -i "$OUT/$name.glb" \
    -o "$packed" -cc >/dev/null
  g1=$(date +%s.%N)
  errors=$(node scripts/gltf_tools/validate.js "$packed" |
    sed -n 's/.*"errors":\([0-9]*\).*/\1/p') || true
  printf '== %s (gltfpack -cc): %.1f s, validator errors %s, %s bytes\n' \
    "$name" "$(echo "$g1 - $g0" | bc)" "$errors" "$(stat -c %s "$packed")"
  ./build/bench/gltf_texture_bench "$OUT/$name.glb" "$packed"
done
