#!/usr/bin/env bash
# The doc tables that set the spline against the mesh a user would ship
# instead, all measured by build/bench/decimation_bench (bench/
# decimation_bench.cpp says how each mode measures). One TABLE per call:
#
#   bash bench/decimation_tables.sh count [RMSE [OUT_DIR]] [MESH ...]
#     docs/FITTING.md, "Against the decimated mesh a user would keep": each
#     mesh (default bunny00 bear retinal fandisk_large homer) fitted with the
#     defaults at --rmse RMSE (0.1), then decimated with CGAL's
#     Garland-Heckbert policy to as many vertices as the spline has control
#     points, both measured against the input the same way (decimation_bench
#     count, 200,000 samples). One line per mesh; ~3 min on 2 cores.
#   bash bench/decimation_tables.sh equal-error
#     docs/FORMAT.md, "Bytes at equal error": for bunny00 (--rmse 0.067),
#     bear and fandisk_large (--rmse 0.1), the .sdcb at several
#     quantizations and at --quantize auto, next to gltfpack -cc and Draco of
#     the decimated mesh at the same dense two-sided rms against the INPUT
#     mesh (decimation_bench sdcb / mesh / draco, 200,000 samples each way):
#       1. sdcb fit MESH --rmse R --knot-grid 16 (the fit --quantize makes,
#          stored exactly), then that model written at each BITS and auto;
#       2. gltfpack -i MESH.obj -si 0 -se E -vp P -cc for P in $VP, E
#          bisected (log scale, 9 steps) for the smallest file whose decoded
#          mesh (scripts/gltf_tools/to_obj.mjs) is within the auto file's rms;
#       3. Draco (edgebreaker, level 10) of the Garland-Heckbert decimation,
#          the faces bisected per position quantization, the smallest file
#          within the same rms.
#     Markdown tables per model and a SUMMARY line; ~10-15 min on 2 cores.
#     Environment: MODELS (default "bunny00 bear fandisk_large"), BITS
#     (default "0 16 14 13 12 11 10 auto"), VP (default "9 10 11 12 14"),
#     OUT (default out/bytes_at_equal_error); e.g.
#       MODELS="bunny00" BITS="0 12 auto" bash bench/decimation_tables.sh equal-error
#     Needs scripts/gltf_tools (gltfpack).
#   bash bench/decimation_tables.sh sizes [OUT_DIR]
#     docs/FORMAT.md, "Sizes": sample meshes fitted as a user would (sdcb
#     fit: lossless default, --quantize 16, --store-parameters), next to the
#     input file, Draco's size of the same input mesh at 14-bit positions
#     (decimation_bench draco-input) and the time to read the lossless file
#     (bench/sdcb_file_bench). OUT_DIR default: a temporary directory.
#     ~2 min on 2 cores.
#
# Needs the build (scripts/setup.sh: ./build/sdcb); builds the benches it
# runs. SDCB=path/to/sdcb runs another binary. Not run by the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
SDCB=${SDCB:-./build/sdcb}
BENCH=${BENCH:-./build/bench/decimation_bench}

# The value after " KEY " in a line on stdin.
field() { sed -n "s/.* $1 \([^ ]*\).*/\1/p"; }

table_count() {
  local rmse=${1:-0.1} out=${2:-/tmp/sdcb_decimation}
  shift $(( $# > 2 ? 2 : $# )) || true
  local meshes=("$@")
  [ ${#meshes[@]} -gt 0 ] || meshes=(bunny00 bear retinal fandisk_large homer)
  mkdir -p "$out"
  local m
  for m in "${meshes[@]}"; do
    "$SDCB" fit "data/meshes/$m.off" -o "$out/$m.sdcb" --rmse "$rmse" --quiet \
      --json "$out/$m.json" 2> /dev/null || true
    "$BENCH" count "data/meshes/$m.off" "$out/$m.sdcb" 200000
  done
}

table_equal_error() {
  local GLTFPACK=scripts/gltf_tools/node_modules/.bin/gltfpack
  local OUT=${OUT:-out/bytes_at_equal_error}
  local MODELS=${MODELS:-"bunny00 bear fandisk_large"}
  local BITS=${BITS:-"0 16 14 13 12 11 10 auto"}
  local VP=${VP:-"9 10 11 12 14"}
  mkdir -p "$OUT"
  rmse() { [ "$1" = bunny00 ] && echo 0.067 || echo 0.1; }
  local m mesh model target sdcb_bytes obj best_g vp lo hi ok mid se g line rms best_d
  for m in $MODELS; do
    mesh=data/meshes/$m.off
    model=$OUT/$m.grid.sdcb
    [ -f "$model" ] || "$SDCB" fit "$mesh" -o "$model" --rmse "$(rmse "$m")" \
      --knot-grid 16 --quiet
    echo "## $m (--rmse $(rmse "$m"))"
    echo
    echo "| .sdcb | bits | bytes | bound % | rms % | max % | chunks (payload bytes) |"
    echo "|---|---|---|---|---|---|---|"
    # shellcheck disable=SC2086
    "$BENCH" sdcb "$mesh" "$model" $BITS > "$OUT/$m.sdcb.txt"
    while read -r line; do
      printf "| %s | %s | %s | %s | %s | %s | %s |\n" "$(echo "$line" | awk '{print $2}')" \
        "$(echo "$line" | field bits)" "$(echo "$line" | field bytes)" \
        "$(echo "$line" | field bound_percent)" "$(echo "$line" | field rms_percent)" \
        "$(echo "$line" | field max_percent)" "$(echo "$line" | sed 's/.*chunks //')"
    done < "$OUT/$m.sdcb.txt"
    target=$(grep '^sdcb auto' "$OUT/$m.sdcb.txt" | field rms_percent)
    sdcb_bytes=$(grep '^sdcb auto' "$OUT/$m.sdcb.txt" | field bytes)
    echo
    echo "target rms: $target % (the auto .sdcb, $sdcb_bytes bytes)"
    echo

    # gltfpack: for each -vp, the largest -se whose decoded mesh is within
    # the target (bisection on log(se)).
    obj="$OUT/$m.input.obj"
    [ -f "$obj" ] || awk 'NF == 0 || $1 ~ /^#/ {next} !h {h = 1; next}
      !c {c = 1; nv = $1; nf = $2; next}
      nv > 0 {print "v", $1, $2, $3; nv--; next}
      nf > 0 {print "f", $2 + 1, $3 + 1, $4 + 1; nf--}' "$mesh" > "$obj"
    echo "| gltfpack -cc | -vp | -se | triangles | bytes | rms % | max % |"
    echo "|---|---|---|---|---|---|---|"
    best_g=""
    for vp in $VP; do
      lo=-4.5 hi=-1.5 ok=""
      for _ in 1 2 3 4 5 6 7 8 9; do
        mid=$(awk -v a="$lo" -v b="$hi" 'BEGIN {print (a + b) / 2}')
        se=$(awk -v e="$mid" 'BEGIN {printf "%.6f", exp(e * log(10))}')
        g="$OUT/$m.g$vp.glb"
        "$GLTFPACK" -i "$obj" -o "$g" -si 0 -se "$se" -vp "$vp" -cc > /dev/null
        node scripts/gltf_tools/to_obj.mjs "$g" "$g.obj"
        line=$("$BENCH" mesh "$mesh" "$g.obj")
        rms=$(echo "$line" | field rms_percent)
        if awk -v r="$rms" -v t="$target" 'BEGIN {exit !(r <= t)}'; then
          lo=$mid
          ok="$vp $se $(echo "$line" | field triangles) $(stat -c %s "$g") $rms $(echo "$line" | field max_percent)"
        else
          hi=$mid
        fi
      done
      if [ -n "$ok" ]; then
        echo "$ok" | awk '{printf "| gltfpack | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6}'
        if [ -z "$best_g" ] || [ "$(echo "$ok" | awk '{print $4}')" -lt "$(echo "$best_g" | awk '{print $4}')" ]; then
          best_g=$ok
        fi
      else
        echo "| gltfpack | $vp | - | - | - | misses the target | - |"
      fi
    done
    echo
    "$BENCH" draco "$mesh" "$target" > "$OUT/$m.draco.txt"
    echo "| Draco (decimated) | qp | faces | bytes | rms % | max % |"
    echo "|---|---|---|---|---|---|"
    grep '^draco qp' "$OUT/$m.draco.txt" | awk '
      $4 == "faces" {printf "| Draco | %s | %s | %s | %s | %s |\n", $3, $5, $7, $9, $11; next}
      {q = $3; sub(":", "", q); r = $NF; sub(")", "", r)
       printf "| Draco | %s | - | - | misses the target (whole mesh: rms %s) | - |\n", q, r}'
    best_d=$(grep '^draco best' "$OUT/$m.draco.txt")
    echo
    echo "SUMMARY $m: rms $target % | .sdcb auto $sdcb_bytes B | gltfpack $(echo "$best_g" | awk '{print $4 " B (vp " $1 ", se " $2 ", rms " $5 ", max " $6 ")"}') | Draco $(echo "$best_d" | awk '{print $8 " B (qp " $4 ", " $6 " faces, rms " $10 ", max " $12 ")"}')"
    echo
  done
}

table_sizes() {
  cmake --build build --target sdcb_file_bench >/dev/null
  local file_bench=./build/bench/sdcb_file_bench
  local out=${1:-$(mktemp -d)}
  mkdir -p "$out"
  # Integer / number value of "key": N in JSON text on stdin.
  json_int() { grep -o "\"$1\": [0-9]*" | head -n 1 | grep -o '[0-9]*$'; }
  json_num() { grep -o "\"$1\": [-0-9.e+]*" | head -n 1 | sed 's/.*: //'; }
  echo "| mesh (degree, rmse %) | input file | vertices | control points |" \
    ".sdcb lossless | --quantize 16 (surface bound) | --store-parameters |" \
    "Draco qp 14 (cl 7 / cl 10) | read lossless (median) |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  local name degree rmse mesh base common info qinfo pinfo draco_line cl7 cl10 read_ms
  while read -r name degree rmse; do
    mesh=data/meshes/$name.off
    base=$out/$name
    common=(--degree "$degree" --rmse "$rmse" --quiet)
    "$SDCB" fit "$mesh" -o "$base.sdcb" "${common[@]}"
    "$SDCB" fit "$mesh" -o "$base.q16.sdcb" --quantize 16 "${common[@]}"
    "$SDCB" fit "$mesh" -o "$base.parm.sdcb" --store-parameters "${common[@]}"
    info=$("$SDCB" info "$base.sdcb" --json -)
    qinfo=$("$SDCB" info "$base.q16.sdcb" --json -)
    pinfo=$("$SDCB" info "$base.parm.sdcb" --json -)
    draco_line=$("$BENCH" draco-input "$mesh" 14)
    cl7=$(echo "$draco_line" | sed 's/.*cl7 \([0-9]*\) bytes.*/\1/')
    cl10=$(echo "$draco_line" | sed 's/.*cl10 \([0-9]*\) bytes.*/\1/')
    read_ms=$($file_bench "$base.sdcb" | sed -n 's/.*read (ReadSdcbFile, 11 runs): median \([0-9.]*\) ms.*/\1/p')
    printf '| %s (%s, %s) | %s | %s | %s | %s | %s (%.2g %%) | %s | %s / %s | %s ms |\n' \
      "$name" "$degree" "$rmse" "$(stat -c %s "$mesh")" \
      "$(echo "$info" | json_int vertices)" \
      "$(echo "$info" | json_int control_points)" \
      "$(echo "$info" | json_int file_bytes)" \
      "$(echo "$qinfo" | json_int file_bytes)" \
      "$(echo "$qinfo" | json_num quantization_error_bound_percent)" \
      "$(echo "$pinfo" | json_int file_bytes)" "$cl7" "$cl10" "$read_ms"
  done <<'ROWS'
bunny00 4 0.067
fandisk_large 3 0.028
cow 4 0.1
blobby 4 0.1
ROWS
  echo
  echo "(files in $out)"
}

table=${1:-}
[ $# -gt 0 ] && shift
case "$table" in
  count | equal-error | sizes) ;;
  *)
    echo "usage: bash bench/decimation_tables.sh count|equal-error|sizes [ARGS]" >&2
    exit 2
    ;;
esac
[ "$BENCH" != ./build/bench/decimation_bench ] ||
  cmake --build build --target decimation_bench >/dev/null
case "$table" in
  count) table_count "$@" ;;
  equal-error) table_equal_error ;;
  sizes) table_sizes "$@" ;;
esac
