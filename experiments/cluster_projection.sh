#!/bin/bash
# The scaling model of `bench cluster` (docs/cluster.md) fed with a whole finished run instead of a
# few bench iterations: the run's own collection, PPO update and policy time per iteration from its
# ppo.csv (a one-process run of RUN_THREADS threads), projected to RANKS ranks of THREADS threads:
#   per iteration: F · rounds(RANKS, THREADS)/rounds(1, RUN_THREADS) · (collect − policy) + policy + update
# with rounds(N, t) = ceil(ceil(PSI / N) / t), F the busiest rank's collection over the mean (1: none);
# messages left out (2–9 µs per exchange here). With P (the ranks' starts during rank 0's update,
# MpiEnvPool::prestart; `bench cluster` prints the F and P for it), each iteration's update term
# is max(update, P · rounds(RANKS, THREADS)/rounds(1, RUN_THREADS) · (collect − policy)), and F is
# the one printed beside P (the collection without those starts).
#
#   bash experiments/cluster_projection.sh RUN_DIR PSI RUN_THREADS RANKS THREADS [F [P]]
set -euo pipefail
if [ $# -lt 5 ]; then
  echo "usage: bash experiments/cluster_projection.sh RUN_DIR PSI RUN_THREADS RANKS THREADS [F [P]]" >&2
  exit 2
fi
RUN=$1; PSI=$2; RT=$3; R=$4; T=$5; F=${6:-1}; P=${7:-0}
CSV="$RUN/ppo.csv"
[ -f "$CSV" ] || { echo "cluster_projection.sh: no $CSV" >&2; exit 2; }
rounds() { local per=$(( ($PSI + $1 - 1) / $1 )); echo $(( (per + $2 - 1) / $2 )); }
R1=$(rounds 1 "$RT"); RN=$(rounds "$R" "$T")
awk -F, -v r1="$R1" -v rn="$RN" -v f="$F" -v pre="$P" -v ranks="$R" -v threads="$T" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  {
    ci = $col["collect_s"]; ui = $col["update_s"]; pi = $col["policy_s"]
    c += ci; u += ui; p += pi; n++
    s = ranks > 1 ? pre * rn / r1 * (ci - pi) : 0
    t += f * rn / r1 * (ci - pi) + pi + (s > ui ? s : ui)
    if (s > ui) over += s - ui
  }
  END {
    if (n == 0) { print "cluster_projection.sh: no PPO updates in ppo.csv" > "/dev/stderr"; exit 2 }
    printf "%d iterations: mean collection %.3f s, PPO update %.3f s, policy %.3f s per iteration\n", n, c / n, u / n, p / n
    if (pre > 0) printf "the ranks'"'"' starts during the update: P = %s, outlasting it by %.3f s per iteration on average\n", pre, over / n
    printf "%d ranks x %d threads, F = %s: %.3f s per iteration, %.2f min for the run\n", ranks, threads, f, t / n, t / 60
  }' "$CSV"
