#!/usr/bin/env bash
# Prints the FEM figures that docs/physics.md and README.md quote for the default design j21
# (tests/fem/whisker_figures_test.cpp, `[figures]` lines):
#   tip compliance (clamped base, 100 µN tip load along z, no gravity, no fibres),
#   f1, f2 (K0, lumped mass, clamped base, no fibres),
#   ε at 10 and 20 kPa and the tip displacement at 10 kPa (static, no gravity, no contact),
#   with and without the default fibres.
# The default mesh takes about a second; --refined adds two refinements of it
# (radius_factor/wall_factor 0.4/0.6 and 0.25/0.4: ~14k and ~45k tets, several minutes).
#
#   scripts/fem_figures.sh [--refined] [path/to/test_fem]
# Default binary: build/release/test_fem (or $TEST_FEM_BIN).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
refined=0
if [[ "${1:-}" == "--refined" ]]; then refined=1; shift; fi
bin="${1:-${TEST_FEM_BIN:-$here/build/release/test_fem}}"
if [[ ! -x "$bin" ]]; then
  echo "fem_figures: no test_fem binary at $bin (build it, or pass its path)" >&2
  exit 2
fi

filter='WhiskerFigures.*'
extra=()
if [[ $refined -eq 1 ]]; then
  extra=(--gtest_also_run_disabled_tests)
fi
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
if ! "$bin" --gtest_filter="$filter" "${extra[@]}" > "$log" 2>&1; then
  cat "$log" >&2
  echo "fem_figures: $bin failed" >&2
  exit 1
fi
grep '^\[figures\]' "$log"
[[ $refined -eq 1 ]] || exit 0

# Default mesh against the finest one (r0.25/w0.4): the discretisation error of the default mesh
# as far as this refinement shows it.
awk '
  /^\[figures\] tip compliance/ { split($5, m, "="); c[m[2]] = $7 }
  /^\[figures\] modal/          { split($4, m, "="); f[m[2]] = $8 }
  /^\[figures\] pressure/ {
    split($4, m, "="); split($6, b, "="); k = m[2] "|" b[2]
    e10[k] = $10 + 0; e20[k] = $14 + 0
    yy = $(NF - 2); sub(/,$/, "", yy); y[k] = yy
  }
  END {
    d = "default"; r = "r0.25/w0.4"
    printf "[ratios] default / finest mesh: tip compliance %.3f (%+.1f %%), f1 %.3f (%+.1f %%)\n",
           c[d] / c[r], 100 * (c[d] / c[r] - 1), f[d] / f[r], 100 * (f[d] / f[r] - 1)
    for (fib = 0; fib < 2; ++fib) {
      s = fib ? "no" : "yes"
      printf "[ratios] default / finest mesh, fibres=%s: eps(10 kPa) %+.1f %%, eps(20 kPa) %+.1f %%;" \
             " tip y at 10 kPa %s mm vs %s mm\n", s,
             100 * (e10[d "|" s ":"] / e10[r "|" s ":"] - 1), 100 * (e20[d "|" s ":"] / e20[r "|" s ":"] - 1),
             y[d "|" s ":"], y[r "|" s ":"]
    }
  }' "$log"
