#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/, clang with ASan + UBSan; only the
# files they link) into build-fuzz/ and runs each for SECONDS (default 30) on
# a scratch copy of its seed corpus (fuzz/corpus/TARGET plus the malformed
# files of tests/data/malformed). A libFuzzer run uses one core, so as many
# targets run at once as there are cores (SDCB_FUZZ_JOBS overrides).
#   bash scripts/fuzz.sh [SECONDS] [TARGET ...]     TARGET: off obj ply stl gltf sdcb manifest
# Exit 1 on a finding: the input is saved under build-fuzz/findings/TARGET/;
# minimize it (TARGET_fuzzer -minimize_crash=1 FILE), fix the bug and add the
# input to fuzz/corpus/TARGET/ as regression-NAME (the io tests replay every
# corpus file). Prints executions per second and coverage for each target.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-30}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(off obj ply stl gltf sdcb manifest); fi

if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ is missing (scripts/setup.sh installs clang)" >&2
  exit 1
fi
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S fuzz -B build-fuzz -G Ninja > build-fuzz.configure.log 2>&1 || {
    cat build-fuzz.configure.log >&2; exit 1; }
  rm -f build-fuzz.configure.log
fi
fuzzers=()
for t in "${targets[@]}"; do fuzzers+=("${t}_fuzzer"); done
began=$SECONDS
cmake --build build-fuzz -j "$(nproc)" --target "${fuzzers[@]}"
echo "fuzz: the build took $((SECONDS - began)) s"

# fuzz_one TARGET: one smoke run; its summary goes to build-fuzz/TARGET.summary
# and its exit status says whether it found a problem.
fuzz_one() {
  local t=$1 pattern
  local work=build-fuzz/corpus/$t findings=build-fuzz/findings/$t
  local log=build-fuzz/$t.log summary=build-fuzz/$t.summary
  mkdir -p "$work" "$findings"
  cp -n fuzz/corpus/"$t"/* "$work"/
  case $t in
    sdcb) pattern='*.sdcb' ;;
    gltf) pattern='*.gl[tb]*' ;;
    *) pattern="*.$t" ;;
  esac
  find tests/data/malformed -name "$pattern" -exec cp -n {} "$work"/ \;
  local found=0
  if ! build-fuzz/"${t}_fuzzer" "$work" -max_total_time="$seconds" \
      -artifact_prefix="$findings/" -rss_limit_mb=2048 -timeout=10 \
      -print_final_stats=1 \
      > "$log" 2>&1; then
    found=1
  fi
  # The last status line: "#N DONE cov: C ft: F corp: ... exec/s: E ...".
  local runs rate cov
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$' || true)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$' || true)
  cov=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -n 1 || true)
  echo "fuzz: $t: ${runs:-?} runs, ${rate:-?} exec/s, ${cov:-no coverage line}" > "$summary"
  return $found
}

jobs=${SDCB_FUZZ_JOBS:-$(nproc)}
echo "fuzz: ${targets[*]} for $seconds s each, $jobs at a time"
declare -A pid_of
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  fuzz_one "$t" &
  pid_of[$t]=$!
done
status=0
for t in "${targets[@]}"; do
  if ! wait "${pid_of[$t]}"; then
    echo "fuzz: $t FOUND A PROBLEM (see build-fuzz/$t.log and build-fuzz/findings/$t/)" >&2
    tail -n 40 "build-fuzz/$t.log" >&2
    status=1
  fi
  cat "build-fuzz/$t.summary"
done
exit $status
