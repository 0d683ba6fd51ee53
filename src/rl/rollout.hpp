#pragma once
// The one rollout loop of the project (SB3's OnPolicyAlgorithm.collect_rollouts), shared by the
// gym trainer (trainer.hpp) and the co-design's Algorithm 1 (core/outer_loop.hpp), and the
// policy seam it talks to.
//
// RolloutPolicy is what collection needs of a policy: sampled actions with their values and
// log-probabilities for a batch of observations (one column per environment), and V of an
// observation. `episode_starts` (1 where the column's observation is the first of an episode)
// is passed with every act() so that a policy with memory can clear the state of those
// columns; a memoryless policy ignores it. value_of(obs, env) is asked for one environment's
// terminal observation (timeout bootstrapping), values() for all columns after the last step.
// MlpPolicy adapts the feed-forward ActorCritic.
//
// collect_rollout(), for n_steps steps:
//   act = policy.act(obs, episode_starts); the environments step with act.actions clipped to
//   the action bounds (the buffer keeps the unclipped sample); the observer sees every
//   environment's raw reward and done flags; where an episode was truncated and not
//   terminated, reward += γ·V(terminal_obs); buffer.add(obs, actions, rewards, episode_starts,
//   values, log_probs); episode_starts = this step's done flags.
// Then GAE with V(obs after the last step) and the last step's done flags. On return `obs` and
// `episode_starts` hold the state to continue from (the trainer keeps them across rollouts, the
// co-design starts each rollout afresh).
#include <cstddef>
#include <functional>

#include <Eigen/Core>

#include "rl/actor_critic.hpp"
#include "rl/env.hpp"
#include "rl/obs_normalizer.hpp"
#include "rl/rng.hpp"
#include "rl/rollout_buffer.hpp"
#include "rl/vec_env.hpp"

namespace codesign::rl {

class RolloutPolicy {
 public:
  using ActResult = ActorCritic::ActResult;
  virtual ~RolloutPolicy() = default;
  // Called before each rollout: the parameters may have changed since the last one.
  virtual void begin_rollout() = 0;
  virtual ActResult act(const Eigen::MatrixXf& obs, const Eigen::RowVectorXf& episode_starts, Rng& rng) = 0;
  virtual float value_of(const Eigen::VectorXf& obs, std::size_t env) = 0;
  virtual Eigen::RowVectorXf values(const Eigen::MatrixXf& obs) = 0;
};

// The feed-forward actor-critic as a RolloutPolicy (its forward passes reuse one cache).
class MlpPolicy final : public RolloutPolicy {
 public:
  explicit MlpPolicy(const ActorCritic& model) : model_(model) {}
  void begin_rollout() override { cache_.weights_changed(); }
  ActResult act(const Eigen::MatrixXf& obs, const Eigen::RowVectorXf& episode_starts, Rng& rng) override;
  float value_of(const Eigen::VectorXf& obs, std::size_t env) override;
  Eigen::RowVectorXf values(const Eigen::MatrixXf& obs) override;

 private:
  const ActorCritic& model_;
  ActorCritic::InferenceCache cache_;
};

// The environments' side: one step of every environment with the given (clipped) actions.
// `last` is true on the rollout's last step (an environment pool may then skip restarting a
// finished episode, whose column is then its terminal observation).
using RolloutStep = std::function<const VecStepResult&(const Eigen::MatrixXd& actions, bool last)>;
// Called after each step for each environment i with the step's result (rewards before
// bootstrapping), in order of i.
using RolloutObserver = std::function<void(int step, std::size_t env, const VecStepResult& result)>;

struct RolloutOptions {
  int n_steps = 2048;
  double gamma = 0.99;
  double gae_lambda = 0.95;
  // Observation normalisation (obs_normalizer.hpp), not owned; null: the policy and the buffer
  // get the observations as the environments give them. Set: each step's observations update
  // the statistics, then the policy, the buffer and the bootstrap values see them normalised.
  RunningObsStats* obs_stats = nullptr;
};

struct RolloutSummary {
  double policy_s = 0.0;  // wall seconds spent in the policy's forward passes
};

RolloutSummary collect_rollout(RolloutPolicy& policy, const RolloutStep& step, const BoxSpec& action_bounds,
                               const RolloutOptions& options, Eigen::MatrixXd& obs,
                               Eigen::RowVectorXf& episode_starts, RolloutBuffer& buffer, Rng& rng,
                               const RolloutObserver& observer = {});

// Clips each action column to [low, high] (SB3 clips before env.step; the buffer keeps the
// unclipped sample).
Eigen::MatrixXd clip_actions(const Eigen::MatrixXd& actions, const BoxSpec& bounds);

}  // namespace codesign::rl
