#include "codesign/env_pool.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace codesign::core {

ThreadEnvPool::ThreadEnvPool(std::shared_ptr<SimulatorPool> sims, const TaskConfig& task, std::size_t n_envs,
                             std::size_t n_threads, bool privileged)
    : pool_(n_threads) {
  if (n_envs < 1) throw std::invalid_argument("ThreadEnvPool: need at least one environment");
  for (std::size_t i = 0; i < n_envs; ++i) envs_.push_back(std::make_unique<WhiskerEnv>(sims, task, privileged));
  result_ = rl::VecStepResult(envs_.front()->spec().observation.dim(), n_envs);
  last_in_band_.assign(n_envs, 0);
  observers_.resize(n_envs);
}

void ThreadEnvPool::set_step_observer(std::size_t i, StepObserver observer, int every) {
  Observer& o = observers_.at(i);
  o.fn = every > 0 ? std::move(observer) : StepObserver();
  o.every = o.fn ? every : 0;
  o.decisions = 0;
}

Eigen::MatrixXd ThreadEnvPool::start(const std::vector<EpisodeSetup>& setups) {
  if (setups.size() != envs_.size()) throw std::invalid_argument("ThreadEnvPool::start: one setup per environment");
  Eigen::MatrixXd obs(spec().observation.dim(), static_cast<Eigen::Index>(envs_.size()));
  pool_.parallel_for(envs_.size(), [&](std::size_t i) {
    envs_[i]->set_episode(setups[i]);
    obs.col(static_cast<Eigen::Index>(i)) = envs_[i]->reset(std::nullopt);
  });
  return obs;
}

const rl::VecStepResult& ThreadEnvPool::step(const Eigen::MatrixXd& actions, bool restart) {
  if (actions.cols() != static_cast<Eigen::Index>(envs_.size()))
    throw std::invalid_argument("ThreadEnvPool::step: one action column per environment");
  pool_.parallel_for(envs_.size(), [&](std::size_t i) {
    const auto c = static_cast<Eigen::Index>(i);
    WhiskerEnv& env = *envs_[i];
    rl::StepResult r = env.step(actions.col(c));
    Observer& o = observers_[i];
    if (o.every > 0 && ++o.decisions % o.every == 0) {
      const double a = std::isfinite(actions(0, c)) ? std::clamp(actions(0, c), -1.0, 1.0) : 0.0;
      o.fn(env.episode(), trace_row(env.simulator().sensors(), env.decisions_taken() - 1, a));
    }
    result_.rewards(c) = r.reward;
    result_.terminated[i] = r.terminated ? 1 : 0;
    result_.truncated[i] = r.truncated ? 1 : 0;
    result_.reasons[i] = r.reason;
    if (r.done()) {
      last_in_band_[i] = env.decisions_in_band();
      result_.obs.col(c) = restart ? env.reset(std::nullopt) : r.obs;
      result_.terminal_obs[i] = std::move(r.obs);
    } else {
      result_.terminal_obs[i].reset();
      result_.obs.col(c) = r.obs;
    }
  });
  return result_;
}

double ThreadEnvPool::settle_seconds() const {
  double s = 0.0;
  for (const auto& e : envs_) s += e->settle_seconds();
  return s;
}

double ThreadEnvPool::step_seconds() const {
  double s = 0.0;
  for (const auto& e : envs_) s += e->step_seconds();
  return s;
}

}  // namespace codesign::core
