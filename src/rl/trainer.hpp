#pragma once
// The PPO training loop (SB3's OnPolicyAlgorithm.learn / collect_rollouts + PPO.train), on top of
// the learner (actor_critic, rollout_buffer, ppo) and the environments (env, vec_env).
//
// One iteration = collect_rollouts() + update():
//   collect: collect_rollout() (rollout.hpp, the loop the co-design uses too) with the
//            actor-critic as MlpPolicy, or with ppo.policy = "gru" the recurrent actor-critic as
//            GruPolicy (gru_policy.hpp), whose hidden states, like the environments, continue
//            across rollouts; the environments continue across rollouts.
//   update:  ppo_update (PPO.train), or recurrent_ppo_update from the states the rollout began
//            with; entropy coefficient from the timesteps collected so far.
// Iterations repeat while num_timesteps < total_timesteps, so the total is rounded up to whole
// rollouts (SB3 does the same): 100k steps at 4 x 1024 per rollout is 25 rollouts, 102400 steps.
//
// Episode statistics follow SB3's Monitor: the return is the sum of the environment's rewards
// (before bootstrapping), kept for the last `stats_window` episodes.
//
// Random streams (all from TrainerConfig::seed, none shared with the environments):
//   Rng(seed).split() x3 -> model init, action sampling, minibatch shuffling.
//   Environment i is seeded with seed + i (VecEnv); evaluation seeds: eval_seed_first() below.
// Results depend only on the seed, not on n_threads.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "rl/actor_critic.hpp"
#include "rl/adam.hpp"
#include "rl/env.hpp"
#include "rl/gru_policy.hpp"
#include "rl/policy_file.hpp"
#include "rl/ppo.hpp"
#include "rl/recurrent_actor_critic.hpp"
#include "rl/rng.hpp"
#include "rl/rollout.hpp"
#include "rl/rollout_buffer.hpp"
#include "rl/vec_env.hpp"

namespace codesign::rl {

struct TrainerConfig {
  PpoConfig ppo;
  int n_envs = 4;
  std::size_t n_threads = 1;  // threads stepping the environments (0 = all cores)
  std::uint64_t seed = 0;
  std::int64_t total_timesteps = 100'000;
  std::size_t stats_window = 100;  // episodes in the running mean return (SB3 stats_window_size)
};

struct EpisodeRecord {
  double episode_return = 0.0;
  int length = 0;
  std::int64_t end_timestep = 0;  // num_timesteps when the episode ended
};

struct TrainProgress {
  int iteration = 0;
  std::int64_t timesteps = 0;
  std::int64_t total_timesteps = 0;
  double elapsed_s = 0.0;        // since the trainer was constructed
  double steps_per_s = 0.0;      // timesteps / elapsed_s (SB3's fps)
  double collect_s = 0.0;        // this iteration's rollout collection
  double update_s = 0.0;         // this iteration's PPO update
  std::int64_t episodes = 0;     // finished episodes so far
  std::optional<double> mean_return;  // over the last stats_window episodes (none yet: nullopt)
  std::optional<double> mean_length;
  PpoStats stats;
};

class Trainer {
 public:
  Trainer(const EnvFactory& factory, const TrainerConfig& config);

  // Collects one rollout into buffer() (advantages and returns computed).
  void collect_rollouts();
  // PPO update on the collected buffer.
  PpoStats update();
  // collect_rollouts() + update(); returns the progress after it.
  TrainProgress iterate();
  // Iterates until num_timesteps() >= total_timesteps, calling on_progress after each iteration.
  void learn(const std::function<void(const TrainProgress&)>& on_progress = {});
  bool finished() const { return num_timesteps_ >= config_.total_timesteps; }

  const TrainerConfig& config() const { return config_; }
  const EnvSpec& spec() const { return venv_.spec(); }
  // The feed-forward model (ppo.policy = "mlp"; with "gru" it is unused and untrained).
  ActorCritic& model() { return model_; }
  const ActorCritic& model() const { return model_; }
  // The recurrent model (ppo.policy = "gru"), else null.
  const RecurrentActorCritic* recurrent() const { return recurrent_ ? &*recurrent_ : nullptr; }
  // The hidden states the last rollout began from (ppo.policy = "gru"), else null.
  const RecurrentState* rollout_start_state() const { return gru_ ? &gru_->rollout_start_state() : nullptr; }
  // The trained policy as a policy file holds it: the model in use and the frozen observation
  // normalisation.
  PolicyFileContents policy_contents() const;
  // log σ of the model in use.
  const Eigen::VectorXf& log_std() const { return recurrent_ ? recurrent_->log_std() : model_.log_std(); }
  const RolloutBuffer& buffer() const { return buffer_; }
  std::int64_t num_timesteps() const { return num_timesteps_; }
  std::int64_t num_episodes() const { return num_episodes_; }
  // The last stats_window finished episodes, oldest first.
  const std::deque<EpisodeRecord>& recent_episodes() const { return recent_; }
  std::optional<double> mean_recent_return() const;
  // The frozen observation normalisation (ppo.normalize_observations), for evaluation and the
  // policy file; nullopt when off.
  std::optional<ObsNormalization> obs_normalization() const;

 private:
  TrainerConfig config_;
  VecEnv venv_;
  ActorCritic model_;
  std::optional<RecurrentActorCritic> recurrent_;  // ppo.policy = "gru"
  std::optional<GruPolicy> gru_;                   // its hidden states, kept across rollouts
  Adam optimizer_;
  RolloutBuffer buffer_;
  Rng act_rng_;
  std::optional<RunningObsStats> obs_stats_;  // ppo.normalize_observations
  Rng update_rng_;
  Eigen::MatrixXd last_obs_;                // obs_dim x n_envs
  Eigen::RowVectorXf last_episode_starts_;  // 1 x n_envs
  Eigen::RowVectorXf last_dones_;           // 1 x n_envs
  std::vector<double> running_return_;
  std::vector<int> running_length_;
  std::deque<EpisodeRecord> recent_;
  std::int64_t num_timesteps_ = 0;
  std::int64_t num_episodes_ = 0;
  int iteration_ = 0;
  double last_collect_s_ = 0.0;
  std::chrono::steady_clock::time_point start_;
};

// ---- Deterministic evaluation ----

struct EvalResult {
  std::vector<double> returns;
  std::vector<int> lengths;
  double mean_return = 0.0;
  double std_return = 0.0;  // population std (numpy's np.std, as SB3's evaluate_policy)
};

// Evaluation seeds, disjoint by construction. Training seed s (its environments are reset with
// s + i, 0 <= i < n_envs) evaluates episode k with
//
//   eval_seed(s, k) = kEvalSeedOffset + s * kEvalSeedStride + k
//                   = 2^63 + s * 2^20 + k,      0 <= s <= kMaxEvalTrainSeed = 2^43 - 1,
//                                               0 <= k < episodes <= kEvalSeedStride = 2^20.
// eval_seed_first(s, episodes) returns eval_seed(s, 0); evaluate(..., episodes, that) then resets
// episode k with eval_seed(s, k). Proof that no seed is used twice:
//   (a) s * 2^20 + k <= (2^43 - 1) * 2^20 + 2^20 - 1 = 2^63 - 1, so eval_seed(s, k) lies in
//       [2^63, 2^64 - 1]: no uint64 wrap-around, and bit 63 is set.
//   (b) Every training environment seed s' + i (s' <= 2^43 - 1, i < n_envs < 2^62) is < 2^63:
//       bit 63 is clear. So no evaluation seed of any run equals a training seed of any run.
//   (c) eval_seed(s, k) - 2^63 = s * 2^20 + k with 0 <= k < 2^20 is the division of that number
//       by 2^20 with quotient s and remainder k, which is unique: different (s, k) give different
//       seeds, so the evaluations of two training seeds never share an episode seed.
// (Seeds do not collide; distinct seeds of one environment RNG give distinct start states up to
// the resolution of the draw, tests/rl/eval_seeds_test.cpp checks Pendulum's.)
inline constexpr std::uint64_t kEvalSeedOffset = 1ULL << 63;
inline constexpr std::uint64_t kEvalSeedStride = 1ULL << 20;  // max episodes per evaluation
inline constexpr std::uint64_t kMaxEvalTrainSeed = (1ULL << 43) - 1;

// eval_seed(train_seed, 0) of the scheme above. Throws std::invalid_argument if train_seed >
// kMaxEvalTrainSeed or episodes is not in [1, kEvalSeedStride].
std::uint64_t eval_seed_first(std::uint64_t train_seed, int episodes);

using DeterministicPolicy = std::function<Eigen::VectorXd(const Eigen::VectorXd& obs)>;

// Runs `episodes` episodes on one environment from `factory`; episode k starts with
// reset(seed + k) and runs until terminated or truncated (max_steps guards against an
// environment without a time limit: exceeding it throws std::runtime_error). Actions are the
// policy's output clipped to the action bounds.
EvalResult evaluate(const DeterministicPolicy& policy, const EnvFactory& factory, int episodes,
                    std::uint64_t seed, int max_steps = 1'000'000);
// The actor-critic's mean action as the policy (of the normalised observation, if given).
EvalResult evaluate(const ActorCritic& model, const EnvFactory& factory, int episodes,
                    std::uint64_t seed, int max_steps = 1'000'000,
                    const std::optional<ObsNormalization>& obs_norm = std::nullopt);
// A loaded policy of either kind, as its file's reader acts: one Policy::Episode per episode (a
// recurrent policy's state starts at zero in each).
EvalResult evaluate(const Policy& policy, const EnvFactory& factory, int episodes, std::uint64_t seed,
                    int max_steps = 1'000'000);

}  // namespace codesign::rl
