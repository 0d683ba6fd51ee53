#!/usr/bin/env bash
# Learning progress of a run folder, per window of W timesteps (default 20000; an iteration
# belongs to the window holding its last timestep, the t of both CSVs):
#  * from episodes.csv, the first episode of every environment in each iteration (first = 1, the
#    episodes fed to Algorithm 2): count, mean return, mean decisions, mean fraction of decisions
#    in the band, and the share that ended at the θ limit;
#  * from ppo.csv, the PPO updates in the window: mean approx_kl and mean epochs run (10 = no
#    early stop by target_kl).
#   bash scripts/learning_table.sh runs/NAME [W]
set -euo pipefail
run=${1:?usage: learning_table.sh RUN_DIR [WINDOW]}
w=${2:-20000}
for f in episodes.csv ppo.csv; do
  [ -f "$run/$f" ] || { echo "learning_table: $run/$f: no such file" >&2; exit 2; }
done
awk -F, -v w="$w" '
  FNR == 1 { delete col; for (i = 1; i <= NF; ++i) col[$i] = i; file++; next }
  file == 1 && $col["first"] == 1 {
    b = int(($col["t"] - 1) / w); n[b]++; r[b] += $col["return"]; d[b] += $col["decisions"]
    if ($col["decisions"] > 0) f[b] += $col["in_band"] / $col["decisions"]
    if ($col["reason"] == "theta_limit") th[b]++
    if (b > last) last = b
  }
  file == 2 {
    b = int(($col["t"] - 1) / w); nu[b]++; kl[b] += $col["approx_kl"]; ep[b] += $col["epochs"]
  }
  END {
    print "| timesteps | episodes | mean return | mean decisions | band fraction | ended at θ limit | PPO updates | mean approx_kl | mean epochs |"
    print "|---|---|---|---|---|---|---|---|---|"
    for (b = 0; b <= last; ++b) if (n[b])
      printf "| %dk-%dk | %d | %.2f | %.1f | %.1f %% | %.1f %% | %d | %.3g | %.1f |\n", b * w / 1000, (b + 1) * w / 1000, n[b], r[b] / n[b], d[b] / n[b], 100 * f[b] / n[b], 100 * th[b] / n[b], nu[b], (nu[b] ? kl[b] / nu[b] : 0), (nu[b] ? ep[b] / nu[b] : 0)
  }' "$run/episodes.csv" "$run/ppo.csv"
