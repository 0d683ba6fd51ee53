#!/bin/bash
# The summary of experiments/cluster_sliced_pairs.sh's rounds in OUTDIR (its N.time files): per round
# the mean active time of its two-rank runs over the mean of its one-process runs, and where a
# round holds two runs of one kind, the second's over the first's (the A/A check: what the method
# gives for no difference); then over the rounds the mean of each ratio, its sample standard
# deviation, standard error and one-sided 95 % upper bound (the rounds taken as independent).
#
#   bash experiments/cluster_sliced_summary.sh OUTDIR [OUTDIR...]
#
# Several OUTDIRs are taken as one series, their rounds numbered on in the order given.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: bash experiments/cluster_sliced_summary.sh OUTDIR [OUTDIR...]" >&2; exit 2; }
for OUT in "$@"; do
  ls "$OUT"/*.time > /dev/null 2>&1 || { echo "cluster_sliced_summary.sh: no N.time file in $OUT" >&2; exit 2; }
done
r=0
for OUT in "$@"; do
  for f in $(ls "$OUT"/*.time | sort -V); do r=$((r + 1)); sed -E "s/^round [0-9]+:/round $r:/" "$f"; done
done | awk '
  # round R: X (kind) S s in W windows, ...
  $1 == "round" { r = $2 + 0; kind = $4; gsub(/[()]/, "", kind); s = $5 + 0
    rounds[r] = 1; if (r > last) last = r; n[r, kind]++; sum[r, kind] += s; if (n[r, kind] <= 2) first[r, kind, n[r, kind]] = s }
  function report(name, k, v,   i, m, d) {
    if (k == 0) return
    m = 0; for (i = 1; i <= k; ++i) m += v[i]; m /= k
    d = 0; for (i = 1; i <= k; ++i) d += (v[i] - m) ^ 2
    if (k > 1) {
      printf "%s: mean %.4f over %d rounds, sample sd %.4f, standard error %.4f", name, m, k, sqrt(d / (k - 1)), sqrt(d / (k - 1) / k)
      # One-sided 95 % upper bound of the mean: Student t with k - 1 degrees of freedom (its 0.95
      # quantile from the usual table; past 30 degrees that of 30, which widens the bound).
      split("6.314 2.920 2.353 2.132 2.015 1.943 1.895 1.860 1.833 1.812 1.796 1.782 1.771 1.761 1.753 " \
            "1.746 1.740 1.734 1.729 1.725 1.721 1.717 1.714 1.711 1.708 1.706 1.703 1.701 1.699 1.697", tq, " ")
      t = tq[(k - 1 <= 30) ? k - 1 : 30]
      printf ", one-sided 95 %% upper bound %.4f (t %.3f)\n", m + t * sqrt(d / (k - 1) / k), t
    }
    else printf "%s: %.4f (one round)\n", name, m
  }
  END {
    kr = 0; ka = 0; kb = 0
    for (r = 1; r <= last; ++r) {
      if (!(r in rounds)) continue
      line = sprintf("round %d:", r)
      if (n[r, "ranks"] > 0 && n[r, "one"] > 0) {
        q = (sum[r, "ranks"] / n[r, "ranks"]) / (sum[r, "one"] / n[r, "one"]); ratio[++kr] = q
        line = line sprintf(" two ranks / one process %.4f", q) }
      if (n[r, "one"] >= 2) { q = first[r, "one", 2] / first[r, "one", 1]; aa[++ka] = q
        line = line sprintf("; one process, second / first %.4f", q) }
      if (n[r, "ranks"] >= 2) { q = first[r, "ranks", 2] / first[r, "ranks", 1]; bb[++kb] = q
        line = line sprintf("; two ranks, second / first %.4f", q) }
      print line
    }
    report("two ranks / one process", kr, ratio)
    report("one process, second / first (A/A)", ka, aa)
    report("two ranks, second / first (B/B)", kb, bb)
  }'
