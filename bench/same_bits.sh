#!/usr/bin/env bash
# Prints the SHA-256 of the artifacts a change that should not move a bit
# must leave byte-identical: bunny00 fitted at the paper's 0.067 % and its
# exports (OBJ and Draco GLB at --tolerance 0.1, STEP, Catmull-Clark cage),
# and with --table the model of every fit of bench/honest_fit_table.sh
# (the 58 closed genus-0 CGAL meshes at --rmse 0.1; about 15 min on 2 cores).
# Run it with two binaries and diff the outputs:
#   SDCB=old/sdcb bench/same_bits.sh /tmp/old [--table] > old.txt
#   SDCB=new/sdcb bench/same_bits.sh /tmp/new [--table] > new.txt
#   diff old.txt new.txt
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bench/same_bits.sh OUT_DIR [--table]}
table=${2:-}
sdcb=${SDCB:-./build/sdcb}
mkdir -p "$out"
model="$out/bunny00.sdcb"
"$sdcb" fit data/meshes/bunny00.off -o "$model" --rmse 0.067 --quiet > /dev/null
"$sdcb" export "$model" -o "$out/bunny00.obj" --tolerance 0.1 --quiet > /dev/null
"$sdcb" export "$model" -o "$out/bunny00_draco.glb" --tolerance 0.1 --draco \
  --quiet > /dev/null
"$sdcb" export "$model" -o "$out/bunny00.step" --quiet > /dev/null
"$sdcb" cage "$model" -o "$out/bunny00_cage.obj" --quiet > /dev/null
(cd "$out" && sha256sum bunny00.sdcb bunny00.obj bunny00_draco.glb \
  bunny00.step bunny00_cage.obj)
if [ "$table" = --table ]; then
  SDCB="$sdcb" bash bench/honest_fit_table.sh 0.1 40000 "$out/table" > \
    "$out/table.md"
  (cd "$out/table" && sha256sum -- *.sdcb)
fi
