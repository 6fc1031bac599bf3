#!/usr/bin/env bash
# CGAL's open genus-0 meshes (and bones.off, 26 closed parts) fitted at
# --rmse RMSE, exported to OBJ at --tolerance TOL, and the export measured
# against the input by open_parts_bench (dense two-sided distance, boundary
# loops, boundary distance, per part): one Markdown row per mesh.
# docs/FITTING.md holds the table.
#   bench/open_parts_table.sh [RMSE [TOL [OUT_DIR [TIMEOUT_S]]]]
# SDCB=path/to/sdcb runs another binary (default ./build/sdcb); MESHES="a.off
# b.off" runs only those of data/meshes.
set -uo pipefail
cd "$(dirname "$0")/.."
rmse=${1:-0.1}
tol=${2:-0.1}
out=${3:-/tmp/sdcb_open}
limit=${4:-900}
sdcb=${SDCB:-./build/sdcb}
mkdir -p "$out"
cmake --build build --target open_parts_bench > /dev/null || exit 1
meshes=${MESHES:-"lion-head.off mannequin-devil.off nefertiti.off mushroom.off three_peaks.off cylinder.off blade.off ChineseDragon-10kv.off head.off mech-holes-shark.off holes.off lion.off pig.off patch-01.off plane.off bones.off"}
echo "| mesh | vertices | parts | loops | reached | control points | fit s | export triangles | export s | rms % | Hausdorff % | boundary % | loops out |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for m in $meshes; do
  f=data/meshes/$m
  [ -f "$f" ] || { echo "| $m | missing |"; continue; }
  v=$("$sdcb" check "$f" --json - 2>/dev/null | sed -n 's/^  "vertices": \([0-9]*\).*/\1/p' | head -n 1)
  start=$(date +%s.%N)
  timeout "$limit" "$sdcb" fit "$f" -o "$out/$m.sdcb" --rmse "$rmse" \
    --json "$out/$m.fit.json" --quiet 2> "$out/$m.fit.err"
  rc=$?
  fit_s=$(echo "$(date +%s.%N) - $start" | bc)
  if [ $rc -ne 0 ]; then
    echo "| $m | $v | - | - | exit $rc | - | $(printf %.1f "$fit_s") | - | - | - | - | - | $(head -c 120 "$out/$m.fit.err" | tr '\n|' '  ') |"
    continue
  fi
  summary=$(python3 - "$out/$m.fit.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
parts = r.get("parts") or [r]
loops = sum(p.get("boundary_loops", 0) for p in parts)
cps = sum(p["final"]["control_points"] for p in parts)
reached = sum(1 for p in parts if p["reached_target"])
print(len(parts), loops, f"{reached}/{len(parts)}", cps)
PY
)
  read -r parts loops reached cps <<< "$summary"
  start=$(date +%s.%N)
  "$sdcb" export "$out/$m.sdcb" -o "$out/$m.obj" --tolerance "$tol" --quiet \
    > /dev/null 2> "$out/$m.export.err"
  rc=$?
  export_s=$(echo "$(date +%s.%N) - $start" | bc)
  if [ $rc -ne 0 ]; then
    echo "| $m | $v | $parts | $loops | $reached | $cps | $(printf %.1f "$fit_s") | export exit $rc | | | | | $(head -c 120 "$out/$m.export.err" | tr '\n|' '  ') |"
    continue
  fi
  tris=$(grep -c '^f ' "$out/$m.obj")
  line=$(./build/bench/open_parts_bench "$f" "$out/$m.obj" | tee "$out/$m.bench.txt" | grep '^SUMMARY')
  rms=$(echo "$line" | sed -n 's/.*max_rms \([0-9.]*\)%.*/\1/p')
  h=$(echo "$line" | sed -n 's/.*max_hausdorff \([0-9.]*\)%.*/\1/p')
  b=$(echo "$line" | sed -n 's/.*max_boundary \([0-9.a-z]*\)%.*/\1/p')
  loops_out=$(grep -o 'loops [0-9]* / [0-9]*' "$out/$m.bench.txt" | awk '{s+=$4} END {print s}')
  [ -n "$line" ] || { rms=-; h=-; b=-; loops_out="$(head -n 1 "$out/$m.bench.txt")"; }
  echo "| $m | $v | $parts | $loops | $reached | $cps | $(printf %.1f "$fit_s") | $tris | $(printf %.1f "$export_s") | $rms | $h | $b | $loops_out |"
done
