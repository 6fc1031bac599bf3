#!/usr/bin/env bash
# Pictures of textured glTF assets written back by sdcb: per asset
# (BoxTextured and the Duck of bench/gltf_assets.sh) `sdcb fit IN.glb -o
# X.sdcb --rmse 0.1` and `sdcb export X.sdcb -o X.out.glb --tolerance 0.1`,
# then Blender (headless, Cycles on the CPU, bench/render_gltf.py) renders
# IN.glb and X.out.glb with one camera, and ImageMagick's montage puts them
# side by side, their triangles below, into docs/images/gltf_asset_NAME.png.
# Prints each file it writes. Installs what is missing (Debian 12): blender,
# python3-numpy (its glTF importer), imagemagick, fonts-dejavu-core (the
# labels' font), assimp-utils and assimp-testmodels.
# 2CylinderEngine is not among them: its fit at --rmse 0.1 had not ended
# after 25 minutes on the shared 2-core machine.
#
# usage: bench/render_assets.sh [WORK_DIR]
#   WORK_DIR  the assets, models and renders (default /tmp/sdcb_render_assets)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/debian_packages.sh
source bench/gltf_assets.sh
RMSE=0.1
TOL=0.1
WIDTH=480   # each of the four views
HEIGHT=360
SAMPLES=64  # Cycles' samples per pixel (Debian's Blender has no denoiser)

WORK=${1:-/tmp/sdcb_render_assets}

install_missing_packages render_assets blender python3-numpy imagemagick \
  fonts-dejavu-core assimp-utils assimp-testmodels
cmake --build build --target sdcb >/dev/null
mkdir -p docs/images

azimuth() {  # the 3/4 view of each asset, degrees about Blender's Z (glTF's +Y)
  case "$1" in
    Duck) echo 40 ;;  # its face, not its back
    *) echo -35 ;;
  esac
}

for name in BoxTextured Duck; do
  gltf_asset_input "$name" "$WORK"
  if ! gltf_asset_fit_export "$name" "$RMSE" "$TOL" "$WORK"; then
    echo "render_assets: $name: the fit refused the asset (above)"
    continue
  fi
  views="$WORK/$name.views"
  mkdir -p "$views"
  s0=$(date +%s.%N)
  blender -b --factory-startup -P bench/render_gltf.py -- "$WORK/$name.glb" \
    "$WORK/$name.out.glb" "$views" "$WIDTH" "$HEIGHT" "$SAMPLES" "$(azimuth "$name")" 25 \
    >"$views/blender.log" 2>&1 || { cat "$views/blender.log" >&2; exit 1; }
  s1=$(date +%s.%N)
  n_in=$(sed -n 's/^input //p' "$views/counts.txt")
  n_out=$(sed -n 's/^output //p' "$views/counts.txt")
  picture=docs/images/gltf_asset_$name.png
  montage -font DejaVu-Sans -pointsize 16 -background white \
    -label "input: $n_in triangles" "$views/input.png" \
    -label "sdcb output at --tolerance $TOL: $n_out triangles" "$views/output.png" \
    -label "input's triangles" "$views/input_wire.png" \
    -label "output's triangles" "$views/output_wire.png" \
    -tile 2x2 -geometry +4+4 -define png:compression-level=9 "$picture"
  printf 'render_assets: %s: fit %.1f s, export %.1f s, render %.1f s\n' "$name" \
    "$FIT_SECONDS" "$EXPORT_SECONDS" "$(echo "$s1 - $s0" | bc)"
  echo "render_assets: wrote $picture ($(stat -c %s "$picture") bytes)"
done
