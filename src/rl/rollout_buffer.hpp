#pragma once
// On-policy storage of n_steps x n_envs transitions, as SB3's RolloutBuffer (float32).
//
// Column index of (step t, env e) in every array: t * n_envs + e.
//
// CONTRACT WITH THE COLLECTOR (what add() expects, mirroring SB3's OnPolicyAlgorithm
// .collect_rollouts):
//   * obs:            the observation the action was taken from (obs_dim x n_envs), already
//                     normalised if the trainer normalises observations.
//   * actions:        the UNCLIPPED sampled actions (act_dim x n_envs).
//   * rewards:        the env rewards of this step, with TIMEOUT BOOTSTRAPPING already applied:
//                     for an env whose episode was truncated (time limit) and not terminated,
//                     reward += gamma * V(terminal_obs), V evaluated on the final observation
//                     returned by the step (before auto-reset). The buffer itself never sees
//                     terminal observations.
//   * episode_starts: 1 if obs is the first observation of an episode (i.e. the previous step of
//                     this env ended the episode, or this is the very first step after the
//                     initial reset), else 0. SB3 starts every rollout with the `done` flags of
//                     the last step of the previous rollout (all 1 at the very start).
//   * values, log_probs: from ActorCritic::act on obs.
// After n_steps adds, call compute_returns_and_advantage(V(last_obs), dones) where dones are the
// done flags (terminated or truncated) of the last step; then read advantages()/returns().
#include <Eigen/Core>

namespace codesign::rl {

class RolloutBuffer {
 public:
  using Mat = Eigen::MatrixXf;
  using RowVec = Eigen::RowVectorXf;

  RolloutBuffer(int n_steps, int n_envs, int obs_dim, int act_dim);

  void reset();  // position back to 0 (contents are overwritten by later adds)
  // Throws std::logic_error if the buffer is full or a size is wrong.
  void add(const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const Mat>& actions,
           const Eigen::Ref<const RowVec>& rewards, const Eigen::Ref<const RowVec>& episode_starts,
           const Eigen::Ref<const RowVec>& values, const Eigen::Ref<const RowVec>& log_probs);
  bool full() const { return pos_ == n_steps_; }
  int pos() const { return pos_; }

  // GAE(lambda) exactly as SB3's RolloutBuffer.compute_returns_and_advantage:
  //   for t = n_steps-1 .. 0:
  //     if t == n_steps-1: next_non_terminal = 1 - dones;  next_value = last_values
  //     else:              next_non_terminal = 1 - episode_starts[t+1]; next_value = values[t+1]
  //     delta = r_t + gamma * next_value * next_non_terminal - values[t]
  //     gae   = delta + gamma * lambda * next_non_terminal * gae
  //     advantages[t] = gae
  //   returns = advantages + values   (the TD(lambda) target of the value function)
  // Requires full(). last_values and dones are (1 x n_envs); dones are 0/1.
  void compute_returns_and_advantage(const Eigen::Ref<const RowVec>& last_values,
                                     const Eigen::Ref<const RowVec>& dones, double gamma,
                                     double gae_lambda);

  int n_steps() const { return n_steps_; }
  int n_envs() const { return n_envs_; }
  int obs_dim() const { return static_cast<int>(obs_.rows()); }
  int act_dim() const { return static_cast<int>(actions_.rows()); }
  Eigen::Index size() const { return static_cast<Eigen::Index>(n_steps_) * n_envs_; }

  const Mat& observations() const { return obs_; }   // obs_dim x size
  const Mat& actions() const { return actions_; }    // act_dim x size
  const RowVec& rewards() const { return rewards_; }
  const RowVec& episode_starts() const { return episode_starts_; }
  const RowVec& values() const { return values_; }
  const RowVec& log_probs() const { return log_probs_; }
  const RowVec& advantages() const { return advantages_; }
  const RowVec& returns() const { return returns_; }

 private:
  int n_steps_;
  int n_envs_;
  int pos_ = 0;
  Mat obs_, actions_;
  RowVec rewards_, episode_starts_, values_, log_probs_, advantages_, returns_;
};

}  // namespace codesign::rl
