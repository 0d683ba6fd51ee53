#!/usr/bin/env bash
# Training return of arms over seeds in one window of timesteps: for each run folder
# RUNS/ARM-sSEED, the mean return of the episodes fed to Algorithm 2 (episodes.csv, first = 1;
# the episodes learning_table.sh counts) whose iteration ended at t in (FROM, TO]; then per arm
# the mean ± std of the seeds' figures (sample std, n − 1) and the 95 % confidence interval of
# that mean (Student's t, n − 1 degrees of freedom, 2 to 11 seeds).
#   bash scripts/training_seeds.sh RUNS "ARM ..." "SEED ..." FROM TO
# Training episodes act with the policy's exploration noise, so this measures how well a body does
# under that noise; the deterministic test return of each run is in seed_table.sh.
set -euo pipefail
root=${1:?usage: training_seeds.sh RUNS_DIR "ARM ..." "SEED ..." FROM TO}
arms=${2:?arms}
seeds=${3:?seeds}
from=${4:?from (timesteps)}
to=${5:?to (timesteps)}
header="| arm |"; rule="|---|"
for s in $seeds; do header="$header seed $s |"; rule="$rule---|"; done
echo "$header across seeds (mean ± std) | 95 % interval of the mean |"
echo "$rule---|---|"
for a in $arms; do
  row="| $a |"; vals=""
  for s in $seeds; do
    f="$root/$a-s$s/episodes.csv"
    [ -f "$f" ] || { row="$row — |"; continue; }
    m=$(awk -F, -v lo="$from" -v hi="$to" 'FNR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
      $c["first"] == 1 && $c["t"] > lo && $c["t"] <= hi { n++; r += $c["return"] }
      END { if (n) printf "%.4f %d", r / n, n }' "$f")
    if [ -z "$m" ]; then row="$row — |"; continue; fi
    row="$row $(echo "$m" | awk '{ printf "%.2f (%d ep.)", $1, $2 }') |"
    vals="$vals ${m%% *}"
  done
  stats=$(echo "$vals" | awk '{ n = NF; if (n == 0) { print "— | —"; exit }
    for (i = 1; i <= n; ++i) s += $i; m = s / n
    if (n == 1) { printf "%.2f (1 seed) | —", m; exit }
    for (i = 1; i <= n; ++i) v += ($i - m) ^ 2; sd = sqrt(v / (n - 1))
    split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228", t, " ")
    if (n > 11) { printf "%.2f ± %.2f (%d seeds) | —", m, sd, n; exit }
    h = t[n - 1] * sd / sqrt(n)
    printf "%.2f ± %.2f (%d seeds) | %.2f to %.2f", m, sd, n, m - h, m + h }')
  echo "$row $stats |"
done
