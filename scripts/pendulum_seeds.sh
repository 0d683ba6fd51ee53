#!/usr/bin/env bash
# Acceptance benchmark of the PPO learner: trains Pendulum-v1 with
# configs/pendulum.toml for seeds 0..4, one after the other (each run is single-threaded),
# and prints, as a Markdown table ready to paste, the deterministic evaluation return of each seed
# (mean ± population std over eval_episodes episodes, 100 in configs/pendulum.toml, seeds disjoint
# from every training seed and from the other seeds' evaluations: 2^63 + seed * 2^20 + k) and its
# wall time. Exits 0 only if at least 4 of the 5 seeds reach a mean return >= -250.
#
#   scripts/pendulum_seeds.sh [path/to/codesign] [output dir]
# Defaults: build/release/codesign (or $CODESIGN_BIN), runs/pendulum_seeds/<UTC timestamp> (a fresh
# directory, so earlier results are never overwritten). $PENDULUM_CONFIG replaces
# configs/pendulum.toml (e.g. a copy with ppo.matmul_precision = "float32").
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${1:-${CODESIGN_BIN:-$here/build/release/codesign}}"
out="${2:-$here/runs/pendulum_seeds/$(date -u +%Y%m%dT%H%M%SZ)}"
config="${PENDULUM_CONFIG:-$here/configs/pendulum.toml}"
threshold=-250
needed=4

if [[ ! -x "$bin" ]]; then
  echo "pendulum_seeds: no codesign binary at $bin (build it, or pass its path)" >&2
  exit 2
fi
mkdir -p "$out"

value() {  # value <summary.txt> <key>
  sed -n "s/^$2 = //p" "$1"
}

precision="$(sed -n 's/^ *matmul_precision *= *"\([a-z0-9]*\)".*/\1/p' "$config")"
echo "config: $config (matmul_precision = ${precision:-auto}); binary: $bin"
echo
echo "| seed | eval mean return ± std | episodes | wall time | ≥ $threshold |"
echo "|---:|---:|---:|---:|:---:|"
passed=0
total_wall=0
for seed in 0 1 2 3 4; do
  dir="$out/seed$seed"
  "$bin" train-gym --config "$config" --seed "$seed" --out "$dir" > "$out/seed$seed.log" 2>&1 || {
    echo "pendulum_seeds: seed $seed failed, see $out/seed$seed.log" >&2
    exit 1
  }
  mean="$(value "$dir/summary.txt" eval_mean_return)"
  std="$(value "$dir/summary.txt" eval_std_return)"
  episodes="$(value "$dir/summary.txt" eval_episodes)"
  wall="$(value "$dir/summary.txt" wall_s)"
  if awk -v m="$mean" -v t="$threshold" 'BEGIN { exit !(m >= t) }'; then
    result=pass
    passed=$((passed + 1))
  else
    result=FAIL
  fi
  total_wall="$(awk -v a="$total_wall" -v b="$wall" 'BEGIN { printf "%.3f", a + b }')"
  # Unicode minus as in the docs' tables.
  cell="$(awk -v m="$mean" -v s="$std" 'BEGIN { printf "%.1f ± %.1f", m, s }' | sed 's/^-/−/')"
  printf '| %s | %s | %s | %.2f s | %s |\n' "$seed" "$cell" "$episodes" "$wall" "$result"
done
echo
echo "$passed of 5 seeds reach a deterministic evaluation mean return >= $threshold" \
     "(need $needed); total wall time ${total_wall} s; results in $out"
[[ $passed -ge $needed ]]
