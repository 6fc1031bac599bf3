#!/usr/bin/env bash
# The main job on the bundled default: check the Stanford bunny.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
./build/sdcb check data/meshes/bunny00.off --json out/bunny00.check.json
echo "demo: wrote out/bunny00.check.json"
