#!/usr/bin/env bash
# Fits whose outcome turns on a round's luck (reaching the target or not,
# control points at the threshold) judged over nearby runs: every mesh
# fitted at --rmse RMSE with --lambda at each of LAMBDAS (the map's energy
# exponent, moved by a hair), one Markdown row per fit. Compare two builds
# by running it with each (docs/FITTING.md, "Small folds repaired").
#   SDCB=build/sdcb bash bench/perturbed_fits.sh [RMSE] [OUT] [MESH...]
# Environment: LAMBDAS (default "0.998 0.999 1 1.001 1.002"); FIT_ARGS,
# more options for every fit (e.g. "--map-vertices 0").
set -uo pipefail
cd "$(dirname "$0")/.."
rmse=${1:-0.1}
out=${2:-/tmp/sdcb_perturbed}
if [ $# -ge 2 ]; then shift 2; else set --; fi
meshes=${*:-armadillo.off hand.off homer.off oblong.off triceratops.off}
lambdas=${LAMBDAS:-0.998 0.999 1 1.001 1.002}
sdcb=${SDCB:-./build/sdcb}
mkdir -p "$out"
echo "| mesh | lambda | reached | control points | rms % | Hausdorff % | folded % | seconds |"
echo "|---|---|---|---|---|---|---|---|"
for m in $meshes; do
  for l in $lambdas; do
    json="$out/$m.$l.json"
    start=$(date +%s.%N)
    "$sdcb" fit "data/meshes/$m" -o "$out/$m.$l.sdcb" --rmse "$rmse" \
      --lambda "$l" --json "$json" --quiet ${FIT_ARGS:-} > /dev/null 2>&1
    rc=$?
    secs=$(echo "$(date +%s.%N) - $start" | bc)
    if [ $rc -ne 0 ] || [ ! -f "$json" ]; then
      echo "| $m | $l | exit $rc | - | - | - | - | $(printf %.1f "$secs") |"
      continue
    fi
    python3 - "$json" "$m" "$l" "$secs" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); f = r["final"]
print("| %s | %s | %s | %d | %.4f | %.3f | %.4f | %.1f |" % (
    sys.argv[2], sys.argv[3], "yes" if r["reached_target"] else "no",
    f["control_points"], f["rmse_percent"], f["max_error_percent"],
    f["folded_area_percent"], float(sys.argv[4])))
PY
  done
done
