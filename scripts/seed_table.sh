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
header="| arm |"; rule="|---|"
for s in $seeds; do header="$header seed $s |"; rule="$rule---|"; done
if [ -n "$interval" ]; then
  echo "$header across seeds (mean ± std) | 95 % interval of the mean |"
  echo "$rule---|---|"
else
  echo "$header across seeds (mean ± std) |"
  echo "$rule---|"
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
  across=$(echo "$vals" | awk '{ n = NF; for (i = 1; i <= n; ++i) s += $i; if (n == 0) { print "—"; exit }
    m = s / n; for (i = 1; i <= n; ++i) v += ($i - m) ^ 2
    if (n > 1) printf "%.2f ± %.2f (%d seeds)", m, sqrt(v / (n - 1)), n; else printf "%.2f (1 seed)", m }')
  if [ -n "$interval" ]; then
    ci=$(echo "$vals" | awk '{ n = NF; if (n < 2 || n > 11) { print "—"; exit }
      split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228", t, " ")
      for (i = 1; i <= n; ++i) s += $i; m = s / n; for (i = 1; i <= n; ++i) v += ($i - m) ^ 2
      h = t[n - 1] * sqrt(v / (n - 1)) / sqrt(n); printf "%.2f ± %.2f (%.2f to %.2f)", m, h, m - h, m + h }')
    echo "$row $across | $ci |"
  else
    echo "$row $across |"
  fi
done
