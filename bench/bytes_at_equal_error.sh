#!/usr/bin/env bash
# Bytes at equal error (docs/FORMAT.md, "Bytes at equal error"): for
# bunny00 (--rmse 0.067), bear and fandisk_large (--rmse 0.1), the .sdcb at
# several quantizations and at --quantize auto, next to gltfpack -cc and
# Draco of the CGAL-decimated mesh at the same dense two-sided rms against
# the INPUT mesh (bench/equal_error_bench.cpp measures all three the same
# way, 200,000 samples each way; the .sdcb as `sdcb compare` measures it).
#   1. sdcb fit MESH --rmse R --knot-grid 16 (the fit --quantize makes,
#      stored exactly), then that model written at each BITS and at auto;
#   2. gltfpack -i MESH.obj -si 0 -se E -vp P -cc for P in $VP, E bisected
#      (log scale, 9 steps) for the smallest file whose
#      decoded mesh (scripts/gltf_tools/to_obj.mjs) is within the .sdcb
#      auto file's rms;
#   3. Draco (edgebreaker, level 10) of the Garland-Heckbert decimation, the
#      faces bisected per position quantization, the smallest file within
#      the same rms.
#   bash bench/bytes_at_equal_error.sh            (~15 min on 2 cores)
#   MODELS="bunny00" BITS="0 12 auto" bash bench/bytes_at_equal_error.sh
# Needs the build (scripts/setup.sh) and scripts/gltf_tools (gltfpack).
set -euo pipefail
cd "$(dirname "$0")/.."
SDCB=${SDCB:-./build/sdcb}
BENCH=${BENCH:-./build/bench/equal_error_bench}
cmake --build build --target equal_error_bench >/dev/null
GLTFPACK=scripts/gltf_tools/node_modules/.bin/gltfpack
OUT=${OUT:-out/bytes_at_equal_error}
MODELS=${MODELS:-"bunny00 bear fandisk_large"}
BITS=${BITS:-"0 16 14 13 12 11 10 auto"}
VP=${VP:-"9 10 11 12 14"}
mkdir -p "$OUT"
rmse() { [ "$1" = bunny00 ] && echo 0.067 || echo 0.1; }
field() { sed -n "s/.* $1 \([^ ]*\).*/\1/p"; }

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
  grep '^draco qp' "$OUT/$m.draco.txt" | awk '{printf "| Draco | %s | %s | %s | %s | %s |\n", $3, $5, $7, $9, $11}'
  best_d=$(grep '^draco best' "$OUT/$m.draco.txt")
  echo
  echo "SUMMARY $m: rms $target % | .sdcb auto $sdcb_bytes B | gltfpack $(echo "$best_g" | awk '{print $4 " B (vp " $1 ", se " $2 ", rms " $5 ", max " $6 ")"}') | Draco $(echo "$best_d" | awk '{print $8 " B (qp " $4 ", " $6 " faces, rms " $10 ", max " $12 ")"}')"
  echo
done
