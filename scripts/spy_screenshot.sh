#!/usr/bin/env bash
# Checks that lcm-spy decodes every channel of a telemetry log, headless, and takes screenshots.
#
#   bash scripts/spy_screenshot.sh RUN.lcm OUTDIR [CHANNEL_ROW]
#
# Starts a virtual X server (Xvfb, display :97, no TCP), lcm-spy on the log (file://RUN.lcm,
# replayed at 10x; no network), captures the channel table (OUTDIR/lcm_spy_channels.png), double-
# clicks a channel row (default 5: CODESIGN_TRAIN_STEP in the alphabetical table) and captures its
# decoded fields (OUTDIR/lcm_spy_fields.png), then stops what it started. Dev-only tools:
# xvfb and xdotool (apt-get install xvfb xdotool), plus what scripts/spy.sh needs.
# Make a log with a run: codesign --config X -o DIR --telemetry 'file:///abs/RUN.lcm?mode=w'.
set -euo pipefail
cd "$(dirname "$0")/.."
LOG="$(realpath "$1")"
OUT="$2"
ROW="${3:-5}"
DISPLAY_NUM=:97
mkdir -p "$OUT"
TMP="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$TMP"
}
trap cleanup EXIT

javac -d "$TMP" scripts/ScreenShot.java
Xvfb "$DISPLAY_NUM" -screen 0 1400x900x24 -nolisten tcp >"$TMP/xvfb.log" 2>&1 &
pids+=($!)
sleep 2
DISPLAY="$DISPLAY_NUM" bash scripts/spy.sh "file://$LOG?speed=10" >"$TMP/spy.log" 2>&1 &
pids+=($!)
sleep 25   # lcm-spy starts and replays the log
DISPLAY="$DISPLAY_NUM" java -cp "$TMP" ScreenShot "$OUT/lcm_spy_channels.png" 0 0 800 120
# Rows are 16 px high below a 20 px header: double-click the middle of row ROW.
DISPLAY="$DISPLAY_NUM" xdotool mousemove 70 $((20 + 16 * (ROW - 1) + 8)) click --repeat 2 --delay 100 1
sleep 3
DISPLAY="$DISPLAY_NUM" java -cp "$TMP" ScreenShot "$OUT/lcm_spy_fields.png" 0 0 650 345
grep -E "Found [0-9]+ LCM types" "$TMP/spy.log" || true
echo "spy_screenshot: $OUT/lcm_spy_channels.png $OUT/lcm_spy_fields.png"
