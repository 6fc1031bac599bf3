#!/usr/bin/env bash
# docs/CAD.md's table: fits bunny00, cow and bull (rmse 0.067 %), exports each
# to STEP (default tolerance 0.05 %, 10 deg) and bunny00 also to IGES, then
# re-reads every file with OpenCASCADE and compares it with the spline
# (build/bench/cad_reread_bench) and, where freecadcmd exists, imports it
# into FreeCAD (scripts/freecad_step_check.sh).
#
#   bash bench/cad_export_table.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/sdcb_cad_table}
mkdir -p "$out"
for m in bunny00 cow bull; do
  [ -f "$out/$m.sdcb" ] || ./build/sdcb fit "data/meshes/$m.off" -o "$out/$m.sdcb" \
    --rmse 0.067 --quiet --json "$out/$m.fit.json" || true
  exts="step"
  [ "$m" = bunny00 ] && exts="step igs"
  for ext in $exts; do
    f="$out/$m.$ext"
    [ -f "$f.json" ] || /usr/bin/time -f "%e s wall, %M KB peak" \
      ./build/sdcb export "$out/$m.sdcb" -o "$f" --json "$f.json" --quiet
    python3 -c "
import json, sys
j = json.load(open(sys.argv[1]))
print(sys.argv[1], {k: j[k] for k in ('faces', 'max_distance_percent',
      'rms_distance_percent', 'measured_points', 'max_normal_angle_degrees',
      'max_normal_jump_degrees', 'volume', 'area', 'rounds', 'seconds')})
" "$f.json"
    ./build/bench/cad_reread_bench "$out/$m.sdcb" "$f"
    if command -v freecadcmd >/dev/null; then
      bash scripts/freecad_step_check.sh "$f" "$f.json"
    fi
  done
done
