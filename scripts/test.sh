#!/usr/bin/env bash
# Builds and runs every test: first the Release build, then a Release build without
# -march=native (exercises the paths taken on CPUs without AVX-512), then the same tests built
# with AddressSanitizer + UndefinedBehaviorSanitizer. Run scripts/setup.sh first (the README's
# test command does both). Exits non-zero if any build or test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"
export OMP_NUM_THREADS=1  # tests are single-threaded unless they say otherwise

echo "=== Release tests"
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/release -j "$jobs"
ctest --test-dir build/release --output-on-failure -j "$jobs" --timeout 1200

echo "=== Portable build tests (no -march=native: the non-AVX-512 fallbacks of the learner)"
cmake -S . -B build/portable -G Ninja -DCMAKE_BUILD_TYPE=Release -DCODESIGN_NATIVE=OFF
cmake --build build/portable -j "$jobs"
ctest --test-dir build/portable --output-on-failure -j "$jobs" --timeout 1200

echo "=== AddressSanitizer + UBSan tests"
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCODESIGN_SANITIZE=ON
cmake --build build/asan -j "$jobs"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build/asan --output-on-failure -j "$jobs" --timeout 3000
