#pragma once
// The config of `codesign train-gym` (PPO on a classic-control task), and the [ppo] table reader
// shared with the co-design run.
//
//   [env]    name = "pendulum", n_envs, n_threads, seed, max_episode_steps
//   [ppo]    every rl::PpoConfig field (see read_ppo_config)
//   [train]  total_timesteps, eval_episodes, stats_window, log_every_iterations,
//            checkpoint_every_iterations, save_policy, output_dir
// Every key is optional (defaults below), range-checked, and unknown keys or tables are errors.
#include <cstdint>
#include <string>
#include <string_view>

#include "base/enum_names.hpp"
#include "io/config/toml_reader.hpp"
#include "rl/ppo.hpp"
#include "rl/trainer.hpp"

namespace codesign::io {

struct GymTrainConfig {
  std::string env_name = "pendulum";
  int max_episode_steps = 200;  // the Gymnasium time limit of Pendulum-v1
  // PPO, n_envs (default 4), n_threads, seed, total_timesteps, stats_window.
  rl::TrainerConfig trainer;
  int eval_episodes = 100;  // the reader allows [1, 100000], within rl::kEvalSeedStride = 2^20
  int log_every_iterations = 1;
  int checkpoint_every_iterations = 0;  // 0: only the final policy is saved
  bool save_policy = true;
  std::string output_dir = "runs/train-gym";
};

// Reads the keys of a [ppo] table over `defaults`:
//   learning_rate, n_steps, batch_size, n_epochs, gamma, gae_lambda, clip_range, ent_coef,
//   ent_decay_start, ent_decay_end, vf_coef, max_grad_norm, target_kl, normalize_advantage,
//   actor_hidden, critic_hidden, log_std_init, adam_eps, matmul_precision.
// matmul_precision is "auto" (the default, whatever `defaults` says: bf16 where the CPU has
// AVX-512 BF16, else float32), "float32" or "bf16" (an error where unavailable).
// Absent optional fields (target_kl, ent_decay_*) keep the default's value. Cross-field rules
// (ent_decay_start < ent_decay_end, both or neither) are checked here too. Does NOT call
// table.finish(): a caller may read extra keys from the same table, then must call finish().
enum class GymEnv { Pendulum };
inline constexpr EnumNames<GymEnv, 1> kGymEnvNames{{{GymEnv::Pendulum, "pendulum"}}};

// [env] of `codesign train-gym`.
template <class V>
void describe_env_table(V& v, GymTrainConfig& g) {
  GymEnv env = value_of(kGymEnvNames, g.env_name).value_or(GymEnv::Pendulum);
  v.choice({"name", "", "the task (Gymnasium's Pendulum-v1)"}, env, kGymEnvNames);
  g.env_name = name_of(kGymEnvNames, env);
  v.integer({"n_envs", "", "environments stepped per rollout"}, g.trainer.n_envs, {1, 4096});
  v.integer({"n_threads", "", "threads stepping the environments (0: all cores)"}, g.trainer.n_threads, {0, 1024});
  // Seeds up to 2^53 so every seed prints and parses exactly as a double too.
  v.integer({"seed", "", "seed of every random stream"}, g.trainer.seed, {0, 9'007'199'254'740'992});
  v.integer({"max_episode_steps", "", "time limit of an episode (Pendulum-v1: 200)"}, g.max_episode_steps,
            {1, 100'000'000});
}

// [train] of `codesign train-gym`.
template <class V>
void describe_train_table(V& v, GymTrainConfig& g) {
  v.integer({"total_timesteps", "", "environment steps over all environments"}, g.trainer.total_timesteps,
            {1, 1'000'000'000'000});
  v.integer({"eval_episodes", "", "episodes of the final evaluation"}, g.eval_episodes, {1, 100'000});
  v.integer({"stats_window", "", "episodes in the running mean return (SB3's stats_window_size)"},
            g.trainer.stats_window, {1, 1'000'000});
  v.integer({"log_every_iterations", "", "a progress line every N iterations"}, g.log_every_iterations,
            {1, 1'000'000});
  v.integer({"checkpoint_every_iterations", "", "a policy file every N iterations (0: only the final one)"},
            g.checkpoint_every_iterations, {0, 1'000'000});
  v.boolean({"save_policy", "", "write the final policy file"}, g.save_policy);
  v.text({"output_dir", "", "folder of the run's files"}, g.output_dir);
  v.require(!g.output_dir.empty(), "output_dir", [] { return std::string("must not be empty"); });
}

rl::PpoConfig read_ppo_config(TableReader& table, const rl::PpoConfig& defaults = {});

// What "auto" resolves to on this build/CPU.
rl::MatmulPrecision default_matmul_precision();
// "float32" -> Float32, "bf16" -> BFloat16, "auto" -> default_matmul_precision(). Callers check
// the name is one of these and that bf16 is available (their error messages differ).
rl::MatmulPrecision matmul_precision_from_name(std::string_view name);

// Reads a whole train-gym config (and finishes every table).
GymTrainConfig read_gym_config(TableReader& root);
GymTrainConfig load_gym_config(const std::string& path);

}  // namespace codesign::io
