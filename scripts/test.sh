#!/usr/bin/env bash
# Builds and runs the tests: first every test on the Release build, then the learner's and the
# engine's tests on a Release build without -march=native (the paths taken on CPUs without
# AVX-512), then the tests built with AddressSanitizer + UndefinedBehaviorSanitizer. Run
# scripts/setup.sh first (the README's test command does both). Exits non-zero if any build or
# test fails.
#
# Under the sanitizers every test runs except the long end-to-end ones listed in ASAN_LONG: a
# sanitized build runs them 6 to 8 times slower (the co-design physics), and with them the CI job
# did not finish in its 90 minutes. Each of them runs on the Release build above, and the code they
# drive stays covered under the sanitizers by shorter tests that run it: a whole run with its
# evaluation and fixed-angle reference (Run.WritesTheRunFolder), resume with the recurrent policy
# and its policy file (Run.ResumedRecurrentRun...), `evaluate` (RunEvaluation.FinalState...), stop
# signals, locks and write errors, the readers' fuzz corpora, and the unit tests of each part
# (docs/reliability.md). CODESIGN_ASAN_ALL=1 runs those long tests under the sanitizers too
# (about an hour more on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"
export OMP_NUM_THREADS=1  # tests are single-threaded unless they say otherwise

ASAN_LONG='^(RunCommand\.KilledAtRandomMoments|RunSignals\.StopAtSeveralMoments|FiguresCommand\.RunDrawsFigures'
ASAN_LONG+='|FiguresCommand\.MissingGnuplot|BadInput\.EveryCase|RunCommand\.MainJobWritesTheRunFolder'
ASAN_LONG+='|FaultInjectionRun\.|BaselinesCli\.RefineAppends|BaselinesCli\.EvaluateRanks|RenderCommand\.RunEndsWithFrames|Run\.ResumedRunWithHistory'
ASAN_LONG+='|Run\.EntropySchedule|Run\.TelemetryLog|Run\.ResumedRunEndsIdentically|Run\.KeepsTheCheckpoints'
ASAN_LONG+='|RunEvaluation\.RanksTheRange|RunEvaluation\.BadInput|EstimatorPid\.FitExplains|WhiskerMesh\.All110Designs'
# The signal and dead-rank test under mpirun (several runs, each resumed). The other MPI tests run
# sanitized, their ranks without LeakSanitizer (tests/apps/mpi_run_test.cpp says why).
ASAN_LONG+='|MpiRun\.StoppedOrBroken)'

echo "=== Release tests"
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/release -j "$jobs"
ctest --test-dir build/release --output-on-failure -j "$jobs" --timeout 1200

echo "=== Portable build: the learner's and the engine's tests without -march=native"
cmake -S . -B build/portable -G Ninja -DCMAKE_BUILD_TYPE=Release -DCODESIGN_NATIVE=OFF
cmake --build build/portable -j "$jobs" --target test_rl test_fem
ctest --test-dir build/portable --output-on-failure -j "$jobs" --timeout 1200 -L '^(rl|fem)$'

echo "=== AddressSanitizer + UBSan tests"
# -O1 -g1 (line tables, enough for the sanitizers' stack traces) instead of RelWithDebInfo's
# -O2 -g: the sanitized build of the Eigen-heavy files took 2.3 times longer with -O2 -g.
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCODESIGN_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
cmake --build build/asan -j "$jobs"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
skip=(-E "$ASAN_LONG")
[ "${CODESIGN_ASAN_ALL:-0}" = 1 ] && skip=()
ctest --test-dir build/asan --output-on-failure -j "$jobs" --timeout 3000 "${skip[@]}"
