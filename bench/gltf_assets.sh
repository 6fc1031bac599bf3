# shellcheck shell=bash
# Sourced by gltf_assets_table.sh and render_assets.sh (run from the
# repository's root): the textured glTF assets of Debian's assimp-testmodels
# and their way through sdcb.
#   gltf_asset_input NAME DIR   writes DIR/NAME.glb (and the image it names)
#     for NAME in BoxTextured (glTF 2), Duck (duck.dae through
#     `assimp export -f glb2`, its duckCM.tga beside it), CesiumMilkTruck
#     (glTF 1 through `assimp export -f glb2`)
#   gltf_asset_fit_export NAME RMSE TOL DIR   `sdcb fit DIR/NAME.glb -o
#     DIR/NAME.sdcb --rmse RMSE`, then `sdcb export DIR/NAME.sdcb -o
#     DIR/NAME.out.glb --tolerance TOL`; sets FIT_SECONDS and EXPORT_SECONDS;
#     returns 1 when the fit refuses the asset (its message on stderr); a
#     failed export ends the script

GLTF_ASSET_MODELS=/usr/share/assimp/models

gltf_asset_input() {
  local name=$1 dir=$2 m=$GLTF_ASSET_MODELS
  mkdir -p "$dir"
  case "$name" in
    BoxTextured) cp "$m/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb" "$dir/" ;;
    Duck)
      assimp export "$m/Collada/duck.dae" "$dir/Duck.glb" -f glb2 >/dev/null
      cp "$m/Collada/duckCM.tga" "$dir/" ;;
    CesiumMilkTruck)
      assimp export "$m/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf" \
        "$dir/CesiumMilkTruck.glb" -f glb2 >/dev/null
      cp "$m/glTF/CesiumMilkTruck/CesiumMilkTruck.png" "$dir/" ;;
    *) echo "gltf_asset_input: no asset $name" >&2; return 1 ;;
  esac
}

# shellcheck disable=SC2034  # FIT_SECONDS, EXPORT_SECONDS: read by the caller
gltf_asset_fit_export() {
  local name=$1 rmse=$2 tol=$3 dir=$4 s0 s1 s2
  s0=$(date +%s.%N)
  ./build/sdcb fit "$dir/$name.glb" -o "$dir/$name.sdcb" --rmse "$rmse" --quiet \
    2> >(grep -v 'pairs of triangles intersect' >&2) || return 1
  s1=$(date +%s.%N)
  ./build/sdcb export "$dir/$name.sdcb" -o "$dir/$name.out.glb" --tolerance "$tol" --quiet ||
    exit 1  # `if ! gltf_asset_fit_export` turns set -e off in here
  s2=$(date +%s.%N)
  FIT_SECONDS=$(echo "$s1 - $s0" | bc)
  EXPORT_SECONDS=$(echo "$s2 - $s1" | bc)
}
