#!/usr/bin/env bash
# Runs one arm of a seed study: configs/ARM.toml (or experiments/configs/ARM.toml if configs/ has
# none) with [codesign] seed = SEED, into RUNS/ARM-sSEED (the folder name scripts/seed_table.sh and
# learning_table.sh read), its log in RUNS/ARM-sSEED.log. The per-seed config is written to
# RUNS/cfg/ARM-sSEED.toml, extending the committed config, so the run folder's config.toml is that
# config with only the seed changed.
#   bash scripts/seed_run.sh ARM SEED [RUNS_DIR] [extra codesign flags, e.g. --threads 1 or --resume]
# A run folder that exists is resumed when --resume is passed, refused otherwise (as codesign does).
set -euo pipefail
arm=${1:?usage: seed_run.sh ARM SEED [RUNS_DIR] [codesign flags]}
seed=${2:?seed}
runs=${3:-runs}
shift $(( $# < 3 ? $# : 3 ))
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${CODESIGN_BIN:-$here/build/release/codesign}"
base="$here/configs/$arm.toml"
[ -f "$base" ] || base="$here/experiments/configs/$arm.toml"
[ -f "$base" ] || { echo "seed_run: no config $arm.toml in $here/configs/ or $here/experiments/configs/" >&2; exit 2; }
mkdir -p "$runs/cfg"
cfg="$runs/cfg/$arm-s$seed.toml"
printf 'extends = "%s"\n\n[codesign]\nseed = %s\n' "$base" "$seed" > "$cfg"
"$bin" --config "$cfg" -o "$runs/$arm-s$seed" "$@" >> "$runs/$arm-s$seed.log" 2>&1
