#!/usr/bin/env bash
# Acceptance benchmark of the PPO learner (issue 3): trains Pendulum-v1 with
# configs/pendulum.toml for seeds 0..4, one after the other (each run is single-threaded),
# and prints the deterministic evaluation return (mean of 20 episodes) and the wall time per seed.
# Exits 0 only if at least 4 of the 5 seeds reach a mean return >= -250.
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

printf '%-6s %14s %12s %12s  %s\n' seed eval_mean eval_std wall_s result
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
  wall="$(value "$dir/summary.txt" wall_s)"
  if awk -v m="$mean" -v t="$threshold" 'BEGIN { exit !(m >= t) }'; then
    result=pass
    passed=$((passed + 1))
  else
    result=FAIL
  fi
  total_wall="$(awk -v a="$total_wall" -v b="$wall" 'BEGIN { printf "%.3f", a + b }')"
  printf '%-6s %14s %12s %12s  %s\n' "$seed" "$mean" "$std" "$wall" "$result"
done
echo "$passed of 5 seeds reach a deterministic evaluation return >= $threshold" \
     "(need $needed); total wall time ${total_wall} s; results in $out"
[[ $passed -ge $needed ]]
