#!/usr/bin/env bash
# docs/CAD.md's table: fits bunny00 (rmse 0.067 %), bear and fandisk_large
# (rmse 0.1 %), exports each to STEP with the defaults (tolerance 0.05 %,
# smoothness 0.5 deg) and bunny00 also to IGES, then re-reads every file
# with OpenCASCADE and compares it with the spline, distances both ways and
# the normal jump across every re-read edge (build/bench/cad_reread_bench),
# and, where freecadcmd exists, imports it into FreeCAD
# (scripts/freecad_step_check.sh: one valid solid, volume and area).
#
#   bash bench/cad_export_table.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target cad_reread_bench >/dev/null
out=${1:-/tmp/sdcb_cad_table}
mkdir -p "$out"
for m in bunny00 bear fandisk_large; do
  rmse=0.1
  [ "$m" = bunny00 ] && rmse=0.067
  [ -f "$out/$m.sdcb" ] || ./build/sdcb fit "data/meshes/$m.off" -o "$out/$m.sdcb" \
    --rmse "$rmse" --quiet --json "$out/$m.fit.json"
  exts="step"
  [ "$m" = bunny00 ] && exts="step igs"
  for ext in $exts; do
    f="$out/$m.$ext"
    /usr/bin/time -f "%e s wall, %U s user, %M KB peak" \
      ./build/sdcb export "$out/$m.sdcb" -o "$f" --json "$f.json" --quiet
    python3 -c "
import json, sys
j = json.load(open(sys.argv[1]))
print(sys.argv[1], {k: j[k] for k in ('faces', 'control_points', 'bytes',
      'max_distance_percent', 'rms_distance_percent', 'measured_points',
      'max_normal_angle_degrees', 'max_normal_jump_degrees', 'jump_points',
      'volume', 'area', 'valid', 'rounds', 'seconds')})
" "$f.json"
    ./build/bench/cad_reread_bench "$out/$m.sdcb" "$f"
    if command -v freecadcmd >/dev/null; then
      bash scripts/freecad_step_check.sh "$f" "$f.json"
    fi
  done
done
