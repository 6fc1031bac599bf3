#!/usr/bin/env bash
# Every OBJ, PLY, OFF and STL file of Debian's assimp-testmodels (real files
# from many writers, and assimp's own broken ones) through `sdcb check` and
# `sdcb fit --rmse RMSE`, each with a timeout: one Markdown row per file with
# its triangles, its parts (closed / open), the outcome (reached, missed, or
# the refusal sentence) and the seconds of the fit. docs/INTAKE.md holds the
# table. About a minute on 2 cores.
#   bench/assimp_models_table.sh [RMSE [OUT_DIR [TIMEOUT_S]]]
# SDCB=path/to/sdcb runs another binary (default ./build/sdcb).
set -uo pipefail
cd "$(dirname "$0")/.."
rmse=${1:-0.5}
out=${2:-/tmp/sdcb_assimp}
limit=${3:-120}
sdcb=${SDCB:-./build/sdcb}
mkdir -p "$out"
files=$(dpkg -L assimp-testmodels 2>/dev/null | grep -iE '\.(obj|ply|off|stl)$' | sort)
[ -n "$files" ] || { echo "assimp-testmodels is not installed" >&2; exit 1; }
echo "| file | triangles | parts (closed / open) | outcome | fit s |"
echo "|---|---|---|---|---|"
for f in $files; do
  name=${f#/usr/share/assimp/models/}
  base=$out/$(echo "$name" | tr '/' '_')
  timeout "$limit" "$sdcb" check "$f" --json "$base.check.json" --quiet \
    2> "$base.check.err"
  read -r tris parts <<< "$(python3 - "$base.check.json" <<'PY'
import json, sys
try:
    r = json.load(open(sys.argv[1]))
except Exception:
    print("- -"); sys.exit()
p = r.get("parts")
if p is None:
    print(r["faces"], "not split")
else:
    closed = sum(1 for x in p if x["closed"])
    print(r["faces"], f"{len(p)} ({closed} / {len(p) - closed})")
PY
)"
  start=$(date +%s.%N)
  timeout "$limit" "$sdcb" fit "$f" -o "$base.sdcb" --rmse "$rmse" \
    --json "$base.fit.json" --quiet > /dev/null 2> "$base.fit.err"
  rc=$?
  secs=$(printf %.1f "$(echo "$(date +%s.%N) - $start" | bc)")
  if [ $rc -eq 0 ]; then
    outcome=$(python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print("reached" if r["reached_target"] else "missed")' "$base.fit.json")
  elif [ $rc -eq 124 ]; then
    outcome="timeout after ${limit} s"
  else
    # The refusal: the last "sdcb: FILE: ..." line, without the path.
    outcome="exit $rc: $(grep -v ': warning: ' "$base.fit.err" | tail -n 1 | sed "s|^sdcb: $f: ||" | tr '|' '/')"
  fi
  echo "| $name | $tris | $parts | $outcome | $secs |"
done
