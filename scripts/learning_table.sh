#!/usr/bin/env bash
# Learning progress of a run folder: for each window of W timesteps (default 20000), the first
# episode of every environment in each iteration (first = 1 in episodes.csv, the episodes fed
# to Algorithm 2): count, mean return, mean decisions, mean fraction of decisions in the band.
#   bash scripts/learning_table.sh runs/NAME [W]
set -euo pipefail
run=${1:?usage: learning_table.sh RUN_DIR [WINDOW]}
w=${2:-20000}
[ -f "$run/episodes.csv" ] || { echo "learning_table: $run/episodes.csv: no such file" >&2; exit 2; }
awk -F, -v w="$w" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  $col["first"] == 1 {
    b = int(($col["t"]) / w); n[b]++; r[b] += $col["return"]; d[b] += $col["decisions"]
    if ($col["decisions"] > 0) f[b] += $col["in_band"] / $col["decisions"]
    if (b > last) last = b
  }
  END {
    print "| timesteps | episodes | mean return | mean decisions | band fraction |"
    print "|---|---|---|---|---|"
    for (b = 0; b <= last; ++b) if (n[b])
      printf "| %dk-%dk | %d | %.2f | %.1f | %.1f %% |\n", b * w / 1000, (b + 1) * w / 1000, n[b], r[b] / n[b], d[b] / n[b], 100 * f[b] / n[b]
  }' "$run/episodes.csv"
