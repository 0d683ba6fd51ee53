#!/usr/bin/env bash
# Where given designs stand among all 110 under the classical baselines (docs/journal/results.md,
# "Classical baselines and the design landscape", its paragraph "Does the co-design agree?", and
# "Where the seeds' d* stand under the classical controllers"; issue 18 §4): the best fixed θ
# from a survey folder (or "-" for none), and every controller a sweep folder holds (force PID,
# strain PID, the PI on the force estimated from strain and angle: sweep.csv's pid_force,
# pid_strain, pid_estimate rows, at the sweep's pressure), each as test return ± std and its
# rank (1 = best of the designs the sweep holds).
#   bash experiments/design_ranks.sh SURVEY_DIR|- SWEEP_DIR J [J ...]
set -euo pipefail
survey=${1:?usage: design_ranks.sh SURVEY_DIR|- SWEEP_DIR J [J ...]}
sweep=${2:?usage: design_ranks.sh SURVEY_DIR|- SWEEP_DIR J [J ...]}
shift 2
[ $# -ge 1 ] || { echo "design_ranks: name at least one design index" >&2; exit 2; }
[ -f "$sweep/sweep.csv" ] || { echo "design_ranks: $sweep/sweep.csv: no such file" >&2; exit 2; }
survey_csv=/dev/null
if [ "$survey" != "-" ]; then
  survey_csv="$survey/survey.csv"
  [ -f "$survey_csv" ] || { echo "design_ranks: $survey_csv: no such file" >&2; exit 2; }
fi
awk -F, -v want="$*" -v sweepf="$sweep/sweep.csv" '
  FNR == 1 { delete col; for (i = 1; i <= NF; ++i) col[$i] = i; file = FILENAME == sweepf ? 2 : 1; next }
  file == 1 && ("fixed_theta_return" in col) { fx[$col["j"]] = $col["fixed_theta_return"]; nfx++ }
  file == 2 {
    c = $col["controller"]; v[c, $col["j"]] = $col["test_return"]; s[c, $col["j"]] = $col["test_return_std"]
    if (!(c in seen)) { seen[c] = 1; p[c] = $col["p1_kPa"] }
  }
  function rank_of(arr, key,   k, r) { r = 1; for (k in arr) if (arr[k] > arr[key]) r++; return r }
  function cell(c, j,   k, q, cnt, rk) {
    if (!((c, j) in v)) return "—"
    rk = 1; cnt = 0
    for (k in v) { split(k, q, SUBSEP); if (q[1] == c) { cnt++; if (v[k] > v[c, j]) rk++ } }
    return sprintf("%.2f ± %.2f (%d/%d)", v[c, j], s[c, j], rk, cnt)
  }
  END {
    nc = 0
    split("pid_force pid_strain pid_estimate", order, " ")
    name["pid_force"] = "force PID"; name["pid_strain"] = "strain PID"; name["pid_estimate"] = "PI on F̂(ε, θ)"
    for (i = 1; i <= 3; ++i) if (order[i] in seen) cs[++nc] = order[i]
    head = "| design | best fixed θ (rank) |"; rule = "|---|---|"
    for (i = 1; i <= nc; ++i) { head = head sprintf(" %s at p1 = %g kPa (rank) |", name[cs[i]], p[cs[i]]); rule = rule "---|" }
    print head; print rule
    m = split(want, js, " ")
    for (i = 1; i <= m; ++i) {
      j = js[i]
      line = sprintf("| j%s | %s |", j, (j in fx) ? sprintf("%.2f (%d/%d)", fx[j], rank_of(fx, j), nfx) : "—")
      for (k = 1; k <= nc; ++k) line = line " " cell(cs[k], j) " |"
      print line
    }
  }' "$survey_csv" "$sweep/sweep.csv"
