#!/usr/bin/env bash
# Test return of d* per seed and arm, and the mean ± std across seeds (sample std, n − 1), from
# the result.toml of run folders named <arm>-s<seed> under a directory:
#   bash scripts/seed_table.sh runs "probe_j47 probe_j47_norm probe_j47_norm_history" "1 2 3"
# Prints a Markdown table: one row per arm, each seed's "mean ± std over N episodes (band %)",
# then the across-seed mean ± std of the per-seed means. A missing run is printed as "—" and
# left out of the across-seed figure. With a fourth argument `interval`, one more column: the 95 %
# confidence interval of the across-seed mean, mean ± t · std / √n with Student's t of n − 1
# degrees of freedom (2 to 11 seeds).
set -euo pipefail
root=${1:?usage: seed_table.sh RUNS_DIR "ARM ..." "SEED ..."}
arms=${2:?arms}
seeds=${3:?seeds}
interval=${4:-}
[ -z "$interval" ] || [ "$interval" = interval ] || { echo "seed_table: the fourth argument is 'interval' or nothing, not '$interval'" >&2; exit 2; }
field() { awk -v k="$2" '/^\[best\]/ { b = 1; next } /^\[/ { b = 0 } b && $1 == k { print $3; exit }' "$1"; }
. "$(dirname "$0")/seed_stats.sh"
if [ -n "$interval" ]; then
  seed_header "$seeds" "across_seeds_(mean_±_std) 95_%_interval_of_the_mean"
else
  seed_header "$seeds" "across_seeds_(mean_±_std)"
fi
for a in $arms; do
  row="| $a |"; vals=""
  for s in $seeds; do
    f="$root/$a-s$s/result.toml"
    if [ -f "$f" ]; then
      m=$(field "$f" test_return); sd=$(field "$f" test_return_std); n=$(field "$f" test_episodes); band=$(field "$f" band_fraction)
      row="$row $(awk -v m="$m" -v s="$sd" -v n="$n" -v b="$band" 'BEGIN { printf "%.2f ± %.2f (%d ep., band %.0f %%)", m, s, n, 100 * b }') |"
      vals="$vals $m"
    else
      row="$row — |"
    fi
  done
  if [ -n "$interval" ]; then
    echo "$row $(across_seeds "$vals") | $(interval_of_mean "$vals") |"
  else
    echo "$row $(across_seeds "$vals") |"
  fi
done
