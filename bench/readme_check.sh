#!/usr/bin/env bash
# Every file of bench/ but README.md and CMakeLists.txt must be listed in
# bench/README.md, its name in backticks (`fit_bench.cpp`). Prints each
# missing file, one per line, then "N missing"; exits 1 when N > 0.
#   bash bench/readme_check.sh
set -euo pipefail
dir=$(cd "$(dirname "$0")" && pwd)
readme=$dir/README.md
missing=0
while IFS= read -r name; do
  case "$name" in README.md | CMakeLists.txt) continue ;; esac
  if [ ! -f "$readme" ] || ! grep -qF -- "\`$name\`" "$readme"; then
    echo "$name"
    missing=$((missing + 1))
  fi
done < <(find "$dir" -maxdepth 1 -type f -printf '%f\n' | LC_ALL=C sort)
echo "$missing missing"
[ "$missing" -eq 0 ]
