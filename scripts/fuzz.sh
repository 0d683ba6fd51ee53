#!/usr/bin/env bash
# Runs each libFuzzer harness of tests/fuzz/ for SECONDS (default 60) seconds, one after the
# other, on its corpus tests/fuzz/corpus/<reader>/ (docs/reliability.md). Needs clang and
# libclang-rt-14-dev (scripts/setup.sh installs both). Builds build-fuzz/ with
# -DCODESIGN_FUZZ=ON (ASan + UBSan + libFuzzer) first.
#
#   bash scripts/fuzz.sh [SECONDS] [READER...]      READER: config msh policy checkpoint
#
# New inputs that add coverage go to build-fuzz/corpus/<reader>/ (not the committed corpus);
# a crash is written to build-fuzz/findings/<reader>/ and stops the script with a non-zero
# status. Logs: build-fuzz/logs/<reader>.log (the last line holds libFuzzer's cov:/ft:/exec
# figures). NICE=15 runs the fuzzers (not the build) at low priority on a shared machine.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
readers=("$@")
((${#readers[@]})) || readers=(config msh policy checkpoint)
nice_level="${NICE:-0}"

CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
  -DCODESIGN_FUZZ=ON -DCODESIGN_TESTS=OFF >/dev/null
targets=()
for r in "${readers[@]}"; do targets+=("fuzz_$r"); done
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]}"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
for r in "${readers[@]}"; do
  work="build-fuzz/corpus/$r"
  mkdir -p "$work" "build-fuzz/findings/$r" build-fuzz/logs
  echo "=== fuzz_$r for ${seconds}s"
  # -rss_limit_mb: a reader that allocates 2 GB on a small input is a finding too.
  if ! nice -n "$nice_level" "build-fuzz/fuzz_$r" "$work" "tests/fuzz/corpus/$r" \
      -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="build-fuzz/findings/$r/" >"build-fuzz/logs/$r.log" 2>&1; then
    tail -n 40 "build-fuzz/logs/$r.log"
    echo "fuzz: fuzz_$r found a problem: build-fuzz/findings/$r/" >&2
    exit 1
  fi
  grep -E '^#[0-9]+ +DONE|^stat::number_of_executed_units|^stat::peak_rss_mb' "build-fuzz/logs/$r.log" || true
done
