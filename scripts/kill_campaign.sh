#!/usr/bin/env bash
# kill -9 campaign (docs/reliability.md): a small co-design run is killed at KILLS (default 10)
# random moments and resumed with --resume each time; the end must equal an uninterrupted run:
# policy.bin, result.toml (but its wall_s line), episodes.csv, distribution.csv, q_disc.csv,
# sampled.csv and eval/*.csv byte for byte. ppo.csv is compared without its timing columns.
#
#   bash scripts/kill_campaign.sh [KILLS] [SEED]
#
# Kill points are drawn at random over the run's progress, not its wall time (which depends on
# the machine's load): KILLS-1 distinct random checkpoints (iterations) in increasing order, and
# the final evaluation. Every third round kills inside the write of its checkpoint for certain:
# the run gets the LD_PRELOAD shim scripts/kill_window_shim.c, which lets the checkpoint writes
# before it through, then stops the process halfway through writing checkpoint.bin.tmp (or,
# every other time, with the .tmp complete just before its rename) and creates a marker file;
# the script waits for the marker, checks the .tmp is there, and kills. The other rounds wait
# until their checkpoint has appeared and kill a random 0 to 1/24 of the uninterrupted run's time
# later (inside the next iteration, or in the evaluation). Fails unless all KILLS rounds really killed a running process. Uses build/release/codesign (built if missing;
# CODESIGN=path overrides). Exits non-zero on any difference.
set -euo pipefail
cd "$(dirname "$0")/.."
kills="${1:-10}"
RANDOM="${2:-20261126}"
bin="${CODESIGN:-build/release/codesign}"
if [ ! -x "$bin" ]; then
  cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build/release --target codesign
fi
work="${WORK:-build/kill_campaign}"
rm -rf "$work"
mkdir -p "$work"
shim="$work/kill_window_shim.so"
cc -O2 -shared -fPIC -o "$shim" scripts/kill_window_shim.c -ldl

cat >"$work/run.toml" <<'TOML'
# 24 iterations of 4 designs x 5 decisions through all three phases of Algorithm 2, a
# checkpoint every iteration, small networks.
[scene]
settle_steps = 5
[task]
episode_steps = 25
action_hold_steps = 5
observation = "proprioceptive"
[ppo]
n_steps = 5
batch_size = 8
n_epochs = 2
actor_hidden = [16, 16]
critic_hidden = [16, 16]
matmul_precision = "float32"
[codesign]
total_timesteps = 480
designs_per_update = 4
exploration_end = 160
exploitation_start = 320
beta_end = 2.0
eval_episodes = 3
checkpoint_every = 20
seed = 11
TOML
args=(--config "$work/run.toml" --quiet --threads 2)

now_ms() { date +%s%3N; }
t0=$(now_ms)
"$bin" "${args[@]}" -o "$work/whole" >"$work/whole.log"
whole_ms=$(($(now_ms) - t0))
echo "kill_campaign: uninterrupted run: ${whole_ms} ms"

run="$work/killed"
marker="$work/window_open"
per_ckpt=20   # [codesign] checkpoint_every: one checkpoint per iteration
total=480
# The kill points: KILLS distinct random checkpoints m (1..23, t = 20 m) in increasing order;
# the last round instead kills during the final evaluation (m = 24). Round i kills either inside
# the write of checkpoint m (every third round) or at a random moment of the iteration after
# checkpoint m (0 to one iteration's time after it appeared).
mapfile -t points < <(for m in $(seq 1 23); do echo "$RANDOM $m"; done | sort -n | head -n $((kills - 1)) |
  awk '{print $2}' | sort -n)
points+=(24)
ckpt_t() { [ -e "$run/checkpoint.bin" ] && od -An -t d8 -j 28 -N 8 "$run/checkpoint.bin" | tr -d ' ' || echo 0; }
started=0
killed=0
for ((i = 1; i <= kills; i++)); do
  m=${points[i - 1]}
  extra=()
  ((started)) && extra=(--resume)
  rm -f "$marker"
  t_now=$(ckpt_t)
  if ((i % 3 == 0 && m < 24)); then
    at=write
    ((i % 6 == 0)) && at=rename
    skip=$((m - 1 - t_now / per_ckpt))   # checkpoint writes to let through before the held one
    KILL_WINDOW_AT=$at KILL_WINDOW_SKIP=$skip KILL_WINDOW_MARKER="$marker" LD_PRELOAD="$PWD/$shim" \
      "$bin" "${args[@]}" -o "$run" "${extra[@]}" >>"$work/killed.log" 2>&1 &
    pid=$!
    while [ ! -e "$marker" ] && kill -0 "$pid" 2>/dev/null; do sleep 0.05; done
    if [ -e "$marker" ]; then
      tmp_bytes=$(stat -c %s "$run/checkpoint.bin.tmp")
      what="inside the write of checkpoint $m (t = $((m * per_ckpt)); $at): checkpoint.bin.tmp $tmp_bytes bytes, checkpoint.bin $(stat -c %s "$run/checkpoint.bin") bytes at t = $(ckpt_t)"
    else
      what="before a checkpoint write was held"
    fi
  else
    ms=$((RANDOM % (whole_ms / 24 + 1)))   # within about one iteration
    "$bin" "${args[@]}" -o "$run" "${extra[@]}" >>"$work/killed.log" 2>&1 &
    pid=$!
    while (($(ckpt_t) < m * per_ckpt)) && kill -0 "$pid" 2>/dev/null; do sleep 0.05; done
    sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"
    if ((m < 24)); then what="$ms ms after checkpoint $m (t = $((m * per_ckpt)))"; else
      what="$ms ms after the last checkpoint (t = $total: final evaluation)"; fi
  fi
  if kill -0 "$pid" 2>/dev/null; then
    kill -9 "$pid"
    wait "$pid" 2>/dev/null || true
    state="killed"
    killed=$((killed + 1))
  else
    wait "$pid" && state="had finished" || state="had exited with status $?"
  fi
  [ -e "$run/config.toml" ] && started=1
  echo "kill_campaign: round $i: $state $what; checkpoint.bin now at t = $(ckpt_t)"
done

extra=()
((started)) && extra=(--resume)
"$bin" "${args[@]}" -o "$run" "${extra[@]}" >>"$work/killed.log" 2>&1
echo "kill_campaign: final --resume completed"

status=0
same() {
  if cmp -s "$1" "$2"; then echo "kill_campaign: identical: ${1#$work/whole/}"; else
    echo "kill_campaign: DIFFERENT: ${1#$work/whole/}"; status=1; fi
}
for f in policy.bin episodes.csv distribution.csv q_disc.csv sampled.csv eval/best.csv eval/runner_up.csv \
         eval/best_trace.csv eval/runner_up_trace.csv; do
  same "$work/whole/$f" "$run/$f"
done
grep -v '^wall_s' "$work/whole/result.toml" >"$work/whole_result.toml"
grep -v '^wall_s' "$run/result.toml" >"$work/killed_result.toml"
same "$work/whole_result.toml" "$work/killed_result.toml"
# ppo.csv without collect_s, update_s, policy_s, steps_per_s (columns 15-18: timings)
cut -d, -f1-14 "$work/whole/ppo.csv" >"$work/whole_ppo.csv"
cut -d, -f1-14 "$run/ppo.csv" >"$work/killed_ppo.csv"
same "$work/whole_ppo.csv" "$work/killed_ppo.csv"
leftover=$(ls "$run" | grep -c '\.tmp$' || true)
echo "kill_campaign: .tmp files left in the run folder: $leftover"
echo "kill_campaign: $killed of $kills rounds killed a running process"
((killed == kills)) || status=1
((status == 0)) && echo "kill_campaign: PASS ($killed kills)" || echo "kill_campaign: FAIL"
exit $status
