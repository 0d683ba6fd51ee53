#!/bin/bash
# Rounds of `codesign bench cluster` on one machine: one process of 2 threads against 2 MPI ranks of
# 2 threads each, the order alternating between rounds (the VM's speed drifts within the hour, so
# only launches of one round are compared). SAMPLE_AFTER seconds into each launch (default 150),
# SAMPLE_FOR seconds (default 20) of every thread's CPU time and context switches are read from
# /proc (docs/journal/cluster.md, "Where the two-rank launch's time goes").
#
#   bash experiments/cluster_rounds.sh BINARY CONFIG OUTDIR ROUNDS [WARMUP]
#
# Writes OUTDIR/N.one.txt and N.ranks.txt (the benches' output), N.one.ctx and N.ranks.ctx (per
# thread: user and system seconds, voluntary and involuntary switches over the window), N.time.
# RANK_THREADS (default 2) sets the two-rank launch's --threads per rank (1: the ranks do not share
# cores). LOCKSTEP=1 adds a third launch to each round, the two ranks with `--lockstep` (rollouts
# step by step, meeting at every decision, as before whole rollouts ran on the ranks), written to
# N.lockstep.txt and N.lockstep.ctx; the order is one, ranks, lockstep in odd rounds and the reverse
# in even ones. Run it on otherwise idle cores. Open MPI on this machine only (shared memory,
# loopback).
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: bash experiments/cluster_rounds.sh BINARY CONFIG OUTDIR ROUNDS [WARMUP]" >&2
  exit 2
fi
BIN=$(readlink -f "$1"); CFG=$2; OUT=$3; N=$4; WARMUP=${5:-40}
AFTER=${SAMPLE_AFTER:-150}; FOR=${SAMPLE_FOR:-20}
mkdir -p "$OUT"
. "$(dirname "$(readlink -f "$0")")/cluster_common.sh"  # $MPI: two ranks on this machine
BENCH="bench cluster --config $CFG --threads 2 --warmup $WARMUP --iterations 5"
RANK_BENCH="bench cluster --config $CFG --threads ${RANK_THREADS:-2} --warmup $WARMUP --iterations 5"

# One line per thread of the bench's processes: pid-tid user_ticks system_ticks voluntary involuntary
threads_now() {
  local p t
  for p in $(pgrep -f "$BIN bench" || true); do
    for t in /proc/"$p"/task/*; do
      echo "$p-$(basename "$t") $(awk '{print $14, $15}' "$t"/stat 2>/dev/null) $(grep -E '^(voluntary|nonvoluntary)_ctxt' "$t"/status 2>/dev/null | awk '{print $2}' | tr '\n' ' ')"
    done
  done | sort
}
sample() {  # $1: output file
  sleep "$AFTER"
  local a b
  a=$(mktemp); b=$(mktemp)
  threads_now > "$a"; sleep "$FOR"; threads_now > "$b"
  join "$a" "$b" | awk -v hz="$(getconf CLK_TCK)" 'NF == 9 {printf "%s user %.2f s, system %.2f s, voluntary %d, involuntary %d\n", $1, ($6-$2)/hz, ($7-$3)/hz, $8-$4, $9-$5}' > "$1"
  rm -f "$a" "$b"
}
one() { sample "$OUT/$1.one.ctx" & "$BIN" $BENCH > "$OUT/$1.one.txt" 2>&1; wait; }
ranks() { sample "$OUT/$1.ranks.ctx" & $MPI "$BIN" $RANK_BENCH > "$OUT/$1.ranks.txt" 2>&1; wait; }
lockstep() {
  [ "${LOCKSTEP:-0}" = 1 ] || return 0
  sample "$OUT/$1.lockstep.ctx" & $MPI "$BIN" $RANK_BENCH --lockstep > "$OUT/$1.lockstep.txt" 2>&1; wait
}
for i in $(seq 1 "$N"); do
  date -u +%T > "$OUT/$i.time"
  if [ $((i % 2)) = 1 ]; then one "$i"; ranks "$i"; lockstep "$i"; else lockstep "$i"; ranks "$i"; one "$i"; fi
  date -u +%T >> "$OUT/$i.time"
done
