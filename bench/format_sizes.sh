#!/usr/bin/env bash
# The `.sdcb` size table of docs/FORMAT.md: fits sample meshes with the
# paper's settings as a user would (sdcb fit: lossless default, --quantize 16,
# --store-parameters), and prints, next to the input file, Draco's size of
# the same input mesh at 14-bit positions (bench/draco_size_bench) and the
# time to read the lossless file (bench/sdcb_file_bench). Re-run it when the
# fit changes. Build first (scripts/setup.sh). Not run by the tests.
# Usage: bench/format_sizes.sh [OUT_DIR]   (default: a temporary directory)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build --target draco_size_bench sdcb_file_bench >/dev/null
sdcb=./build/sdcb
draco=./build/bench/draco_size_bench
file_bench=./build/bench/sdcb_file_bench
out=${1:-$(mktemp -d)}
mkdir -p "$out"

# Integer value of "key": N in JSON text on stdin.
json_int() { grep -o "\"$1\": [0-9]*" | head -n 1 | grep -o '[0-9]*$'; }
json_num() { grep -o "\"$1\": [-0-9.e+]*" | head -n 1 | sed 's/.*: //'; }

echo "| mesh (degree, rmse %) | input file | vertices | control points |" \
  ".sdcb lossless | --quantize 16 (surface bound) | --store-parameters |" \
  "Draco qp 14 (cl 7 / cl 10) | read lossless (median) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
while read -r name degree rmse; do
  mesh=data/meshes/$name.off
  base=$out/$name
  common=(--degree "$degree" --rmse "$rmse" --quiet)
  $sdcb fit "$mesh" -o "$base.sdcb" "${common[@]}"
  $sdcb fit "$mesh" -o "$base.q16.sdcb" --quantize 16 "${common[@]}"
  $sdcb fit "$mesh" -o "$base.parm.sdcb" --store-parameters "${common[@]}"
  info=$($sdcb info "$base.sdcb" --json -)
  qinfo=$($sdcb info "$base.q16.sdcb" --json -)
  pinfo=$($sdcb info "$base.parm.sdcb" --json -)
  draco_line=$($draco "$mesh" 14)
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
done <<'EOF'
bunny00 4 0.067
fandisk_large 3 0.028
cow 4 0.1
blobby 4 0.1
EOF
echo
echo "(files in $out)"
