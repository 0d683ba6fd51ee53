#pragma once
// A whole co-design run in a run folder: Algorithm 1 with checkpoints and logs, then the
// evaluation of d* and the runner-up, then result.toml and policy.bin.
//
// Run folder (DIR):
//   config.toml        the resolved config: every key the run reads, with the value used
//                      (checkpoints carry its fingerprint; resuming checks it)
//   config.input.toml  the config file as given
//   episodes.csv       every episode of training (first = the one fed to Algorithm 2)
//   ppo.csv            one row per PPO update
//   distribution.csv   one row per distribution update: phase, β, entropy, top designs, best
//   q_disc.csv         the 110 probabilities per update
//   sampled.csv        the sampled designs per update with μ, σ (kPa) of their q_cont after it
//   checkpoint.bin     everything needed to resume (checkpoint.hpp), written atomically
//   policy.bin         the final policy (rl/policy_file.hpp)
//   result.toml        [best], [runner_up], [run]
//   eval/<which>.csv   per-episode results of the final evaluation; eval/<which>_trace.csv the
//                      per-step trace of its first episode
// Resuming (options.resume) continues from checkpoint.bin: logs are cut back to the lengths
// they had at the checkpoint, and the run ends with the same policy.bin and result.toml as an
// uninterrupted run (wall-clock fields aside).
//
// One writer per run folder: the run holds DIR/.lock (io/formats/run_lock.hpp) while it writes; a second
// run, --resume or --force on a folder whose lock is held stops with an InputError naming the
// holder, before anything is read or written. SIGTERM / SIGINT (with StopSignals installed,
// stop_signals.hpp) stop the run after the current iteration with a checkpoint; during the
// final evaluation they stop it before result.toml is written (the checkpoint holds the whole
// training, so --resume only evaluates again).
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/outer_loop.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"
#include "run/folder_lock.hpp"
#include "run/run_settings.hpp"

namespace codesign::io {
class RunLock;
}

namespace codesign::run {

struct RunOptions {
  std::string dir;
  bool resume = false;
  bool force = false;           // start afresh even if DIR holds an earlier run
  std::size_t threads = 0;      // rollout and evaluation threads (0: all cores)
  // MPI ranks stepping the rollouts (rollout_backend.hpp): 1 = this process alone; N > 1 = this is
  // rank 0 of N and ranks 1..N-1 are in serve_rollouts. Results do not depend on it.
  int ranks = 1;
  // Threads of the final evaluation (0: `threads`). Under mpirun the other ranks sleep through it,
  // so the main job gives rank 0 their threads on its machine too (main_job.cpp); results do not
  // depend on it.
  std::size_t evaluation_threads = 0;
  // The world ranks on rank 0's machine (cluster::ranks_on_this_machine; empty: rank 0 alone): in a
  // whole rollout rank 0 takes up the threads of those done with theirs (cluster/lent_threads.hpp).
  std::vector<int> machine_ranks;
  bool progress = true;         // progress line on stdout
  // LCM telemetry URL ("" = off): episodes, PPO updates and distribution updates as they
  // happen, decimated simulation steps of one training environment, and the simulation steps of
  // the final evaluation's first episodes (docs/telemetry.md).
  std::string telemetry_url;
  // With telemetry on: the simulation state at the end of every N-th decision of training
  // environment 0 is published on CODESIGN_TRAIN_STEP (0: none). Default 2: with 5 simulation
  // steps per decision, every 10th simulation step of one of the ψ environments.
  int telemetry_train_every = 2;
  // Stop (as if killed, after the iteration that reaches it) once t ≥ stop_after; for tests.
  std::int64_t stop_after = -1;
  // The lock of DIR, taken by the caller (lock_run_folder) when it writes more into DIR after the
  // run (frames, figures); null: run_codesign takes it itself for its own duration.
  const io::RunLock* lock = nullptr;
};

struct RunResult {
  bool completed = false;       // false: stopped by stop_after or by a signal
  int stop_signal = 0;          // SIGTERM or SIGINT if a signal stopped the run (checkpointed)
  double wall_s = 0.0;
  std::int64_t timesteps = 0;
  // Telemetry cost of this session (0 when off): messages published, and the wall time spent
  // filling, encoding and sending them, summed over threads.
  std::int64_t telemetry_messages = 0;
  double telemetry_s = 0.0;
};

RunResult run_codesign(const RunSettings& settings, const RunOptions& options);

}  // namespace codesign::run
