#!/bin/bash
# How a rank waits in MPI_Finalize while rank 0 is still at work, without and with a barrier
# waited first as codesign's ranks wait (experiments/finalize_wakes.c; docs/journal/cluster.md,
# "A waiting rank's polls"). Two ranks on this machine (shared memory, loopback only).
#   bash experiments/finalize_wakes.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mpicc -O2 -o "$work/finalize_wakes" experiments/finalize_wakes.c -lm
. "$(dirname "$(readlink -f "$0")")/cluster_common.sh"  # $MPI: two ranks on this machine
for b in 0 1; do BARRIER=$b $MPI -x BARRIER "$work/finalize_wakes" "${1:-5}" | sort; done
