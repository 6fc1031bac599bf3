#!/usr/bin/env bash
# Builds the whole test suite with AddressSanitizer and UndefinedBehavior-
# Sanitizer (gcc, -O1, no benchmarks) into build-asan/ and runs it. Any
# sanitizer report fails the test that caused it (-fno-sanitize-recover).
#   bash scripts/sanitize.sh [CTEST ARGS...]   e.g. -R MeshReader
# Differences from the regular run: the install test is skipped (the
# installed static libraries would need the sanitizer flags in the sample
# build), and the malformed corpus runs without `ulimit -v` (ASan reserves
# terabytes of address space for its shadow memory). Timings on the 2-core
# development machine are in docs/INTAKE.md.
set -euo pipefail
cd "$(dirname "$0")/.."

flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
if [ ! -f build-asan/build.ninja ]; then
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DSDCB_BUILD_BENCH=OFF > build-asan.configure.log 2>&1 || {
    cat build-asan.configure.log >&2; exit 1; }
  rm -f build-asan.configure.log
fi
start=$SECONDS
cmake --build build-asan -j "$(nproc)"
echo "sanitize: build took $((SECONDS - start)) s"
start=$SECONDS
# TBB keeps thread-local buffers until exit: not leaks of ours.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export SDCB_CORPUS_NO_ULIMIT=1
ctest --test-dir build-asan -j "$(nproc)" --output-on-failure --timeout 3600 \
  -E '^install\.' "$@"
echo "sanitize: tests took $((SECONDS - start)) s"
