#!/usr/bin/env bash
# What the converters cost and what they hold, side by side with gltfpack
# (meshoptimizer's simplifier on the input mesh, the tool an asset pipeline
# would use instead). Prints Markdown tables:
#   1. per model (bunny00 at --rmse 0.067; bear, fandisk_large at 0.1) and
#      tolerance (1, 0.1, 0.01 %): the plain GLB export's wall and CPU
#      seconds and its stage seconds, triangles, triangles / N_opt, and the
#      distance measured independently of the tessellator: `sdcb compare`
#      (CGAL's AABB tree, both ways) with 40 samples per triangle each way;
#   2. bunny00 at 0.1 % with --draco;
#   3. gltfpack -si 0 -se (tolerance / 100) -cc on the input mesh: seconds,
#      triangles, bytes;
#   4. bunny00's cage (--tolerance 0.1) and STEP (defaults), and the bull's
#      folded model at 0.05 % (refused at once: its fit measured folds;
#      bounded by a 120 s timeout all the same).
#   bash bench/export_speed.sh            (all of it; ~15 min on 2 cores)
#   MODELS="bunny00" TOLERANCES="1 0.1" bash bench/export_speed.sh
# Needs the build (scripts/setup.sh) and scripts/gltf_tools (gltfpack).
set -euo pipefail
cd "$(dirname "$0")/.."
SDCB=./build/sdcb
GLTFPACK=scripts/gltf_tools/node_modules/.bin/gltfpack
OUT=out/export_speed
mkdir -p "$OUT"
MODELS=${MODELS:-"bunny00 bear fandisk_large"}
TOLERANCES=${TOLERANCES:-"1 0.1 0.01"}
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
# timed LOG COMMAND...: runs COMMAND, its wall and CPU seconds into LOG.
timed() {
  local log=$1
  shift
  /usr/bin/time -f "%e %U %S" -o "$log" "$@"
}
wall() { tail -n 1 "$1" | awk '{print $1}'; }
cpu() { tail -n 1 "$1" | awk '{printf "%.2f", $2 + $3}'; }
rmse() { [ "$1" = bunny00 ] && echo 0.067 || echo 0.1; }

for m in $MODELS; do
  [ -f "$OUT/$m.sdcb" ] ||
    "$SDCB" fit "data/meshes/$m.off" -o "$OUT/$m.sdcb" --rmse "$(rmse "$m")" --quiet
done

echo "| model | tolerance % | wall s | CPU s | samples / simplify / verify / measure / optimum s | triangles | x N_opt | compare spline -> mesh % | compare mesh -> spline % |"
echo "|---|---|---|---|---|---|---|---|---|"
for m in $MODELS; do
  for tol in $TOLERANCES; do
    base="$OUT/${m}_$tol"
    timed "$base.time" "$SDCB" export "$OUT/$m.sdcb" -o "$base.glb" \
      --tolerance "$tol" --json "$base.json" --quiet
    "$SDCB" export "$OUT/$m.sdcb" -o "$base.obj" --tolerance "$tol" --quiet \
      --measure-samples 0
    n=$(json "$base.json" "d['triangles']")
    "$SDCB" compare "$OUT/$m.sdcb" "$base.obj" --samples $((40 * n)) \
      --mesh-samples $((40 * n)) --json "$base.compare.json" > /dev/null
    printf "| %s | %s | %s | %s | %s | %s | %.3f | %.4f | %.4f |\n" "$m" "$tol" \
      "$(wall "$base.time")" "$(cpu "$base.time")" \
      "$(json "$base.json" "'%.2f / %.2f / %.2f / %.2f / %.2f' % tuple(d['seconds'][k] for k in ('samples','simplify','verify','measure','optimum'))")" \
      "$n" "$(json "$base.json" "d['triangles_vs_optimum']")" \
      "$(json "$base.compare.json" "d['surface_to_mesh_max_percent']")" \
      "$(json "$base.compare.json" "d['mesh_to_surface_max_percent']")"
  done
done

echo
first=${MODELS%% *}
timed "$OUT/draco.time" "$SDCB" export "$OUT/$first.sdcb" -o "$OUT/${first}_draco.glb" \
  --tolerance 0.1 --draco --json "$OUT/draco.json" --quiet
echo "$first --draco at 0.1 %: $(wall "$OUT/draco.time") s wall, $(cpu "$OUT/draco.time") s CPU, $(json "$OUT/draco.json" "d['triangles']") triangles, $(json "$OUT/draco.json" "d['bytes']") bytes"

echo
echo "| gltfpack on the input | -se | wall s | CPU s | triangles | bytes |"
echo "|---|---|---|---|---|---|"
for m in $MODELS; do
  obj="$OUT/$m.input.obj"
  [ -f "$obj" ] || python3 - "data/meshes/$m.off" "$obj" <<'EOF'
import sys
words = open(sys.argv[1]).read().split()
assert words[0] == "OFF"
nv, nf = int(words[1]), int(words[2])
at = 4
with open(sys.argv[2], "w") as out:
    for _ in range(nv):
        out.write("v %s %s %s\n" % tuple(words[at:at + 3]))
        at += 3
    for _ in range(nf):
        k = int(words[at])
        out.write("f " + " ".join(str(int(w) + 1) for w in words[at + 1:at + 1 + k]) + "\n")
        at += 1 + k
EOF
  for tol in $TOLERANCES; do
    se=$(python3 -c "print($tol / 100)")
    g="$OUT/${m}_${tol}.gltfpack.glb"
    timed "$g.time" "$GLTFPACK" -i "$obj" -o "$g" -si 0 -se "$se" -cc > /dev/null
    printf "| %s | %s | %s | %s | %s | %s |\n" "$m" "$se" "$(wall "$g.time")" \
      "$(cpu "$g.time")" \
      "$(node scripts/gltf_tools/decode.mjs "$g" | python3 -c "import json,sys; print(json.load(sys.stdin)['triangles'])")" \
      "$(stat -c %s "$g")"
  done
done

echo
timed "$OUT/cage.time" "$SDCB" cage "$OUT/$first.sdcb" -o "$OUT/${first}_cage.obj" \
  --tolerance 0.1 --quiet
echo "$first cage --tolerance 0.1: $(wall "$OUT/cage.time") s wall, $(cpu "$OUT/cage.time") s CPU"
timed "$OUT/step.time" "$SDCB" export "$OUT/$first.sdcb" -o "$OUT/$first.step" --quiet
echo "$first STEP: $(wall "$OUT/step.time") s wall, $(cpu "$OUT/step.time") s CPU"

if [ -z "${SKIP_BULL:-}" ]; then
  [ -f "$OUT/bull.sdcb" ] ||
    "$SDCB" fit data/meshes/bull.off -o "$OUT/bull.sdcb" --rmse 0.1 --quiet
  rc=0
  timed "$OUT/bull.time" timeout 120 "$SDCB" export "$OUT/bull.sdcb" \
    -o "$OUT/bull.glb" --tolerance 0.05 --json "$OUT/bull.json" --quiet || rc=$?
  echo "bull (folded) at 0.05 %: exit $rc, $(wall "$OUT/bull.time") s wall$( [ $rc = 0 ] && echo ", $(json "$OUT/bull.json" "d['triangles']") triangles")"
fi
