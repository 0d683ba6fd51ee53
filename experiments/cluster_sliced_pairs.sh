#!/bin/bash
# Whole runs of the same config timed in turns, so that all see the same speed of the machine.
# The runs of a round are started together, each in a session of its own, all stopped; then each
# in turn runs for SLICE seconds while the others are stopped (SIGSTOP to every process of their
# sessions), until all have finished. A run's time is the sum of its own windows (bash's
# EPOCHREALTIME, in microseconds). A VM whose speed drifts by several per cent over minutes
# (docs/journal/cluster.md) then moves every run of a round alike, which runs one after
# the other (experiments/cluster_run_pairs.sh) cannot give.
#
#   [KINDS="one ranks one"] bash experiments/cluster_sliced_pairs.sh BINARY OUTDIR ROUNDS [DECISIONS] [SLICE]
#
# KINDS lists the round's runs, 2 to 6 of: one (one process of 2 threads) and ranks (2 MPI ranks
# of 1 thread each); the default, one ranks one, gives the two-rank run beside two one-process
# runs, whose ratio to each other is the method's own spread (an A/A check). The config is
# cluster_run_pairs.sh's: configs/paper.toml cut to DECISIONS decisions (default 60000) with its
# phases scaled, written to OUTDIR/config.toml. SLICE: whole seconds, default 10. The run that
# takes the first slice turns with the rounds. Writes OUTDIR/N.A/, N.B/, ... (run folders, logs
# beside them), OUTDIR/N.time and OUTDIR/N.windows (per window: run, start, end in microseconds,
# how it ended), and prints per run its active seconds, windows and ratio to run A, and
# scripts/compare_runs.sh's count against A (the runs must be identical but for wall-clock fields;
# the runs' own timing columns include the time they were stopped). Run it on otherwise idle
# cores. Open MPI on this machine only (shared memory, loopback).
set -euo pipefail
export LC_ALL=C  # EPOCHREALTIME with a decimal point
if [ $# -lt 3 ]; then
  echo "usage: bash experiments/cluster_sliced_pairs.sh BINARY OUTDIR ROUNDS [DECISIONS] [SLICE]" >&2
  exit 2
fi
BIN=$(readlink -f "$1"); mkdir -p "$2"; OUT=$(readlink -f "$2"); N=$3; D=${4:-60000}; SLICE=${5:-10}
read -r -a KIND <<< "${KINDS:-one ranks one}"
NAME=(A B C D E F)
[ ${#KIND[@]} -ge 2 ] && [ ${#KIND[@]} -le 6 ] || { echo "cluster_sliced_pairs.sh: KINDS holds 2 to 6 kinds" >&2; exit 2; }
for k in "${KIND[@]}"; do
  case "$k" in one|ranks) ;; *) echo "cluster_sliced_pairs.sh: KINDS holds one or ranks, not '$k'" >&2; exit 2 ;; esac
done
cd "$(dirname "$0")/.."
CFG="$OUT/config.toml"
. "$(dirname "$(readlink -f "$0")")/cluster_common.sh"  # $MPI: two ranks on this machine
paper_cut_to "$D" "$CFG" cluster_sliced_pairs.sh

# $1: kind, $2: run folder. Starts the run stopped, in a session of its own (mpirun puts each rank
# in a process group of its own, so the stops go to the whole session): the shell stops itself
# before it becomes the run. The session's id is left in $started; it is the pid of a child of
# this shell, to be waited for (setsid does not fork here: a background job of a script leads no
# process group).
start() {
  local cmd
  if [ "$1" = one ]; then cmd="$BIN --threads 2"; else cmd="$MPI $BIN --threads 1"; fi
  setsid bash -c 'kill -STOP $$; exec "$@"' _ $cmd --config "$CFG" -o "$2" > "$2.log" 2>&1 &
  local pid=$!
  # Wait until it has stopped itself, so that the first SIGCONT cannot come before its SIGSTOP.
  state_of "$pid"
  until [ "$state" = T ]; do
    [ "$state" != Z ] || { echo "cluster_sliced_pairs.sh: the run for $2 ended before it began (log $2.log)" >&2; exit 1; }
    state_of "$pid"
  done
  started=$pid
}
# Leaves in $state the state letter of process $1 from /proc (Z also for one that is gone: it
# has ended and been reaped). A builtin read, no new process.
state_of() {
  state=Z
  { read -r _ _ state _ < "/proc/$1/stat"; } 2> /dev/null || state=Z
}
# $1: pid. True while the run has not ended (a zombie has ended: it waits only to be reaped).
alive() {
  state_of "$1"
  [ "$state" != Z ]
}
# True when every process of session $1 is stopped or has ended.
stopped() {
  local p
  for p in $(pgrep -s "$1"); do
    state_of "$p"
    case "$state" in T|t|Z|X) ;; *) return 1 ;; esac
  done
}
# Continues session $1 until it ends or $2 seconds pass; adds the window's microseconds to the
# variable named $3 and one window to $4. Polls every 20 ms with builtins only (no process is
# started while a run computes, beside pkill at the window's two ends).
exec {nap}<> <(:)  # a pipe nobody writes to: read -t on it sleeps without a new process
window() {
  local t0=${EPOCHREALTIME/./} t1
  pkill -CONT -s "$1"
  while alive "$1"; do
    t1=${EPOCHREALTIME/./}
    (( t1 - t0 < $2 * 1000000 )) || break
    read -r -t 0.02 -u "$nap" _ || true
  done
  # The window ends when every process of the run has stopped or ended: one already ending (a
  # process in exit cannot be stopped) keeps its window open until it has.
  local how=ended
  if alive "$1"; then
    how=slice
    pkill -STOP -s "$1"
    until stopped "$1"; do read -r -t 0.001 -u "$nap" _ || true; done
    alive "$1" || how=ended-while-stopping
  fi
  t1=${EPOCHREALTIME/./}
  echo "$3 $t0 $t1 $how" >> "$windows"
  printf -v "$3" '%d' $(( ${!3} + t1 - t0 ))
  printf -v "$4" '%d' $(( ${!4} + 1 ))
}
for i in $(seq 1 "$N"); do
  echo "round $i from $(date -u +%T) UTC: ${KIND[*]} in slices of $SLICE s"
  pid=(); t=(); w=(); windows="$OUT/$i.windows"; : > "$windows"  # per window: run, start, end [us], how it ended
  for k in "${!KIND[@]}"; do start "${KIND[$k]}" "$OUT/$i.${NAME[$k]}"; pid[k]=$started; t[k]=0; w[k]=0; done
  # The run that takes the first slice turns with the rounds.
  order=(); for k in "${!KIND[@]}"; do order+=($(( (k + i - 1) % ${#KIND[@]} ))); done
  more=1
  while [ $more = 1 ]; do
    more=0
    for k in "${order[@]}"; do
      alive "${pid[k]}" || continue
      window "${pid[k]}" "$SLICE" "t[$k]" "w[$k]"; more=1
    done
  done
  for k in "${!KIND[@]}"; do
    rc=0; wait "${pid[k]}" || rc=$?
    [ $rc = 0 ] || { echo "round $i: run ${NAME[$k]} failed with exit $rc (log $OUT/$i.${NAME[$k]}.log)" >&2; exit 1; }
  done
  : > "$OUT/$i.time"
  for k in "${!KIND[@]}"; do
    awk -v t="${t[k]}" -v t0="${t[0]}" -v w="${w[k]}" -v n="${NAME[$k]}" -v kind="${KIND[$k]}" -v i="$i" \
      'BEGIN { printf "round %d: %s (%s) %.3f s in %d windows, %.4f of A\n", i, n, kind, t / 1e6, w, t / t0 }' |
      tee -a "$OUT/$i.time"
  done
  for k in "${!KIND[@]}"; do
    [ "$k" = 0 ] && continue
    { bash scripts/compare_runs.sh "$OUT/$i.A" "$OUT/$i.${NAME[$k]}" || true; } | tail -1
  done
done
