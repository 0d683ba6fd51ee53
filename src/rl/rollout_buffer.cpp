#include "rl/rollout_buffer.hpp"

#include <stdexcept>
#include <string>

namespace codesign::rl {

RolloutBuffer::RolloutBuffer(int n_steps, int n_envs, int obs_dim, int act_dim)
    : n_steps_(n_steps), n_envs_(n_envs) {
  if (n_steps <= 0 || n_envs <= 0 || obs_dim <= 0 || act_dim <= 0)
    throw std::invalid_argument("RolloutBuffer: all sizes must be > 0");
  const Eigen::Index n = size();
  obs_ = Mat::Zero(obs_dim, n);
  actions_ = Mat::Zero(act_dim, n);
  rewards_ = episode_starts_ = values_ = log_probs_ = advantages_ = returns_ = RowVec::Zero(n);
}

void RolloutBuffer::reset() { pos_ = 0; }

void RolloutBuffer::add(const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const Mat>& actions,
                        const Eigen::Ref<const RowVec>& rewards,
                        const Eigen::Ref<const RowVec>& episode_starts,
                        const Eigen::Ref<const RowVec>& values,
                        const Eigen::Ref<const RowVec>& log_probs) {
  if (full()) throw std::logic_error("RolloutBuffer::add: buffer is full");
  if (obs.rows() != obs_.rows() || obs.cols() != n_envs_ || actions.rows() != actions_.rows() ||
      actions.cols() != n_envs_ || rewards.size() != n_envs_ ||
      episode_starts.size() != n_envs_ || values.size() != n_envs_ ||
      log_probs.size() != n_envs_)
    throw std::logic_error("RolloutBuffer::add: wrong sizes (expected " +
                           std::to_string(n_envs_) + " environments)");
  const Eigen::Index c = static_cast<Eigen::Index>(pos_) * n_envs_;
  obs_.middleCols(c, n_envs_) = obs;
  actions_.middleCols(c, n_envs_) = actions;
  rewards_.segment(c, n_envs_) = rewards;
  episode_starts_.segment(c, n_envs_) = episode_starts;
  values_.segment(c, n_envs_) = values;
  log_probs_.segment(c, n_envs_) = log_probs;
  ++pos_;
}

void RolloutBuffer::compute_returns_and_advantage(const Eigen::Ref<const RowVec>& last_values,
                                                  const Eigen::Ref<const RowVec>& dones,
                                                  double gamma, double gae_lambda) {
  if (!full()) throw std::logic_error("RolloutBuffer: compute_returns_and_advantage before full");
  if (last_values.size() != n_envs_ || dones.size() != n_envs_)
    throw std::logic_error("RolloutBuffer: last_values/dones must have one entry per env");
  const float g = static_cast<float>(gamma);
  const float gl = static_cast<float>(gamma * gae_lambda);
  for (int e = 0; e < n_envs_; ++e) {
    float gae = 0.0f;
    for (int t = n_steps_ - 1; t >= 0; --t) {
      const Eigen::Index i = static_cast<Eigen::Index>(t) * n_envs_ + e;
      float next_non_terminal, next_value;
      if (t == n_steps_ - 1) {
        next_non_terminal = 1.0f - dones(e);
        next_value = last_values(e);
      } else {
        next_non_terminal = 1.0f - episode_starts_(i + n_envs_);
        next_value = values_(i + n_envs_);
      }
      const float delta = rewards_(i) + g * next_value * next_non_terminal - values_(i);
      gae = delta + gl * next_non_terminal * gae;
      advantages_(i) = gae;
    }
  }
  returns_ = advantages_ + values_;
}

}  // namespace codesign::rl
