#!/usr/bin/env bash
# The robustness study's figures (docs/journal/robustness.md): for each arm, d*'s return under
# each verify condition, mean ± std across seeds (each seed: the mean over its test phases) and
# the lowest seed; then the issue's targets for one arm: modulus ±20 % mean >= 40 with no seed
# below 37, nominal >= 45, plate x1.5 and the refined mesh >= 42.
#   [VERIFY_DIR=verify_validation] bash experiments/robust_summary.sh OUT "tared nominal inflation" "1 2 3" [TARGET_ARM]
# OUT holds j40_<arm>_s<seed>/$VERIFY_DIR/conditions.csv (experiments/robust_arms.sh; VERIFY_DIR
# defaults to verify, the test phases; verify_validation holds `verify --phase-set validation`,
# the phases to compare arms on). A missing run or verify is printed as "—".
set -euo pipefail
out=${1:?usage: robust_summary.sh OUT "ARMS" "SEEDS" [TARGET_ARM]}
arms=${2:?arms}
seeds=${3:?seeds}
target=${4:-}
vdir=${VERIFY_DIR:-verify}
conditions="nominal modulus_-20% modulus_+20% refined_mesh plate_x0.5 plate_x1.5 gain_-10% gain_+10% strain_noise"

# d*'s mean return under a condition in a verify's conditions.csv (empty if absent). Files of the
# first verify had no subject column: every row was d*.
dstar_mean() {
  awk -F, -v cond="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    $c["condition"] == cond && (!("subject" in c) || $c["subject"] == "d*") { print $c["mean_return"]; exit }' "$1" 2>/dev/null || true
}

printf '%-10s' arm
for c in $conditions; do printf ' | %-17s' "$c"; done
printf '\n'
for arm in $arms; do
  printf '%-10s' "$arm"
  for c in $conditions; do
    vals=""
    for s in $seeds; do
      v=$(dstar_mean "$out/j40_${arm}_s$s/$vdir/conditions.csv" "$c")
      vals="$vals ${v:-nan}"
    done
    echo "$vals" | awk '{ n = 0; miss = 0; for (i = 1; i <= NF; ++i) { if ($i == "nan") { miss = 1; continue } x[++n] = $i }
      if (n == 0) { printf " | —%-16s", ""; exit }
      m = 0; for (i = 1; i <= n; ++i) m += x[i]; m /= n
      v = 0; for (i = 1; i <= n; ++i) v += (x[i] - m) ^ 2; sd = n > 1 ? sqrt(v / (n - 1)) : 0
      lo = x[1]; for (i = 2; i <= n; ++i) if (x[i] < lo) lo = x[i]
      printf " | %5.2f±%4.2f (%5.2f)%s", m, sd, lo, (miss ? "*" : "") }'
  done
  printf '\n'
done
echo "each cell: mean ± std across seeds (sample std), the lowest seed in parentheses; * = a seed missing"

[ -n "$target" ] || exit 0
verdict() { if awk -v a="$2" -v b="$3" 'BEGIN { exit !(a + 0 >= b + 0) }'; then echo "$1: met"; else echo "$1: NOT met"; fi; }
stat() {  # mean and min across seeds of a condition for the target arm
  for s in $seeds; do dstar_mean "$out/j40_${target}_s$s/$vdir/conditions.csv" "$1"; done |
    awk '{ x[++n] = $1; m += $1; if (n == 1 || $1 < lo) lo = $1 } END { if (n) printf "%.4f %.4f %d", m / n, lo, n; else print "nan nan 0" }'
}
read -r m_lo min_lo n_lo <<< "$(stat modulus_-20%)"
read -r m_hi min_hi n_hi <<< "$(stat modulus_+20%)"
read -r m_nom _ _ <<< "$(stat nominal)"
read -r m_plate _ _ <<< "$(stat plate_x1.5)"
read -r m_mesh _ _ <<< "$(stat refined_mesh)"
echo "targets for $target over $n_lo seeds:"
verdict "  modulus -20 % mean $m_lo >= 40" "$m_lo" 40
verdict "  modulus +20 % mean $m_hi >= 40" "$m_hi" 40
verdict "  no seed below 37 at either modulus (lowest $min_lo, $min_hi)" "$(awk -v a="$min_lo" -v b="$min_hi" 'BEGIN { print (a < b ? a : b) }')" 37
verdict "  nominal mean $m_nom >= 45" "$m_nom" 45
verdict "  plate x1.5 mean $m_plate >= 42" "$m_plate" 42
verdict "  refined mesh mean $m_mesh >= 42" "$m_mesh" 42
