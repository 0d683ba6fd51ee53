#pragma once
// The recurrent actor-critic as a RolloutPolicy (rollout.hpp): it keeps one hidden state per
// environment (actor and critic GRU, H x n_envs each) across the steps of a rollout and across
// rollouts, zeroes a column where `episode_starts` is 1 before acting on it, and answers the
// value questions of the collector with the state of the right column:
//   * value_of(terminal_obs, env): the episode of column env ended by truncation; the terminal
//     observation continues that episode, so the critic takes one step from env's current state
//     (the state after the step that produced it) without keeping the result, as SB3-contrib's
//     RecurrentPPO does.
//   * values(last_obs) after the last step: one critic step from every column's state, no reset.
//     Where the last step ended an episode this value is multiplied by (1 − done) = 0 in GAE, so
//     the missing reset does not matter.
// begin_rollout() records the state the rollout starts from: rollout_start_state() is the
// initial state of each sequence for recurrent_ppo_update.
#include <cstddef>

#include <Eigen/Core>

#include "rl/recurrent_actor_critic.hpp"
#include "rl/rollout.hpp"

namespace codesign::rl {

class GruPolicy final : public RolloutPolicy {
 public:
  GruPolicy(const RecurrentActorCritic& model, Eigen::Index n_envs)
      : model_(model), state_(model.zero_state(n_envs)), rollout_start_(state_) {}
  void begin_rollout() override { rollout_start_ = state_; }
  ActResult act(const Eigen::MatrixXf& obs, const Eigen::RowVectorXf& episode_starts, Rng& rng) override;
  float value_of(const Eigen::VectorXf& obs, std::size_t env) override;
  Eigen::RowVectorXf values(const Eigen::MatrixXf& obs) override;

  const RecurrentState& state() const { return state_; }
  const RecurrentState& rollout_start_state() const { return rollout_start_; }

 private:
  const RecurrentActorCritic& model_;
  RecurrentState state_;
  RecurrentState rollout_start_;
};

}  // namespace codesign::rl
