#!/usr/bin/env bash
# Where designs stood in a run's design distribution: for each J, its rank and probability in
# q_disc after the update at timestep T (rank 1 = most probable; q_disc is monotone in R̂), and
# how many updates it led (distribution.csv best_j) and the last timestep it did.
#   bash experiments/qdisc_rank.sh RUN_DIR T J [J ...]
set -euo pipefail
run=${1:?usage: qdisc_rank.sh RUN_DIR T J [J ...]}
t=${2:?usage: qdisc_rank.sh RUN_DIR T J [J ...]}
shift 2
[ $# -ge 1 ] || { echo "qdisc_rank: name at least one design index" >&2; exit 2; }
for f in q_disc.csv distribution.csv; do
  [ -f "$run/$f" ] || { echo "qdisc_rank: $run/$f: no such file" >&2; exit 2; }
done
awk -F, -v T="$t" -v want="$*" '
  FNR == 1 { delete col; for (i = 1; i <= NF; ++i) col[$i] = i; file++; next }
  file == 1 && $col["t"] == T { found = 1; for (j = 0; j < 110; ++j) q[j] = $col["q" j] }
  file == 2 { led[$col["best_j"]]++; last[$col["best_j"]] = $col["t"] }
  END {
    if (!found) { print "qdisc_rank: no update at t = " T " in q_disc.csv" > "/dev/stderr"; exit 2 }
    print "| design | rank in q_disc at t = " T " | q_disc | updates led | last led at t |"
    print "|---|---|---|---|---|"
    m = split(want, js, " ")
    for (i = 1; i <= m; ++i) {
      j = js[i]; r = 1
      for (k = 0; k < 110; ++k) if (q[k] > q[j]) r++
      printf "| j%d | %d | %.4f | %d | %s |\n", j, r, q[j], led[j] + 0, (j in last) ? last[j] : "—"
    }
  }' "$run/q_disc.csv" "$run/distribution.csv"
