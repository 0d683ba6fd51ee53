#!/usr/bin/env bash
# The arms of the robustness study (docs/journal/robustness.md), seed by seed: each arm's config
# experiments/configs/robust_j40_<arm>.toml with [codesign] seed = N, trained into
# OUT/j40_<arm>_s<N> (resumed when a checkpoint is there), then verified on d* without the PIDs
# (`codesign verify --no-baselines`; the PIDs on j40 are the same for every arm, so verify one
# run of them with the PIDs once). Runs that are done are skipped, so the script can be run
# again after a stop. Summarise with experiments/robust_summary.sh.
#   bash experiments/robust_arms.sh OUT "inflation nominal" "1 2 3" [BINARY]
set -euo pipefail
out=${1:?usage: robust_arms.sh OUT "ARMS" "SEEDS" [BINARY]}
arms=${2:?arms}
seeds=${3:?seeds}
bin=${4:-build/release/codesign}
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")
mkdir -p "$out"
cd "$out"
for arm in $arms; do
  for s in $seeds; do
    name=j40_${arm}_s$s
    printf 'extends = "%s/experiments/configs/robust_j40_%s.toml"\n\n[codesign]\nseed = %s\n' "$root" "$arm" "$s" > $name.toml
    if [ ! -f $name/result.toml ]; then
      resume=""; [ -f $name/checkpoint.bin ] && resume="--resume"
      /usr/bin/time -v "$bin" --config $name.toml -o $name --threads 2 --no-figures $resume >> $name.log 2>&1
    fi
    [ -f $name/verify/report.md ] || /usr/bin/time -v "$bin" verify --run $name --threads 2 --no-baselines >> $name/verify.log 2>&1
  done
done
