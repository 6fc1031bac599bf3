#!/usr/bin/env bash
# The malformed corpus: every file of tests/data/malformed, plus large files
# generated here, must make sdcb exit 1 within 20 s under `ulimit -v
# 4000000` (4 GB of address space), with exactly one line on stderr naming
# the file, and leave no file behind.
#   meshes: sdcb check FILE (but for $check_ok); sdcb fit FILE -o OUT/m.sdcb
#           --json OUT/f.json
#   models: sdcb info FILE --json OUT/i.json; eval FILE -i P -o OUT/v.txt;
#           dump FILE -o OUT/d.json; cage FILE -o OUT/c.obj --json OUT/c.json
# Usage: malformed_corpus_test.sh SDCB_BINARY CORPUS_DIR WORK_DIR
# SDCB_CORPUS_NO_ULIMIT=1 drops the ulimit (for the AddressSanitizer build,
# whose shadow memory needs terabytes of address space).
set -u
sdcb=$1 corpus=$2 work=$3
rm -rf "$work"
mkdir -p "$work/generated" "$work/out"
gen=$work/generated

# --- Large files (too big for the repository) --------------------------------
# 2 million vertices, 4 million faces declared, the faces cut off halfway.
{
  printf 'OFF\n2000000 4000000 0\n'
  yes '0.5 0.25 1e-3' | head -n 2000000
  yes '3 0 1 2' | head -n 2000000
} > "$gen/big_truncated_faces.off"
# One million vertices; the last face refers to vertex 1000001.
{
  yes 'v 1 2 3' | head -n 1000000
  yes 'f 1 2 3' | head -n 100000
  printf 'f 1 2 1000001\n'
} > "$gen/big_bad_last_index.obj"
# 10 million vertices and 20 million faces declared; 1 MB of body.
{
  printf 'ply\nformat binary_little_endian 1.0\nelement vertex 10000000\n'
  printf 'property float x\nproperty float y\nproperty float z\n'
  printf 'element face 20000000\nproperty list uchar int vertex_indices\n'
  printf 'end_header\n'
  head -c 1000000 /dev/zero
} > "$gen/big_declared_counts.ply"
# A face with a million corners.
{
  printf 'OFF\n1000000 1 0\n'
  yes '0 0 0' | head -n 1000000
  printf '1000000 '
  seq 0 999999 | tr '\n' ' '
  printf '\n'
} > "$gen/big_polygon.off"
# A binary STL of a million triangles, the last with a NaN.
{
  head -c 80 /dev/zero
  printf '\x40\x42\x0f\x00'
  head -c $((50 * 999999 + 12)) /dev/zero
  printf '\x00\x00\xc0\x7f'
  head -c 34 /dev/zero
} > "$gen/big_nan_in_last_triangle.stl"
# An open fan of 300,000 triangles around one vertex (more than a fittable
# part's vertex may have: refused by check and fit alike).
{
  n=300000
  printf 'OFF\n%d %d 0\n0 0 1\n' $((n + 1)) $((n - 1))
  awk -v n=$n 'BEGIN { for (i = 0; i < n; ++i) printf "%.9f %.9f 0\n", cos(6.283185307 * i / n), sin(6.283185307 * i / n);
                       for (i = 1; i < n; ++i) printf "3 0 %d %d\n", i, i + 1 }'
} > "$gen/big_open_fan.off"

printf '0 0 1\n1 0 0\n' > "$work/points.txt"

fittable="off_open_surface.off off_two_components.off obj_open_surface.obj"
fittable+=" off_unreferenced_vertex.off"
files=0 runs=0 failures=0
run() {  # run NAME ARGS...: one sdcb invocation, checked
  local name=$1
  shift
  runs=$((runs + 1))
  local start=$SECONDS
  (
    [ "${SDCB_CORPUS_NO_ULIMIT:-0}" = 1 ] || ulimit -v 4000000
    timeout 20 "$sdcb" "$@"
  ) > "$work/stdout" 2> "$work/stderr" < /dev/null
  local rc=$?
  local lines
  lines=$(wc -l < "$work/stderr")
  local problem=""
  if [ $rc -eq 124 ]; then
    problem="took more than 20 s"
  elif [ $rc -ne 1 ]; then
    problem="exit code $rc, not 1"
  elif [ "$lines" -ne 1 ]; then
    problem="$lines lines on stderr, not one"
  elif ! grep -qF "$name" "$work/stderr"; then
    problem="stderr does not name the file"
  elif [ -n "$(ls -A "$work/out")" ]; then
    problem="left $(ls -A "$work/out" | tr '\n' ' ')"
  fi
  if [ -n "$problem" ]; then
    failures=$((failures + 1))
    echo "FAIL: sdcb $*: $problem ($((SECONDS - start)) s)"
    head -c 600 "$work/stderr"
  fi
  rm -rf "$work/out" && mkdir -p "$work/out"
}

for f in "$corpus"/* "$gen"/*; do
  name=$(basename "$f")
  case $name in
    *.off | *.obj | *.ply | *.stl)
      files=$((files + 1))
      # Meshes whose every part sdcb can fit (open, two parts, a vertex no
      # triangle uses) are not malformed: `check` says ok and `fit` fits
      # them (tests/tools/check_cli_test.cpp, open_parts_cli_test.cpp).
      case " $fittable " in
        *" $name "*) ;;
        *)
          run "$name" check "$f"
          run "$name" fit "$f" -o "$work/out/m.sdcb" --json "$work/out/f.json" --quiet
          ;;
      esac
      ;;
    *.sdcb)
      files=$((files + 1))
      run "$name" info "$f" --json "$work/out/i.json"
      run "$name" eval "$f" -i "$work/points.txt" -o "$work/out/v.txt"
      run "$name" dump "$f" -o "$work/out/d.json"
      run "$name" cage "$f" -o "$work/out/c.obj" --json "$work/out/c.json" --quiet
      ;;
  esac
done
echo "malformed corpus: $files files, $runs runs, $failures failures"
[ "$failures" -eq 0 ] && [ "$files" -ge 60 ]
