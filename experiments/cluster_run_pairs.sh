#!/bin/bash
# Whole runs on one machine: one process of 2 threads against 2 MPI ranks of 1 thread each, the
# order alternating between rounds (the VM's speed drifts within the hour, so only the runs of one
# round are compared). Each run is a whole `codesign --config ... -o ...`: meshing, every
# iteration, the checkpoints, the final evaluation and the figures, as a user launches it.
#
#   bash experiments/cluster_run_pairs.sh BINARY OUTDIR ROUNDS [DECISIONS]
#
# The config is configs/paper.toml cut to DECISIONS decisions (default 200000, i.e. 100 iterations
# of the paper's 40 x 50), with its phase boundaries (T1, T2, the entropy decay) scaled by
# DECISIONS / 1000000 so the run passes through every phase; it is written to OUTDIR/config.toml.
# A paper-size pair takes about 3 hours on a Zen 1 VM of 2 cores; this one is about an hour.
# Writes OUTDIR/N.one/ and N.ranks/ (run folders with their logs), and prints per run the wall
# seconds and ppo.csv's sums of collect_s, update_s and policy_s, the two-rank run's ratio to the
# one-process run of its round, and scripts/compare_runs.sh's count (the runs must be identical
# but for wall-clock fields). BASELINE=BIN0 adds to each round a two-rank run of another binary
# (N.base/, e.g. the commit before a change to the ranks' code), compared with the same counts;
# the order is one, base, ranks in odd rounds and the reverse in even ones. Run it on otherwise
# idle cores. Open MPI on this machine only
# (shared memory, loopback).
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: bash experiments/cluster_run_pairs.sh BINARY OUTDIR ROUNDS [DECISIONS]" >&2
  exit 2
fi
BIN=$(readlink -f "$1"); [ -z "${BASELINE:-}" ] || BASELINE=$(readlink -f "$BASELINE"); mkdir -p "$2"; OUT=$(readlink -f "$2"); N=$3; D=${4:-200000}
cd "$(dirname "$0")/.."
CFG="$OUT/config.toml"
. "$(dirname "$(readlink -f "$0")")/cluster_common.sh"  # $MPI: two ranks on this machine
paper_cut_to "$D" "$CFG" cluster_run_pairs.sh

# $1: run folder, $2: wall seconds. ppo.csv's columns are looked up by name in its header.
report() {
  awk -F, -v w="$2" -v name="$1" 'NR == 1 { for (k = 1; k <= NF; ++k) col[$k] = k
      if (!("collect_s" in col) || !("update_s" in col) || !("policy_s" in col)) {
        print name "/ppo.csv: no collect_s, update_s or policy_s column" > "/dev/stderr"; bad = 1; exit 1 } }
    NR > 1 { c += $col["collect_s"]; u += $col["update_s"]; p += $col["policy_s"] }
    END { if (bad) exit 1; printf "%s: wall %d s, collect %.1f s, update %.1f s, policy %.1f s\n", name, w, c, u, p }' "$1/ppo.csv"
}
# $1: round, $2: kind (one, base or ranks), then the launcher and binary; runs one whole run into
# OUT/ROUND.KIND with its log beside it and writes its report to OUT/ROUND.KIND.time.
launch() {
  local dir="$OUT/$1.$2" s; shift 2; s=$(date +%s)
  "$@" --config "$CFG" -o "$dir" > "$dir.log" 2>&1
  report "$dir" "$(( $(date +%s) - s ))" | tee "$dir.time"
}
one() { launch "$1" one "$BIN" --threads 2; }
ranks() { launch "$1" ranks $MPI "$BIN" --threads 1; }
base() { [ -z "${BASELINE:-}" ] || launch "$1" base $MPI "$BASELINE" --threads 1; }
wall() { sed -E 's/.*wall ([0-9]+) s.*/\1/' "$1"; }
for i in $(seq 1 "$N"); do
  echo "round $i from $(date -u +%T) UTC"
  if [ $((i % 2)) = 1 ]; then one "$i"; base "$i"; ranks "$i"; else ranks "$i"; base "$i"; one "$i"; fi
  for r in ranks base; do
    [ -f "$OUT/$i.$r.time" ] || continue
    awk -v a="$(wall "$OUT/$i.one.time")" -v b="$(wall "$OUT/$i.$r.time")" -v i="$i" -v r="$r" \
      'BEGIN { printf "round %d: two ranks (%s) / one process = %.3f (wall)\n", i, r, b / a }'
    { bash scripts/compare_runs.sh "$OUT/$i.one" "$OUT/$i.$r" || true; } | tail -1
  done
done
