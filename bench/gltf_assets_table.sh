#!/usr/bin/env bash
# Textured glTF assets through `sdcb fit` and `sdcb export` (plain and
# Draco): BoxTextured (assimp-testmodels' glTF 2), the Khronos Duck
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
mkdir -p "$OUT"
cmake --build build --target sdcb gltf_texture_bench >/dev/null
M=/usr/share/assimp/models
cp "$M/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb" "$OUT/BoxTextured.glb"
assimp export "$M/Collada/duck.dae" "$OUT/Duck.glb" -f glb2 >/dev/null
cp "$M/Collada/duckCM.tga" "$OUT/"
assimp export "$M/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf" \
  "$OUT/CesiumMilkTruck.glb" -f glb2 >/dev/null
cp "$M/glTF/CesiumMilkTruck/CesiumMilkTruck.png" "$OUT/"
for name in BoxTextured Duck CesiumMilkTruck; do
  in="$OUT/$name.glb"
  s0=$(date +%s.%N)
  if ! ./build/sdcb fit "$in" -o "$OUT/$name.sdcb" --rmse "$RMSE" --quiet \
    2> >(grep -v 'pairs of triangles intersect' >&2); then
    echo "== $name: the fit refused the asset (above)"
    continue
  fi
  s1=$(date +%s.%N)
  ./build/sdcb export "$OUT/$name.sdcb" -o "$OUT/$name.out.glb" \
    --tolerance "$TOL" --quiet
  s2=$(date +%s.%N)
  ./build/sdcb export "$OUT/$name.sdcb" -o "$OUT/$name.draco.glb" \
    --tolerance "$TOL" --draco --quiet
  for kind in out draco; do
    errors=$(node scripts/gltf_tools/validate.js "$OUT/$name.$kind.glb" |
      sed -n 's/.*"errors":\([0-9]*\).*/\1/p')
    printf '== %s (%s): fit %.1f s, export %.1f s, validator errors %s, %s bytes (input %s)\n' \
      "$name" "$kind" "$(echo "$s1 - $s0" | bc)" "$(echo "$s2 - $s1" | bc)" \
      "$errors" "$(stat -c %s "$OUT/$name.$kind.glb")" "$(stat -c %s "$in")"
    ./build/bench/gltf_texture_bench "$in" "$OUT/$name.$kind.glb"
  done
  packed="$OUT/$name.gltfpack.glb"
  g0=$(date +%s.%N)
  scripts/gltf_tools/node_modules/.bin/gltfpack -i "$in" -o "$packed" -cc \
    >/dev/null
  g1=$(date +%s.%N)
  errors=$(node scripts/gltf_tools/validate.js "$packed" |
    sed -n 's/.*"errors":\([0-9]*\).*/\1/p')
  printf '== %s (gltfpack -cc): %.1f s, validator errors %s, %s bytes\n' \
    "$name" "$(echo "$g1 - $g0" | bc)" "$errors" "$(stat -c %s "$packed")"
  ./build/bench/gltf_texture_bench "$in" "$packed"
done
