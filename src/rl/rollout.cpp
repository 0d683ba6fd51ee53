#include "rl/rollout.hpp"

#include <algorithm>
#include <stdexcept>

#include "base/seconds_since.hpp"

namespace codesign::rl {

RolloutPolicy::ActResult MlpPolicy::act(const Eigen::MatrixXf& obs, const Eigen::RowVectorXf& /*episode_starts*/,
                                        Rng& rng) {
  return model_.act(obs, rng, cache_);
}

float MlpPolicy::value_of(const Eigen::VectorXf& obs, std::size_t /*env*/) {
  return model_.value(obs, cache_)(0);
}

Eigen::RowVectorXf MlpPolicy::values(const Eigen::MatrixXf& obs) { return model_.value(obs, cache_); }

Eigen::MatrixXd clip_actions(const Eigen::MatrixXd& actions, const BoxSpec& bounds) {
  // Scalar loop: Eigen's AVX-512 cwiseMax/cwiseMin trip GCC 12's -Wmaybe-uninitialized.
  Eigen::MatrixXd out(actions.rows(), actions.cols());
  for (Eigen::Index j = 0; j < actions.cols(); ++j)
    for (Eigen::Index i = 0; i < actions.rows(); ++i)
      out(i, j) = std::clamp(actions(i, j), bounds.low(i), bounds.high(i));
  return out;
}

RolloutSummary collect_rollout(RolloutPolicy& policy, const RolloutStep& step, const BoxSpec& action_bounds,
                               const RolloutOptions& options, Eigen::MatrixXd& obs,
                               Eigen::RowVectorXf& episode_starts, RolloutBuffer& buffer, Rng& rng,
                               const RolloutObserver& observer) {
  const Eigen::Index n = obs.cols();
  if (episode_starts.size() != n) throw std::invalid_argument("collect_rollout: one episode_starts flag per column");
  RolloutSummary summary;
  policy.begin_rollout();
  buffer.reset();
  Eigen::RowVectorXf rewards(n);
  Eigen::RowVectorXf dones = Eigen::RowVectorXf::Zero(n);
  for (int k = 0; k < options.n_steps; ++k) {
    const bool last = k + 1 == options.n_steps;
    ObsNormalization norm;
    if (options.obs_stats) {
      options.obs_stats->update(obs);
      norm = options.obs_stats->frozen();
    }
    const Eigen::MatrixXf obs_f = (options.obs_stats ? normalize_columns(norm, obs) : obs).cast<float>();
    auto t0 = std::chrono::steady_clock::now();
    RolloutPolicy::ActResult act = policy.act(obs_f, episode_starts, rng);
    summary.policy_s += seconds_since(t0);
    const VecStepResult& r = step(clip_actions(act.actions.cast<double>(), action_bounds), last);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      if (observer) observer(k, iu, r);
      double reward = r.rewards(i);
      const bool done = r.done(iu);
      dones(i) = done ? 1.0f : 0.0f;
      if (done && r.truncated[iu] && !r.terminated[iu] && r.terminal_obs[iu]) {
        t0 = std::chrono::steady_clock::now();
        const Eigen::VectorXd& raw = *r.terminal_obs[iu];
        const Eigen::VectorXf terminal = (options.obs_stats ? norm.apply(raw) : raw).cast<float>();
        reward += options.gamma * static_cast<double>(policy.value_of(terminal, iu));
        summary.policy_s += seconds_since(t0);
      }
      rewards(i) = static_cast<float>(reward);
    }
    buffer.add(obs_f, act.actions, rewards, episode_starts, act.values, act.log_probs);
    obs = r.obs;
    episode_starts = dones;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::MatrixXf last_obs =
      (options.obs_stats ? normalize_columns(options.obs_stats->frozen(), obs) : obs).cast<float>();
  buffer.compute_returns_and_advantage(policy.values(last_obs), dones, options.gamma, options.gae_lambda);
  summary.policy_s += seconds_since(t0);
  return summary;
}

}  // namespace codesign::rl
