#!/usr/bin/env bash
# Checks that Blender imports the creases of a cage written by `sdcb cage`
# as FBX (docs/CAGE.md, "Creases in Blender"):
#   1. sdcb fit MESH -o model.sdcb --rmse 0.1 (sharp edges kept)
#   2. sdcb cage model.sdcb -o cage.fbx --json cage.json
#   3. Blender (headless) imports cage.fbx (scripts/blender_fbx_creases.py)
#      and prints its vertex, face and creased-edge counts, and how far its
#      subdivided mesh is from the cage's corners
# and fails unless Blender's counts equal the report's `vertices`, `faces`
# and `creases` (at least one crease) and the corners stay put.
#
# usage: scripts/blender_crease_check.sh MESH [WORK_DIR]
#   e.g. scripts/blender_crease_check.sh data/meshes/cube.off   (12 creases)
# Needs Debian's blender package (not installed by scripts/setup.sh: it is
# large and only the Blender checks use it): apt-get install blender
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
mesh="$1"
work="${2:-$(mktemp -d)}"
sdcb="${SDCB:-$here/../build/sdcb}"
mkdir -p "$work"
command -v blender > /dev/null || { echo "blender_crease_check: blender is not installed" >&2; exit 1; }

"$sdcb" fit "$mesh" -o "$work/model.sdcb" --rmse 0.1 --quiet
"$sdcb" cage "$work/model.sdcb" -o "$work/cage.fbx" --json "$work/cage.json" --quiet
read -r vertices faces creases < <(python3 -c '
import json, sys
r = json.load(open(sys.argv[1]))
print(r["vertices"], r["faces"], r["creases"])' "$work/cage.json")
echo "sdcb: cage.fbx: $vertices vertices, $faces faces, $creases creases"
if [ "$creases" -lt 1 ]; then
  echo "blender_crease_check: the cage has no creases (a model that kept its sharp edges, whose arcs make quads, has)" >&2
  exit 1
fi
blender -b --factory-startup --python-exit-code 1 \
  --python "$here/blender_fbx_creases.py" -- \
  "$work/cage.fbx" "$vertices" "$faces" "$creases" > "$work/blender.log" 2>&1 \
  || { cat "$work/blender.log" >&2; exit 1; }
grep -E '^(blender|blender_fbx_creases):' "$work/blender.log"
