#!/usr/bin/env bash
# Reproduces the numbers and the plot of docs/CAGE.md: fits bunny00 (rmse
# 0.067, as the paper) and cow, fits Catmull-Clark and Loop cages to both,
# runs bunny00's 0.05 % cages with a face budget and cage_bench (uniform
# cages pulled / fitted against the adaptive fit), draws
# docs/cage_error_vs_faces.svg. About 30 minutes on 2 cores.
#   bash bench/cage_sizes.sh [WORK_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
sdcb="$root/build/sdcb"
cmake --build "$root/build" --target cage_bench >/dev/null
work="${1:-$root/build/cage_sizes}"
mkdir -p "$work"
cd "$work"
"$sdcb" fit "$root/data/meshes/bunny00.off" -o bunny.sdcb --rmse 0.067 --quiet
"$sdcb" fit "$root/data/meshes/cow.off" -o cow.sdcb --rmse 0.067 --quiet || true
for scheme in catmark loop; do
  for tolerance in 0.1 0.05; do
    /usr/bin/time -f "  %e s wall, %M KB" "$sdcb" cage bunny.sdcb -o "bunny_${scheme}_${tolerance}.obj" \
      --scheme "$scheme" --tolerance "$tolerance" --json "bunny_${scheme}_${tolerance}.json"
  done
  /usr/bin/time -f "  %e s wall, %M KB" "$sdcb" cage cow.sdcb -o "cow_${scheme}_0.05.obj" \
    --scheme "$scheme" --tolerance 0.05 --json "cow_${scheme}_0.05.json"
done
# The face count for 0.05 %: a budget just above the interpolated need.
/usr/bin/time -f "  %e s wall, %M KB" "$sdcb" cage bunny.sdcb -o bunny_catmark_0.05_f3000.obj \
  --tolerance 0.05 --faces 3000 --json bunny_catmark_0.05_f3000.json
/usr/bin/time -f "  %e s wall, %M KB" "$sdcb" cage bunny.sdcb -o bunny_loop_0.05_f5000.obj \
  --scheme loop --tolerance 0.05 --faces 5000 --json bunny_loop_0.05_f5000.json
for scheme in catmark loop; do
  /usr/bin/time -f "  %e s wall, %U s user" "$root/build/bench/cage_bench" bunny.sdcb --scheme "$scheme"
done
python3 "$root/bench/cage_curve.py" "$root/docs/cage_error_vs_faces.svg" \
  "bunny00, Catmull-Clark=bunny_catmark_0.05.json" "bunny00, Loop=bunny_loop_0.05.json" \
  "cow, Catmull-Clark=cow_catmark_0.05.json" "cow, Loop=cow_loop_0.05.json"
