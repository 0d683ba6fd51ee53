#!/bin/bash
# The final evaluation alone (d*, the runner-up, the fixed-angle reference), timed on one machine:
# a finished run's folder is resumed, which only evaluates (docs/run_folder.md, "Stopping a run
# (SIGTERM, SIGINT)"; formerly docs/reliability.md §5), in rounds whose order alternates (the
# VM's speed drifts within the hour; compare runs of one round).
#
#   bash experiments/evaluation_pairs.sh BINARY RUN OUTDIR ROUNDS [WAKER_US]
#
# RUN is a run folder whose training is complete (checkpoint.bin at its total_timesteps). Each
# round copies it without result.toml, eval/, frames/ and figures/, and resumes it twice with
# OUTDIR/config.toml (RUN's config with [render] off) and --no-figures:
#   - without WAKER_US: one process of 2 threads ("one") against 2 MPI ranks of 1 thread
#     ("ranks"; rank 0 evaluates on both ranks' threads while rank 1 waits for its end);
#   - with WAKER_US: one process alone ("one") against one process beside experiments/idle_waker.c
#     waking every WAKER_US microseconds ("waker"): what a waiting rank's wake-ups alone cost.
# Prints per run the seconds from launch to result.toml and their split by the eval/ files'
# times: to best.csv (startup, d*'s model and 100 episodes), to runner_up.csv, to result.toml (the
# fixed-angle reference). Open MPI on this machine only (shared memory, loopback). Run it on
# otherwise idle cores. docs/journal/cluster.md, "A waiting rank's polls".
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: bash experiments/evaluation_pairs.sh BINARY RUN OUTDIR ROUNDS [WAKER_US]" >&2
  exit 2
fi
BIN=$(readlink -f "$1"); RUN=$(readlink -f "$2"); mkdir -p "$3"; OUT=$(readlink -f "$3"); N=$4; WAKER=${5:-}
[ -f "$RUN/checkpoint.bin" ] && [ -f "$RUN/config.toml" ] || { echo "evaluation_pairs.sh: $RUN: no checkpoint.bin or config.toml" >&2; exit 2; }
cd "$(dirname "$0")/.."
# RUN's config with its [render] table (if any) replaced by one that is off.
awk '/^\[/ { skip = ($0 ~ /^\[render\]/) } !skip' "$RUN/config.toml" > "$OUT/config.toml"
printf '\n[render]\nenabled = false\n' >> "$OUT/config.toml"
if [ -n "$WAKER" ]; then cc -O2 -o "$OUT/idle_waker" experiments/idle_waker.c; fi
. "$(dirname "$(readlink -f "$0")")/cluster_common.sh"  # $MPI: two ranks on this machine
mtime() { stat -c %.3Y "$1"; }
# $1: round, $2: kind; the rest: the launch. Resumes a fresh copy of RUN into OUT/ROUND.KIND.
launch() {
  local dir="$OUT/$1.$2" kind=$2 s pid=""; shift 2
  rm -rf "$dir"; mkdir -p "$dir"
  find "$RUN" -maxdepth 1 -type f ! -name result.toml -exec cp {} "$dir/" \;
  [ "$kind" = waker ] && { "$OUT/idle_waker" "$WAKER" 100000 > /dev/null & pid=$!; }
  s=$(date +%s.%N)
  "$@" --config "$OUT/config.toml" -o "$dir" --resume --no-figures --quiet > "$dir.log" 2>&1 || { echo "$dir: exit $?" >&2; }
  [ -z "$pid" ] || kill "$pid"
  [ -f "$dir/result.toml" ] || { echo "$dir: no result.toml (log: $dir.log)" >&2; exit 1; }
  awk -v s="$s" -v b="$(mtime "$dir/eval/best.csv")" -v r="$(mtime "$dir/eval/runner_up.csv")" \
      -v e="$(mtime "$dir/result.toml")" -v name="$dir" \
      'BEGIN { printf "%s: %.2f s to result.toml (to best.csv %.2f, runner_up.csv %.2f, result.toml %.2f)\n",
               name, e - s, b - s, r - b, e - r }' | tee "$dir.time"
}
first() { sed -E 's/.*: ([0-9.]+) s to result.*/\1/' "$1"; }
other=ranks; [ -z "$WAKER" ] || other=waker
for i in $(seq 1 "$N"); do
  echo "round $i from $(date -u +%T) UTC"
  for kind in $([ $((i % 2)) = 1 ] && echo "one $other" || echo "$other one"); do
    case $kind in
      one) launch "$i" one "$BIN" run --threads 2 ;;
      ranks) launch "$i" ranks $MPI "$BIN" run --threads 1 ;;
      waker) launch "$i" waker "$BIN" run --threads 2 ;;
    esac
  done
  awk -v a="$(first "$OUT/$i.one.time")" -v b="$(first "$OUT/$i.$other.time")" -v i="$i" -v o="$other" \
    'BEGIN { printf "round %d: %s - one = %+.2f s (%+.1f %%)\n", i, o, b - a, 100 * (b - a) / a }'
done
