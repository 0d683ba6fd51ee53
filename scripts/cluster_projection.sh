#!/bin/bash
# The scaling model of `bench cluster` (docs/cluster.md) fed with a whole finished run instead of a
# few bench iterations: the run's own collection, PPO update and policy time per iteration from its
# ppo.csv (a one-process run of RUN_THREADS threads), projected to RANKS ranks of THREADS threads:
#   per iteration: F · rounds(RANKS, THREADS)/rounds(1, RUN_THREADS) · (collect − policy) + policy + update
# with rounds(N, t) = ceil(ceil(PSI / N) / t), F the busiest rank's collection over the mean (1: none);
# messages left out (2–9 µs per exchange here).
#
#   bash scripts/cluster_projection.sh RUN_DIR PSI RUN_THREADS RANKS THREADS [F]
set -euo pipefail
if [ $# -lt 5 ]; then
  echo "usage: bash scripts/cluster_projection.sh RUN_DIR PSI RUN_THREADS RANKS THREADS [F]" >&2
  exit 2
fi
RUN=$1; PSI=$2; RT=$3; R=$4; T=$5; F=${6:-1}
CSV="$RUN/ppo.csv"
[ -f "$CSV" ] || { echo "cluster_projection.sh: no $CSV" >&2; exit 2; }
rounds() { local per=$(( ($PSI + $1 - 1) / $1 )); echo $(( (per + $2 - 1) / $2 )); }
R1=$(rounds 1 "$RT"); RN=$(rounds "$R" "$T")
awk -F, -v r1="$R1" -v rn="$RN" -v f="$F" -v ranks="$R" -v threads="$T" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  { c += $col["collect_s"]; u += $col["update_s"]; p += $col["policy_s"]; n++ }
  END {
    if (n == 0) { print "cluster_projection.sh: no PPO updates in ppo.csv" > "/dev/stderr"; exit 2 }
    t = f * rn / r1 * (c - p) + p + u
    printf "%d iterations: mean collection %.3f s, PPO update %.3f s, policy %.3f s per iteration\n", n, c / n, u / n, p / n
    printf "%d ranks x %d threads, F = %s: %.3f s per iteration, %.2f min for the run\n", ranks, threads, f, t / n, t / 60
  }' "$CSV"
