#!/usr/bin/env bash
# Fits every closed genus-0 mesh of one part of CGAL's data with at most MAX_VERTICES
# vertices (degree 4, --rmse RMSE, otherwise the defaults a user gets) and
# prints one Markdown table row per mesh: the honest two-sided errors the fit
# reports, the folded area, the paper's vertex errors, control points and
# time. docs/FITTING.md holds the table.
#   bench/honest_fit_table.sh [RMSE [MAX_VERTICES [OUT_DIR [TIMEOUT_S]]]]
# SDCB=path/to/sdcb runs another binary (default ./build/sdcb); MESHES="a.off
# b.off" runs only those of data/meshes.
set -uo pipefail
cd "$(dirname "$0")/.."
rmse=${1:-0.1}
max_vertices=${2:-40000}
out=${3:-/tmp/sdcb_table}
limit=${4:-900}
sdcb=${SDCB:-./build/sdcb}
mkdir -p "$out"
echo "| mesh | vertices | reached | control points | rms % | Hausdorff % | folded % | vertex rms % | vertex max % | seconds | note |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
if [ -n "${MESHES:-}" ]; then
  files=$(for m in $MESHES; do echo "data/meshes/$m"; done)
else
  files=$(ls data/meshes/*.off data/meshes/*.ply data/meshes/*.obj data/meshes/*.stl 2>/dev/null)
fi
for f in $files; do
  [ -f "$f" ] || continue
  check=$("$sdcb" check "$f" --json - 2>/dev/null)
  rc=$?
  # 1: not a closed genus-0 mesh (skipped); anything else is a failure of
  # the check itself (a binary being rebuilt, a crash), shown as a row.
  if [ $rc -ne 0 ] && [ $rc -ne 1 ]; then
    echo "| $(basename "$f") | - | - | - | - | - | - | - | - | - | check exit $rc |"
    continue
  fi
  # One closed genus-0 part (open and many-part meshes: open_parts_table.sh).
  echo "$check" | grep -q '"ok": true' || continue
  echo "$check" | grep -q '"boundary_edges": 0,' || continue
  echo "$check" | grep -q '"components": 1,' || continue
  echo "$check" | grep -q '"unreferenced_vertices": 0,' || continue
  v=$(echo "$check" | sed -n 's/.*"vertices": \([0-9]*\).*/\1/p' | head -n 1)
  [ "$v" -le "$max_vertices" ] || continue
  name=$(basename "$f")
  start=$(date +%s.%N)
  timeout "$limit" "$sdcb" fit "$f" -o "$out/$name.sdcb" --rmse "$rmse" \
    --json "$out/$name.json" --quiet 2> "$out/$name.err" > /dev/null
  rc=$?
  secs=$(echo "$(date +%s.%N) - $start" | bc)
  if [ $rc -ne 0 ] || [ ! -f "$out/$name.json" ]; then
    echo "| $name | $v | - | - | - | - | - | - | - | $(printf %.1f "$secs") | exit $rc: $(head -c 120 "$out/$name.err" | tr '\n|' '  ') |"
    continue
  fi
  /usr/bin/env python3 - "$out/$name.json" "$name" "$v" "$secs" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); f = r["final"]
note = r.get("shortfall", "")
print("| %s | %s | %s | %d | %.4f | %.3f | %.4f | %.4f | %.3f | %.1f | %s |" % (
    sys.argv[2], sys.argv[3], "yes" if r["reached_target"] else "no",
    f["control_points"], f["rmse_percent"], f["max_error_percent"],
    f["folded_area_percent"], f["vertex_rmse_percent"],
    f["vertex_max_error_percent"], float(sys.argv[4]), note))
PY
done
