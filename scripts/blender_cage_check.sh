#!/usr/bin/env bash
# Checks that a Catmull-Clark cage written by `sdcb cage` gives, in Blender,
# the limit surface its report describes (docs/CAGE.md, "Blender"):
#   1. sdcb cage MODEL -o cage.obj --faces FACES --json cage.json
#   2. Blender (headless) imports cage.obj as a mesh, adds a Subdivision
#      Surface modifier (LEVELS levels, limit surface on, Blender's
#      defaults) and writes the evaluated mesh (scripts/blender_subsurf_limit.py)
#   3. sdcb compare MODEL blender_limit.obj: the distance of Blender's limit
#      vertices to the spline (mesh -> surface) and back
# and fails unless Blender's limit -> spline rms is within 5 % of the
# report's (max within 15 %).
#
# usage: scripts/blender_cage_check.sh MODEL.sdcb [FACES=2000] [LEVELS=3] [WORK_DIR]
# (a WORK_DIR that already holds cage.obj and cage.json checks that cage)
# Needs Debian's blender package (not installed by scripts/setup.sh: it is
# large and only this check uses it): apt-get install blender
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
model="$1"
faces="${2:-2000}"
levels="${3:-3}"
work="${4:-$(mktemp -d)}"
sdcb="${SDCB:-$here/../build/sdcb}"
mkdir -p "$work"
command -v blender > /dev/null || { echo "blender_cage_check: blender is not installed" >&2; exit 1; }

if [ ! -f "$work/cage.obj" ] || [ ! -f "$work/cage.json" ]; then
  "$sdcb" cage "$model" -o "$work/cage.obj" --faces "$faces" --tolerance 0.001 \
    --json "$work/cage.json" --quiet 2> "$work/cage.stderr" || { cat "$work/cage.stderr" >&2; exit 1; }
fi
blender -b --factory-startup --python "$here/blender_subsurf_limit.py" -- \
  "$work/cage.obj" "$work/blender_limit.obj" "$levels" > "$work/blender.log" 2>&1 \
  || { cat "$work/blender.log" >&2; exit 1; }
grep '^blender:' "$work/blender.log"
"$sdcb" compare "$model" "$work/blender_limit.obj" --json "$work/compare.json" --quiet
"$sdcb" dump "$model" -o "$work/model.json"

python3 - "$work/cage.json" "$work/compare.json" "$work/model.json" "$work/blender_limit.obj" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
blender = json.load(open(sys.argv[2]))
# compare gives percent of the compared mesh's largest side, the report of
# the model's input (its normalizing scale): convert.
scale = json.load(open(sys.argv[3]))["transform"]["scale"]
lo, hi = [float("inf")] * 3, [float("-inf")] * 3
for line in open(sys.argv[4]):
    if line.startswith("v "):
        p = [float(x) for x in line.split()[1:4]]
        lo = [min(a, b) for a, b in zip(lo, p)]
        hi = [max(a, b) for a, b in zip(hi, p)]
unit = max(b - a for a, b in zip(lo, hi)) / scale
rows = [
    ("limit -> spline rms %", report["limit_to_spline_rms_percent"], unit * blender["mesh_to_surface_rms_percent"], 0.05),
    ("limit -> spline max %", report["limit_to_spline_max_percent"], unit * blender["mesh_to_surface_max_percent"], 0.15),
    ("two-sided rms %", report["limit_rmse_percent"], unit * blender["rmse_percent"], 0.05),
]
print("cage: %d faces, %d vertices (%s)" % (report["faces"], report["vertices"], report["scheme"]))
print("%-24s %12s %12s" % ("", "sdcb report", "Blender"))
ok = True
for name, ours, theirs, tolerance in rows:
    print("%-24s %12.5f %12.5f" % (name, ours, theirs))
    ok &= abs(ours - theirs) <= tolerance * ours
print("(Blender's side: sdcb compare, converted to percent of the model's input)")
if not ok:
    print("blender_cage_check: Blender's limit surface disagrees with the report", file=sys.stderr)
    sys.exit(1)
print("blender_cage_check: agree")
PY
