#include "core/run_ahead.hpp"

#include <chrono>
#include <stdexcept>

#include "base/seconds_since.hpp"
#include "rl/rollout.hpp"

namespace codesign::core {

ShareRollout empty_share(int n_steps, std::size_t n, std::size_t obs_dim, std::size_t act_dim) {
  if (n_steps < 1) throw std::invalid_argument("a rollout needs at least one decision");
  const auto cols = static_cast<Eigen::Index>(n);
  ShareRollout s;
  s.steps.resize(static_cast<std::size_t>(n_steps));
  for (RolloutStepColumns& c : s.steps) {
    c.obs = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(obs_dim), cols);
    c.actions = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(act_dim), cols);
    c.values = c.log_probs = c.rewards = Eigen::RowVectorXf::Zero(cols);
    c.raw_rewards = Eigen::RowVectorXd::Zero(cols);
    c.done.assign(n, 0);
    c.in_band.assign(n, 0);
    c.reasons.assign(n, std::string());
  }
  s.last_values = Eigen::RowVectorXf::Zero(cols);
  return s;
}

ShareRollout run_share(EnvPool& pool, const std::vector<EpisodeSetup>& setups, const rl::ActorCritic& model,
                       rl::ActorCritic::InferenceCache& cache, const std::vector<std::size_t>& places,
                       std::size_t width, const std::vector<Eigen::MatrixXd>& normals, double gamma) {
  if (setups.size() != pool.size()) throw std::invalid_argument("run_share: one setup per environment of the pool");
  return run_started_share(pool, pool.start(setups), model, cache, places, width, normals, gamma);
}

ShareRollout run_started_share(EnvPool& pool, Eigen::MatrixXd obs, const rl::ActorCritic& model,
                               rl::ActorCritic::InferenceCache& cache, const std::vector<std::size_t>& places,
                               std::size_t width, const std::vector<Eigen::MatrixXd>& normals, double gamma) {
  const std::size_t n = pool.size(), d = pool.spec().observation.dim(), a = pool.spec().action.dim();
  if (places.size() != n) throw std::invalid_argument("run_share: one place per environment of the pool");
  if (obs.rows() != static_cast<Eigen::Index>(d) || obs.cols() != static_cast<Eigen::Index>(n))
    throw std::invalid_argument("run_share: the first observations must be obs_dim x environments");
  for (std::size_t p : places)
    if (p >= width) throw std::invalid_argument("run_share: a place beyond the batch's width");
  for (const Eigen::MatrixXd& z : normals)
    if (z.rows() != static_cast<Eigen::Index>(a) || z.cols() != static_cast<Eigen::Index>(width))
      throw std::invalid_argument("run_share: each decision's normals must be act_dim x width");
  const int n_steps = static_cast<int>(normals.size());
  ShareRollout out = empty_share(n_steps, n, d, a);
  cache.weights_changed();
  const auto col = [](std::size_t j) { return static_cast<Eigen::Index>(j); };
  // The ψ-wide batch the one-process rollout would compute, this share's columns at their places.
  Eigen::MatrixXf batch = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(width));
  for (int k = 0; k < n_steps; ++k) {
    RolloutStepColumns& rec = out.steps[static_cast<std::size_t>(k)];
    rec.obs = obs.cast<float>();
    for (std::size_t j = 0; j < n; ++j) batch.col(col(places[j])) = rec.obs.col(col(j));
    auto t0 = std::chrono::steady_clock::now();
    const rl::ActorCritic::ActResult act = model.act_with(batch, normals[static_cast<std::size_t>(k)], cache);
    out.policy_s += seconds_since(t0);
    for (std::size_t j = 0; j < n; ++j) {
      rec.actions.col(col(j)) = act.actions.col(col(places[j]));
      rec.values(col(j)) = act.values(col(places[j]));
      rec.log_probs(col(j)) = act.log_probs(col(places[j]));
    }
    const bool last = k + 1 == n_steps;
    const rl::VecStepResult& r = pool.step(rl::clip_actions(rec.actions.cast<double>(), pool.spec().action), !last);
    for (std::size_t j = 0; j < n; ++j) {
      double reward = r.rewards(col(j));
      rec.raw_rewards(col(j)) = reward;
      rec.done[j] = r.done(j) ? 1 : 0;
      if (r.done(j)) {
        rec.in_band[j] = pool.last_in_band(j);
        rec.reasons[j] = r.reasons[j];
      }
      if (r.done(j) && r.truncated[j] && !r.terminated[j] && r.terminal_obs[j]) {
        t0 = std::chrono::steady_clock::now();
        const Eigen::VectorXf terminal = r.terminal_obs[j]->cast<float>();
        reward += gamma * static_cast<double>(model.value(terminal, cache)(0));
        out.policy_s += seconds_since(t0);
      }
      rec.rewards(col(j)) = static_cast<float>(reward);
    }
    obs = r.obs;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::MatrixXf last = obs.cast<float>();
  for (std::size_t j = 0; j < n; ++j) batch.col(col(places[j])) = last.col(col(j));
  const Eigen::RowVectorXf values = model.value(batch, cache);
  for (std::size_t j = 0; j < n; ++j) out.last_values(col(j)) = values(col(places[j]));
  out.policy_s += seconds_since(t0);
  return out;
}

void place_share(const ShareRollout& share, const std::vector<std::size_t>& places, ShareRollout& into) {
  if (share.steps.size() != into.steps.size() || share.last_values.size() != static_cast<Eigen::Index>(places.size()))
    throw std::invalid_argument("place_share: the share's decisions or environments do not fit");
  for (std::size_t p : places)
    if (p >= static_cast<std::size_t>(into.last_values.size()))
      throw std::invalid_argument("place_share: a place beyond the rollout's environments");
  for (std::size_t k = 0; k < share.steps.size(); ++k) {
    const RolloutStepColumns& from = share.steps[k];
    RolloutStepColumns& to = into.steps[k];
    for (std::size_t j = 0; j < places.size(); ++j) {
      const auto s = static_cast<Eigen::Index>(j), t = static_cast<Eigen::Index>(places[j]);
      to.obs.col(t) = from.obs.col(s);
      to.actions.col(t) = from.actions.col(s);
      to.values(t) = from.values(s);
      to.log_probs(t) = from.log_probs(s);
      to.rewards(t) = from.rewards(s);
      to.raw_rewards(t) = from.raw_rewards(s);
      to.done[places[j]] = from.done[j];
      to.in_band[places[j]] = from.in_band[j];
      to.reasons[places[j]] = from.reasons[j];
    }
  }
  for (std::size_t j = 0; j < places.size(); ++j)
    into.last_values(static_cast<Eigen::Index>(places[j])) = share.last_values(static_cast<Eigen::Index>(j));
}

void fill_buffer(const ShareRollout& rollout, double gamma, double gae_lambda, rl::RolloutBuffer& buffer) {
  const Eigen::Index n = rollout.last_values.size();
  buffer.reset();
  Eigen::RowVectorXf episode_starts = Eigen::RowVectorXf::Ones(n);
  Eigen::RowVectorXf dones = Eigen::RowVectorXf::Zero(n);
  for (const RolloutStepColumns& s : rollout.steps) {
    buffer.add(s.obs, s.actions, s.rewards, episode_starts, s.values, s.log_probs);
    for (Eigen::Index i = 0; i < n; ++i) dones(i) = s.done[static_cast<std::size_t>(i)] ? 1.0f : 0.0f;
    episode_starts = dones;
  }
  buffer.compute_returns_and_advantage(rollout.last_values, dones, gamma, gae_lambda);
}

}  // namespace codesign::core
