#!/usr/bin/env bash
# Where given designs stand among all 110 under the classical baselines (docs/results.md, "Does
# the co-design agree?"): best fixed θ from a survey folder, force PID and strain PID from a
# sweep folder (test return ± std, rank 1 = best of 110).
#   bash scripts/design_ranks.sh SURVEY_DIR SWEEP_DIR J [J ...]
set -euo pipefail
survey=${1:?usage: design_ranks.sh SURVEY_DIR SWEEP_DIR J [J ...]}
sweep=${2:?usage: design_ranks.sh SURVEY_DIR SWEEP_DIR J [J ...]}
shift 2
[ $# -ge 1 ] || { echo "design_ranks: name at least one design index" >&2; exit 2; }
for f in "$survey/survey.csv" "$sweep/sweep.csv"; do
  [ -f "$f" ] || { echo "design_ranks: $f: no such file" >&2; exit 2; }
done
echo "| design | best fixed θ (rank) | force PID at p = 0 (rank) | strain PID at p = 0 (rank) |"
echo "|---|---|---|---|"
awk -F, -v want="$*" '
  FNR == 1 { delete col; for (i = 1; i <= NF; ++i) col[$i] = i; file++; next }
  file == 1 { fx[$col["j"]] = $col["fixed_theta_return"]; nfx++ }
  file == 2 { c = $col["controller"]; v[c, $col["j"]] = $col["test_return"]; s[c, $col["j"]] = $col["test_return_std"]; n[c]++ }
  function rank_of(arr, key, total,   k, r) { r = 1; for (k in arr) if (arr[k] > arr[key]) r++; return r }
  function cell(c, j,   k, r, cnt, rk) {
    if (!((c, j) in v)) return "—"
    rk = 1; cnt = 0
    for (k in v) { split(k, p, SUBSEP); if (p[1] == c) { cnt++; if (v[k] > v[c, j]) rk++ } }
    return sprintf("%.2f ± %.2f (%d/%d)", v[c, j], s[c, j], rk, cnt)
  }
  END {
    m = split(want, js, " ")
    for (i = 1; i <= m; ++i) {
      j = js[i]
      f = (j in fx) ? sprintf("%.2f (%d/%d)", fx[j], rank_of(fx, j), nfx) : "—"
      printf "| j%s | %s | %s | %s |\n", j, f, cell("pid_force", j), cell("pid_strain", j)
    }
  }' "$survey/survey.csv" "$sweep/sweep.csv"
