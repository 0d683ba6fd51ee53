#!/usr/bin/env bash
# Compares two run folders of the same config file by file, to show that a change (or a kill -9
# and --resume) left a run's results as they were:
#   bash scripts/compare_runs.sh RUN_A RUN_B
# One line per file of RUN_A: "same" (byte for byte); "same*" with what alone differs, for the
# wall-clock fields (result.toml's wall_s, ppo.csv's timing columns collect_s..steps_per_s) and
# the run folder's own path (figures/data, figures/gnuplot_commands.txt); for checkpoints the
# number of differing bytes (their wall_s, the recorded length of ppo.csv and the checksum may
# differ); "DIFFERENT" otherwise. Ends with a count; exits 1 if any file is DIFFERENT or missing.
set -uo pipefail
a=${1:?usage: compare_runs.sh RUN_A RUN_B}; b=${2:?usage: compare_runs.sh RUN_A RUN_B}
abs_a=$(realpath "$a"); abs_b=$(realpath "$b")
# A run started from another folder names itself by a shorter path, down to its folder's name.
base_a=$(basename "$abs_a"); base_b=$(basename "$abs_b")
same=0; alike=0; bad=0
while IFS= read -r f; do
  if [ ! -f "$b/$f" ]; then echo "MISSING   $f"; bad=$((bad + 1)); continue; fi
  if cmp -s "$a/$f" "$b/$f"; then same=$((same + 1)); echo "same      $f"; continue; fi
  case "$f" in
    result.toml)
      if diff <(grep -v '^wall_s' "$a/$f") <(grep -v '^wall_s' "$b/$f") > /dev/null; then
        alike=$((alike + 1)); echo "same*     $f (wall_s aside)"; else bad=$((bad + 1)); echo "DIFFERENT $f"; fi ;;
    ppo.csv)
      if diff <(cut -d, -f1-14 "$a/$f") <(cut -d, -f1-14 "$b/$f") > /dev/null; then
        alike=$((alike + 1)); echo "same*     $f (timing columns aside)"; else bad=$((bad + 1)); echo "DIFFERENT $f"; fi ;;
    figures/*)
      if diff <(sed "s|$abs_a|RUN|g; s|$a|RUN|g; s|$base_a|RUN|g" "$a/$f") \
              <(sed "s|$abs_b|RUN|g; s|$b|RUN|g; s|$base_b|RUN|g" "$b/$f") > /dev/null; then
        alike=$((alike + 1)); echo "same*     $f (the run folder's path aside)"; else bad=$((bad + 1)); echo "DIFFERENT $f"; fi ;;
    checkpoint*.bin)
      alike=$((alike + 1))
      echo "same*     $f ($(stat -c %s "$a/$f") and $(stat -c %s "$b/$f") bytes; $(cmp -l "$a/$f" "$b/$f" | wc -l) bytes differ)" ;;
    *) bad=$((bad + 1)); echo "DIFFERENT $f" ;;
  esac
done < <(cd "$a" && find . -type f ! -name '.lock' | sed 's|^\./||' | sort)
echo "compare_runs: $same files identical, $alike alike but for wall-clock fields or paths, $bad different or missing"
[ "$bad" -eq 0 ]
