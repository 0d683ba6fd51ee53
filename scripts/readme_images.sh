#!/usr/bin/env bash
# Makes the two pictures of README.md from a finished quick run: a rendered frame of d*'s first
# evaluation episode (mid-episode, in contact) and Fig. 2a (the training return of every sampled
# design).
#   bash scripts/readme_images.sh [RUN]     RUN defaults to runs/quick, run first if missing
# Writes docs/img/readme_frame.png and docs/img/readme_fig2a.png.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
run=${1:-runs/quick}
bin="${CODESIGN_BIN:-$here/build/release/codesign}"
if [ ! -f "$run/result.toml" ]; then
  [ -e "$run" ] && { echo "readme_images: $run exists but holds no finished run (no result.toml)" >&2; exit 2; }
  "$bin" --config "$here/configs/quick.toml" -o "$run"
fi
frame="$run/frames/best/frame_0025.png"   # decision 25 of 50: half-way through the episode
fig="$run/figures/fig2a.png"
for f in "$frame" "$fig"; do
  [ -f "$f" ] || { echo "readme_images: $f: missing (a run without frames or figures?)" >&2; exit 2; }
done
cp "$frame" "$here/docs/img/readme_frame.png"
cp "$fig" "$here/docs/img/readme_fig2a.png"
echo "readme_images: docs/img/readme_frame.png, docs/img/readme_fig2a.png from $run"
