#!/usr/bin/env bash
# Prints the tree's house-keeping figures, each with its limit, and exits 1
# when one is over:
#   - the longest function in core/ (at most 150 lines);
#   - the definitions of pi, the stopwatch and the progress-callback type
#     (one each, in core/common/);
#   - the places each fit option is written outside its table and the docs
#     (scripts/option_places.sh);
#   - the lines of docs/FITTING.md (a reference: at most 420);
#   - the bench/ files missing from bench/README.md (none).
set -uo pipefail
cd "$(dirname "$0")/.."
failed=0
check() {  # check LABEL VALUE LIMIT: prints, and fails when VALUE > LIMIT
  local verdict=ok
  if [ "$2" -gt "$3" ]; then verdict=OVER; failed=1; fi
  printf '%-58s %6s  (limit %s) %s\n' "$1" "$2" "$3" "$verdict"
}
sources="core io converters tools tests bench fuzz samples"

longest=$(python3 scripts/function_lengths.py --top 1 core)
check "longest function in core/: ${longest#* }" "${longest%% *}" 150

definitions() {  # definitions REGEX: files defining it, one per line
  grep -rlE --include='*.h' --include='*.cpp' "$1" $sources
}
for what in \
  "pi|constexpr double kPi =|#define M_PI" \
  "stopwatch|class Stopwatch\b|struct Stopwatch\b" \
  "progress callback type|std::function<void\(const std::string&( stage)?, *double( fraction)?\)>"; do
  name=${what%%|*}
  regex=${what#*|}
  files=$(definitions "$regex" | tr '\n' ' ')
  check "definitions of the $name: ${files:-none}" "$(definitions "$regex" | wc -l)" 1
done

bash scripts/option_places.sh || failed=1

check "lines of docs/FITTING.md" "$(wc -l < docs/FITTING.md)" 420

missing=$(bash bench/readme_check.sh | grep -vc ' missing$')
check "bench/ files missing from bench/README.md" "$missing" 0

exit $failed
