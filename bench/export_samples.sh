#!/usr/bin/env bash
# Regenerates the tables of docs/EXPORT.md from fitted models: for each model
# and tolerance, the adaptive tessellation written plain, Draco and meshopt
# (GLB), its triangle count, measured distance, ratio to N_opt, bytes and
# time; every mesh goes through `sdcb check`. Prints Markdown.
#   bash bench/export_samples.sh [MODEL.sdcb ...]
# Without arguments it fits bunny00 (--rmse 0.067), bear and fandisk_large
# (--rmse 0.1, as in docs/FITTING.md's table) into out/export_bench/ first.
# The measured distance uses 40 random points per face (--measure-samples 40).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target surface_evaluation_bench >/dev/null
SDCB=./build/sdcb
OUT=out/export_bench
mkdir -p "$OUT"
models=("$@")
if [ ${#models[@]} -eq 0 ]; then
  for row in bunny00:0.067 bear:0.1 fandisk_large:0.1; do
    m=${row%%:*}
    [ -f "$OUT/$m.sdcb" ] || "$SDCB" fit "data/meshes/$m.off" -o "$OUT/$m.sdcb" --rmse "${row##*:}" --quiet
    models+=("$OUT/$m.sdcb")
  done
fi
TOLERANCES=${TOLERANCES:-"1 0.1 0.01"}
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
echo "| model | tolerance % | triangles | vertices | measured max % | certified % | triangles / N_opt | plain GLB bytes | Draco GLB bytes | meshopt GLB bytes | check | seconds |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for model in "${models[@]}"; do
  name=$(basename "$model" .sdcb)
  for tol in $TOLERANCES; do
    base="$OUT/${name}_$tol"
    "$SDCB" export "$model" -o "$base.glb" --tolerance "$tol" --json "$base.json" --measure-samples 40 --quiet
    "$SDCB" export "$model" -o "$base.draco.glb" --tolerance "$tol" --draco --json "$base.draco.json" --quiet
    "$SDCB" export "$model" -o "$base.meshopt.glb" --tolerance "$tol" --meshopt --json "$base.meshopt.json" --quiet
    "$SDCB" export "$model" -o "$base.obj" --tolerance "$tol" --quiet
    if "$SDCB" check "$base.obj" > /dev/null 2>&1; then check=ok; else check=FAILED; fi
    j="$base.json"
    printf "| %s | %s | %s | %s | %.4f | %.4f | %.2f | %s | %s | %s | %s | %.1f |\n" "$name" "$tol" \
      "$(json "$j" "d['triangles']")" "$(json "$j" "d['vertices']")" \
      "$(json "$j" "d['max_distance_percent']")" "$(json "$j" "d['certified_distance_percent']")" \
      "$(json "$j" "d['triangles_vs_optimum']")" "$(json "$j" "d['bytes']")" \
      "$(json "$base.draco.json" "d['bytes']")" "$(json "$base.meshopt.json" "d['bytes']")" \
      "$check" "$(json "$j" "d['seconds']['tessellate']")"
  done
done
echo
echo "Evaluation speed (one thread):"
./build/bench/surface_evaluation_bench "${models[0]}"
