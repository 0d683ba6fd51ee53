#pragma once
// `codesign train-gym` (docs/pendulum.md): trains PPO on a classic-control task (Pendulum-v1),
// printing a progress line every log_every_iterations rollouts, then evaluates the deterministic policy (mean action) on
// eval_episodes episodes whose seeds are disjoint from every training environment's and from
// the evaluation seeds of every other training seed (rl::eval_seed_first, src/rl/trainer.hpp):
// episode k of training seed s is reset with 2^63 + s * 2^20 + k.
//
// Output directory (--out, else [train] output_dir):
//   config.toml        copy of the config file given
//   metrics.csv        one row per PPO iteration (written and flushed as training goes)
//   eval.csv           one row per evaluation episode
//   policy.cdspol      the final policy (rl/policy_file.hpp), if save_policy
//   checkpoints/       policy_<timesteps>.cdspol every checkpoint_every_iterations, if > 0
//   summary.txt        key = value lines: seed, timesteps, eval mean/std, wall time
// An earlier run's results are never overwritten silently: if the directory already holds any
// of these files the command refuses (exit 2) unless --force is given.
#include <cstdint>
#include <optional>
#include <string>

namespace codesign::run {

struct GymRunOptions {
  std::optional<std::int64_t> seed;  // overrides [env] seed; must be >= 0
  std::string out;                   // overrides [train] output_dir
  bool force = false;                // overwrite an earlier run's results in the directory
};

// Reads the gym config at `config_path` ([env], [ppo], [train]), trains, evaluates and writes the
// output directory. Bad input (config, seed, a directory holding earlier results) is an
// InputError before any training.
void train_gym(const std::string& config_path, const GymRunOptions& options);

}  // namespace codesign::run
