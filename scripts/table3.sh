#!/usr/bin/env bash
# The Table III equivalent of docs/journal/results.md, printed from finished run folders.
#   bash scripts/table3.sh runs/paper [LABEL=RUN_DIR ...]
# First table: one row per run (the co-design run first, then e.g. no_feedback=runs/paper_no_feedback)
# with d*, p*, its test return (mean ± std over the evaluation episodes) and band fraction, the
# runner-up likewise, timesteps and wall time (summed over resumes). Second table: how the co-design
# run's distribution evolved: phase, β, entropy of q_disc, the leading design with its R̂, q_disc of
# the final d* and runner-up, and μ1, σ1 (kPa) of d* from its last sample (sampled.csv).
set -euo pipefail
main=${1:?usage: table3.sh RUN_DIR [LABEL=RUN_DIR ...]}
shift
for d in "$main" "${@#*=}"; do
  [ -f "$d/result.toml" ] || { echo "table3: $d/result.toml: no such file (run not finished?)" >&2; exit 2; }
done

# key VALUE of a section of result.toml (first token after '=', comments dropped)
get() { awk -v sec="[$2]" -v key="$3" '
  /^\[/ { in_sec = ($0 == sec) }
  in_sec && $1 == key { sub(/^[^=]*= */, ""); sub(/ *#.*$/, ""); print; exit }' "$1/result.toml"; }

hm() { awk -v s="$1" 'BEGIN { m = int(s / 60 + 0.5); printf "%d h %02d min", int(m / 60), m % 60 }'; }
design() { printf 'j%s {%s, %s mm, %s mm}' "$(get "$1" "$2" design)" "$(get "$1" "$2" n)" "$(get "$1" "$2" l_mm)" "$(get "$1" "$2" w_mm)"; }
pressures() { get "$1" "$2" pressures_kPa | awk -F'[][, ]+' '{ printf "[%.3f, %.3f] kPa", $2, $3 }'; }
ret() { awk -v m="$(get "$1" "$2" test_return)" -v s="$(get "$1" "$2" test_return_std)" -v n="$(get "$1" "$2" test_episodes)" \
          -v b="$(get "$1" "$2" band_fraction)" 'BEGIN { printf "%.2f ± %.2f (%d episodes), band %.0f %%", m, s, n, 100 * b }'; }

echo "| run | observation, baseline | d* | p* | test return of d* | runner-up | its p | its test return | timesteps | wall time |"
echo "|---|---|---|---|---|---|---|---|---|---|"
row() {
  local label=$1 d=$2 ru="— | — | —"
  # a single-design run has no runner-up
  [ -n "$(get "$d" runner_up design)" ] && ru="$(design "$d" runner_up) | $(pressures "$d" runner_up) | $(ret "$d" runner_up)"
  printf '| %s | %s, %s | %s | %s | %s | %s | %s | %s |\n' "$label" \
    "$(get "$d" run observation | tr -d '"')" "$(get "$d" run baseline | tr -d '"')" \
    "$(design "$d" best)" "$(pressures "$d" best)" "$(ret "$d" best)" "$ru" \
    "$(get "$d" run timesteps)" "$(hm "$(get "$d" run wall_s)")"
}
row "co-design ($main)" "$main"
for a in "$@"; do row "${a%%=*} (${a#*=})" "${a#*=}"; done

jb=$(get "$main" best design); jr=$(get "$main" runner_up design)
echo
echo "Evolution of $main (d* = j$jb, runner-up j$jr):"
echo
echo "| t | phase | β | entropy of q_disc (nats) | leading design, R̂ | q_disc(j$jb) | q_disc(j$jr) | μ1, σ1 of j$jb (kPa) |"
echo "|---|---|---|---|---|---|---|---|"
awk -F, -v jb="$jb" -v jr="$jr" '
  FNR == 1 { delete col; for (i = 1; i <= NF; ++i) col[$i] = i; file++; next }
  file == 1 { T = $col["t"]; if (T > tmax) tmax = T
              ph[T] = $col["phase"]; be[T] = $col["beta"]; en[T] = $col["entropy"]
              lead[T] = $col["best_j"]; sc[T] = $col["best_score"]; n++; ts[n] = T }
  file == 2 { qb[$col["t"]] = $col["q" jb]; qr[$col["t"]] = $col["q" jr] }
  file == 3 && $col["j"] == jb { ms[$col["t"]] = sprintf("%.3f, %.3f", $col["mu1_kPa"], $col["sigma1_kPa"]) }
  END {
    # milestones: every tenth of the run, and the last iteration
    last = ""; ms_now = "not sampled yet"; m = 1
    for (i = 1; i <= n; ++i) {
      T = ts[i]; if (T in ms) ms_now = ms[T]
      if (T >= m * tmax / 10 - 1e-9 || i == n) {
        printf "| %d | %s | %.3g | %.3f | j%d, %.2f | %.4f | %.4f | %s |\n", T, ph[T], be[T], en[T], lead[T], sc[T], qb[T], qr[T], ms_now
        while (m * tmax / 10 <= T + 1e-9) m++
      }
    }
  }' "$main/distribution.csv" "$main/q_disc.csv" "$main/sampled.csv"
