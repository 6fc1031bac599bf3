#!/usr/bin/env bash
# Imports a STEP or IGES file written by `sdcb export` into FreeCAD (headless
# freecadcmd, Debian's `freecad` package) and checks that it is one valid,
# closed solid; prints FreeCAD's volume, area and face count, and compares
# the volume and area with the report's when a JSON report is given.
#
#   bash scripts/freecad_step_check.sh OUT.step [OUT.step.json]
#
# Exit 0: FreeCAD reads one valid closed solid (and its volume and area are
# the report's within 1e-5: FreeCAD integrates with a fixed rule, which is
# ~1e-6 off on faces of many knot spans; the report's are exact). Exit 1 otherwise; exit 2 if freecadcmd is missing.
set -euo pipefail
file=${1:?usage: freecad_step_check.sh FILE.step|FILE.igs [REPORT.json]}
report=${2:-}
if ! command -v freecadcmd >/dev/null; then
  echo "freecad_step_check: freecadcmd not found (apt-get install freecad)" >&2
  exit 2
fi
script=$(mktemp --suffix=.py)
out=$(mktemp)
trap 'rm -f "$script" "$out"' EXIT
cat >"$script" <<'EOF'
import json, os, sys
import Part
path = os.environ["SDCB_CAD_FILE"]
report = os.environ.get("SDCB_CAD_REPORT", "")
shape = Part.Shape()
shape.read(path)
solids = shape.Solids
ok = len(solids) == 1 and shape.isValid() and all(s.isClosed() for s in shape.Shells)
result = {"solids": len(solids), "shells": len(shape.Shells),
          "faces": len(shape.Faces), "valid": shape.isValid(),
          "closed": all(s.isClosed() for s in shape.Shells),
          "volume": shape.Volume, "area": shape.Area}
if report:
    with open(report) as f:
        expected = json.load(f)
    result["report_volume"] = expected["volume"]
    result["report_area"] = expected["area"]
    ok = (ok and abs(shape.Volume / expected["volume"] - 1.0) < 1e-5
          and abs(shape.Area / expected["area"] - 1.0) < 1e-5)
result["ok"] = ok
print("SDCB_FREECAD " + json.dumps(result))
EOF
SDCB_CAD_FILE=$(realpath "$file") SDCB_CAD_REPORT=${report:+$(realpath "$report")} \
  freecadcmd "$script" >"$out" 2>&1 || true
line=$(grep '^SDCB_FREECAD ' "$out" || true)
if [ -z "$line" ]; then
  echo "freecad_step_check: FreeCAD did not read $file:" >&2
  cat "$out" >&2
  exit 1
fi
echo "${line#SDCB_FREECAD }"
case "$line" in
  *'"ok": true'*) exit 0 ;;
  *) exit 1 ;;
esac
