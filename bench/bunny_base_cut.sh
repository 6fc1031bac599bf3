#!/usr/bin/env bash
# bunny00 against bunny00 with its base cut off (the triangles whose
# vertices all lie within CUT of the bottom of its bounding box, in percent of
# its height; a scan's usual hole; the first of CUT, CUT + 0.5, ... that
# leaves one manifold part): fit time and control points of both at --rmse
# RMSE, and the open one exported at --tolerance TOL and measured by
# open_parts_bench. docs/PARTS.md holds the numbers.
#   bench/bunny_base_cut.sh [RMSE [TOL [CUT [OUT_DIR]]]]
set -euo pipefail
cd "$(dirname "$0")/.."
rmse=${1:-0.1}
tol=${2:-0.1}
cut=${3:-3}
out=${4:-/tmp/sdcb_bunny_cut}
sdcb=${SDCB:-./build/sdcb}
mkdir -p "$out"
cmake --build build --target open_parts_bench > /dev/null
for attempt in 0 1 2 3 4 5 6 7; do
  python3 - data/meshes/bunny00.off "$out/bunny00_open.off" "$cut" <<'PY'
import sys
src, dst, cut = sys.argv[1], sys.argv[2], float(sys.argv[3])
tokens = open(src).read().split()
assert tokens[0] == "OFF"
nv, nf = int(tokens[1]), int(tokens[2])
v = [tuple(map(float, tokens[4 + 3 * i: 7 + 3 * i])) for i in range(nv)]
at = 4 + 3 * nv
faces = []
for _ in range(nf):
    n = int(tokens[at]); faces.append(tuple(map(int, tokens[at + 1: at + 1 + n]))); at += 1 + n
# The up axis: the bounding box's axis whose lowest 1 % holds the flattest
# part is not needed; bunny00 stands on -y.
ys = [p[1] for p in v]
low, high = min(ys), max(ys)
limit = low + cut / 100 * (high - low)
kept = [f for f in faces if not all(v[i][1] < limit for i in f)]
used = sorted({i for f in kept for i in f})
row = {old: new for new, old in enumerate(used)}
with open(dst, "w") as o:
    o.write(f"OFF\n{len(used)} {len(kept)} 0\n")
    for i in used: o.write("%.17g %.17g %.17g\n" % v[i])
    for f in kept: o.write("3 %d %d %d\n" % tuple(row[i] for i in f))
print(f"cut {nf - len(kept)} of {nf} triangles below y = {limit:.6g}")
PY
  if "$sdcb" check "$out/bunny00_open.off" --json "$out/cut.json" > /dev/null 2>&1 &&
     grep -q '"components": 1,' "$out/cut.json"; then
    break
  fi
  cut=$(echo "$cut + 0.5" | bc)
done
"$sdcb" check "$out/bunny00_open.off" | grep -i "part 1"
for m in bunny00 bunny00_open; do
  f=data/meshes/$m.off; [ "$m" = bunny00_open ] && f=$out/$m.off
  start=$(date +%s.%N)
  "$sdcb" fit "$f" -o "$out/$m.sdcb" --rmse "$rmse" --json "$out/$m.json" --quiet
  s=$(echo "$(date +%s.%N) - $start" | bc)
  python3 - "$out/$m.json" "$m" "$s" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
p = (r.get("parts") or [r])[0]
f = p["final"]
print(f"{sys.argv[2]}: {float(sys.argv[3]):.1f} s, {f['control_points']} control points, "
      f"rms {f['rmse_percent']:.4f}%, max {f['max_error_percent']:.4f}%, reached {p['reached_target']}")
PY
done
"$sdcb" export "$out/bunny00_open.sdcb" -o "$out/bunny00_open.obj" --tolerance "$tol" --quiet > /dev/null
./build/bench/open_parts_bench "$out/bunny00_open.off" "$out/bunny00_open.obj"
