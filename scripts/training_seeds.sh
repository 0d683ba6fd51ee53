#!/usr/bin/env bash
# Training return of arms over seeds in one window of timesteps: for each run folder
# RUNS/ARM-sSEED, the mean return of the episodes fed to Algorithm 2 (episodes.csv, first = 1;
# the episodes learning_table.sh counts) whose iteration ended at t in (FROM, TO]; then per arm
# the mean ± std of the seeds' figures (sample std, n − 1) and the 95 % confidence interval of
# that mean (Student's t, n − 1 degrees of freedom, 2 to 11 seeds; scripts/seed_stats.sh).
#   bash scripts/training_seeds.sh RUNS "ARM ..." "SEED ..." FROM TO
# Training episodes act with the policy's exploration noise, so this measures how well a body does
# under that noise; the deterministic test return of each run is in seed_table.sh.
set -euo pipefail
root=${1:?usage: training_seeds.sh RUNS_DIR "ARM ..." "SEED ..." FROM TO}
arms=${2:?arms}
seeds=${3:?seeds}
from=${4:?from (timesteps)}
to=${5:?to (timesteps)}
. "$(dirname "$0")/seed_stats.sh"
seed_header "$seeds" "across_seeds_(mean_±_std) 95_%_interval_of_the_mean"
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
  echo "$row $(across_seeds "$vals") | $(interval_of_mean "$vals") |"
done
