# Sourced by seed_table.sh and training_seeds.sh: the Markdown header of a table with one column
# per seed, and the statistics across seeds of a list of per-seed figures.

# seed_header "SEED ..." "COLUMN ...": "| arm | seed 1 | ... |" and its rule, then the extra
# columns, each given as one word with underscores for spaces.
seed_header() {
  local header="| arm |" rule="|---|" s c
  for s in $1; do header="$header seed $s |"; rule="$rule---|"; done
  for c in $2; do header="$header ${c//_/ } |"; rule="$rule---|"; done
  echo "$header"
  echo "$rule"
}

# across_seeds "V ...": "mean ± std (n seeds)" (sample std, n − 1), "mean (1 seed)", or "—".
across_seeds() {
  echo "$1" | awk '{ n = NF; if (n == 0) { print "—"; exit }
    for (i = 1; i <= n; ++i) s += $i; m = s / n; for (i = 1; i <= n; ++i) v += ($i - m) ^ 2
    if (n > 1) printf "%.2f ± %.2f (%d seeds)", m, sqrt(v / (n - 1)), n; else printf "%.2f (1 seed)", m }'
}

# interval_of_mean "V ...": the 95 % confidence interval of the mean, "mean ± h (low to high)"
# with h = t · std / √n, Student's t of n − 1 degrees of freedom; "—" outside 2 to 11 figures.
interval_of_mean() {
  echo "$1" | awk '{ n = NF; if (n < 2 || n > 11) { print "—"; exit }
    split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228", t, " ")
    for (i = 1; i <= n; ++i) s += $i; m = s / n; for (i = 1; i <= n; ++i) v += ($i - m) ^ 2
    h = t[n - 1] * sqrt(v / (n - 1)) / sqrt(n); printf "%.2f ± %.2f (%.2f to %.2f)", m, h, m - h, m + h }'
}
