#!/usr/bin/env bash
# Installs what sdcb needs on Debian 12 (only what is missing), extracts CGAL's
# sample meshes into data/meshes, and builds into build/. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/debian_packages.sh

PACKAGES=(build-essential cmake ninja-build pkg-config
  libeigen3-dev libcgal-dev libcgal-demo libopenmesh-dev libtinygltf-dev
  nlohmann-json3-dev libosd-dev libdraco-dev libgtest-dev libtbb-dev
  libsuitesparse-dev libopenblas0-serial zlib1g-dev libmeshoptimizer-dev
  # stb_image / stb_image_write: the glTF texture bake's image codecs.
  libstb-dev
  # The glTF reader's tests: the glTF 2 files of assimp-testmodels, and the
  # Khronos Duck converted from its COLLADA duck.dae by `assimp export`.
  assimp-testmodels assimp-utils
  clang libclang-rt-14-dev
  slurmctld slurmd slurm-client munge
  libocct-foundation-dev libocct-modeling-data-dev
  libocct-modeling-algorithms-dev libocct-data-exchange-dev)

install_missing_packages setup "${PACKAGES[@]}"

# CGAL's test meshes (bunny00, fandisk, ...) from libcgal-demo's data.tar.gz.
if [ ! -f data/meshes/bunny00.off ]; then
  archive=$(dpkg -L libcgal-demo | grep '/data.tar.gz$' | head -n 1)
  if [ -z "$archive" ] || [ ! -f "$archive" ]; then
    echo "setup: libcgal-demo's data.tar.gz was not found" >&2
    exit 1
  fi
  rm -rf data/meshes.tmp && mkdir -p data/meshes.tmp
  tar -xzf "$archive" -C data/meshes.tmp data/meshes
  rm -rf data/meshes && mv data/meshes.tmp/data/meshes data/meshes && rm -rf data/meshes.tmp
  echo "setup: extracted $(ls data/meshes | wc -l) meshes into data/meshes"
fi

# Node.js + npm (Debian's, if no node is installed) and the npm glTF tools
# the tests use (Khronos glTF validator, glTF Transform), installed into
# scripts/gltf_tools/node_modules: nothing global.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "setup: installing nodejs npm"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm
fi
if [ ! -f scripts/gltf_tools/node_modules/.sdcb-installed ] ||
   [ scripts/gltf_tools/package.json -nt scripts/gltf_tools/node_modules/.sdcb-installed ]; then
  echo "setup: installing the npm glTF tools into scripts/gltf_tools/node_modules"
  # --ignore-scripts: no install script may download binaries (sharp's).
  (cd scripts/gltf_tools && npm install --no-audit --no-fund --ignore-scripts --loglevel=error)
  touch scripts/gltf_tools/node_modules/.sdcb-installed
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > build.configure.log 2>&1 || {
  cat build.configure.log >&2; exit 1; }
rm -f build.configure.log
cmake --build build -j "$(nproc)"
