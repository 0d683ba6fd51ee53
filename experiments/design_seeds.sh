#!/usr/bin/env bash
# Issue 18 §3: does the design answer survive seeds? From the run folders <arm>-s<seed> under a
# directory, each finished and evaluated at T2 (`codesign evaluate --run DIR --at t2`), prints:
#   * per seed: d*, p*, its test return (result.toml), H(q_disc) at T2 and its largest
#     probability (the first distribution.csv row with t >= T2), and the rank of d* in its own
#     T2 evaluation of all designs (evaluate/t2/ranking.csv);
#   * the rank of each seed's d* in every other seed's T2 evaluation, and, where it exists, in the
#     other seed's T2 evaluation at this seed's pressures (`codesign evaluate --run OTHER --at t2
#     --pressures-of THIS`: every design at the pressures THIS run's T2 state gives it, so d* runs
#     at its own pressure; evaluate/t2_pressures_of_<THIS>/ranking.csv);
#   * the acceptance of issue 18 §3: H(q_disc) at T2 <= ln 3, each d* in the top 3 of its own T2
#     evaluation, each d* in the top 5 of the others'.
#   bash experiments/design_seeds.sh runs paper_best_gru "1 2 3"
# A seed whose run or evaluation is missing is printed as "—" and fails the acceptance.
set -euo pipefail
root=${1:?usage: design_seeds.sh RUNS_DIR ARM "SEED ..."}
arm=${2:?arm}
seeds=${3:?seeds}

get() { awk -v sec="[$2]" -v key="$3" '
  /^\[/ { in_sec = ($0 == sec) }
  in_sec && $1 == key { sub(/^[^=]*= */, ""); sub(/ *#.*$/, ""); print; exit }' "$1"; }
# the T2 of a run folder (its resolved config)
t2_of() { get "$1/config.toml" codesign exploitation_start; }
# "entropy largest_q" at the first distribution update with t >= T2
entropy_at_t2() {
  awk -F, -v t2="$2" 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    $c["t"] + 0 >= t2 { printf "%s %s", $c["entropy"], $c["top1_q"]; exit }' "$1/distribution.csv"
}
# rank of design J in a ranking.csv (empty if absent)
rank_in() { awk -F, -v j="$2" 'NR > 1 && $2 == j { print $1; exit }' "$1"; }
count_in() { awk 'END { print NR - 1 }' "$1"; }

ln3=$(awk 'BEGIN { printf "%.17g", log(3) }')
ok=1
declare -A dstar
echo "| seed | d* | p* (kPa) | test return of d* | H(q_disc) at T2 (largest q) | rank of d* in its own T2 evaluation |"
echo "|---|---|---|---|---|---|"
for s in $seeds; do
  d="$root/$arm-s$s"
  if [ ! -f "$d/result.toml" ]; then
    echo "| $s | — | — | — | — | — |"; ok=0; continue
  fi
  j=$(get "$d/result.toml" best design); dstar[$s]=$j
  label="j$j {$(get "$d/result.toml" best n), $(get "$d/result.toml" best l_mm) mm, $(get "$d/result.toml" best w_mm) mm}"
  p=$(get "$d/result.toml" best pressures_kPa | awk -F'[][, ]+' '{ printf "%.2f, %.2f", $2, $3 }')
  r=$(awk -v m="$(get "$d/result.toml" best test_return)" -v sd="$(get "$d/result.toml" best test_return_std)" \
        'BEGIN { printf "%.2f ± %.2f", m, sd }')
  read -r h q <<< "$(entropy_at_t2 "$d" "$(t2_of "$d")")"
  awk -v h="$h" -v l="$ln3" 'BEGIN { exit !(h <= l + 1e-9) }' || ok=0  # the schedule meets its target to ~1e-12
  rk="—"
  if [ -f "$d/evaluate/t2/ranking.csv" ]; then
    rk=$(rank_in "$d/evaluate/t2/ranking.csv" "$j")
    n=$(count_in "$d/evaluate/t2/ranking.csv")
    [ -n "$rk" ] && [ "$rk" -le 3 ] || ok=0
    rk="${rk:-—} of $n"
  else
    ok=0
  fi
  echo "| $s | $label | $p | $r | $(awk -v h="$h" -v q="$q" 'BEGIN { printf "%.3f (%.1f %%)", h, 100 * q }') | $rk |"
done
echo
echo "| d* of seed | rank in the T2 evaluation of seed ... (at that seed's pressures) | ... at this seed's pressures (--pressures-of) |"
echo "|---|---|---|"
fair=1
for s in $seeds; do
  [ -n "${dstar[$s]:-}" ] || continue
  row=""; row2=""
  for o in $seeds; do
    [ "$o" = "$s" ] && continue
    f="$root/$arm-s$o/evaluate/t2/ranking.csv"
    if [ -f "$f" ]; then
      rk=$(rank_in "$f" "${dstar[$s]}"); row="$row seed $o: ${rk:-—};"
      [ -n "$rk" ] && [ "$rk" -le 5 ] || ok=0
    else
      row="$row seed $o: —;"; ok=0
    fi
    f="$root/$arm-s$o/evaluate/t2_pressures_of_$arm-s$s/ranking.csv"
    if [ -f "$f" ]; then
      rk=$(rank_in "$f" "${dstar[$s]}"); row2="$row2 seed $o: ${rk:-—} of $(count_in "$f");"
      [ -n "$rk" ] && [ "$rk" -le 5 ] || fair=0
    else
      row2="$row2 seed $o: —;"; fair=0
    fi
  done
  echo "| $s (j${dstar[$s]}) |${row%;} |${row2%;} |"
done
echo
nseeds=$(echo $seeds | wc -w)
if [ "$nseeds" -lt 3 ]; then
  echo "issue 18 §3 acceptance: not decided: $nseeds seed(s) given, the claim needs >= 3"
elif [ "$ok" = 1 ]; then
  echo "issue 18 §3 acceptance: met (H at T2 <= ln 3 = $(awk -v l="$ln3" 'BEGIN { printf "%.4f", l }'); each d* top 3 of its own T2 evaluation, top 5 of the others')"
else
  echo "issue 18 §3 acceptance: NOT met (or a seed's run or T2 evaluation is missing)"
fi
if [ "$nseeds" -ge 3 ]; then
  if [ "$fair" = 1 ]; then
    echo "cross-seed check at each d*'s own pressures (--pressures-of): each d* in the top 5 of every other seed's policy"
  else
    echo "cross-seed check at each d*'s own pressures (--pressures-of): NOT met (or an evaluation is missing)"
  fi
fi
