#include "core/env_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "base/seconds_since.hpp"
#include "fem/design.hpp"

namespace codesign::core {

ThreadEnvPool::ThreadEnvPool(std::shared_ptr<SimulatorPool> sims, const TaskConfig& task, std::size_t n_envs,
                             std::size_t n_threads, bool privileged)
    : sims_(sims), pool_(n_threads), in_use_(pool_.size()) {
  if (!sims_) throw std::invalid_argument("ThreadEnvPool: no simulator pool");
  if (n_envs < 1) throw std::invalid_argument("ThreadEnvPool: need at least one environment");
  for (std::size_t i = 0; i < n_envs; ++i) envs_.push_back(std::make_unique<WhiskerEnv>(sims, task, privileged));
  result_ = rl::VecStepResult(envs_.front()->spec().observation.dim(), n_envs);
  last_in_band_.assign(n_envs, 0);
  observers_.resize(n_envs);
  step_cost_.assign(n_envs, 0.0);
  start_cost_.assign(fem::kDesignCount, std::numeric_limits<double>::infinity());
  order_.resize(n_envs);
  work_mark_.assign(n_envs, 0.0);
}

void ThreadEnvPool::order_by_cost(const std::vector<double>& cost) {
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
}

void ThreadEnvPool::set_threads_in_use(std::size_t n) { in_use_ = std::clamp<std::size_t>(n, 1, pool_.size()); }

std::function<std::size_t()> ThreadEnvPool::recount() {
  if (!lender_) return {};
  set_threads_in_use(lender_());
  return [this] {
    set_threads_in_use(lender_());
    return in_use_;
  };
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
  std::vector<double> predicted(envs_.size());
  for (std::size_t i = 0; i < envs_.size(); ++i) {
    const int d = setups[i].design;
    predicted[i] = d >= 0 && d < fem::kDesignCount ? start_cost_[static_cast<std::size_t>(d)] : 0.0;
  }
  order_by_cost(predicted);
  for (std::size_t i = 0; i < envs_.size(); ++i) work_mark_[i] = envs_[i]->settle_seconds() + envs_[i]->step_seconds();
  std::vector<double> took(envs_.size());  // this start's cost per environment
  const std::function<std::size_t()> more = recount();
  pool_.parallel_for_ordered(order_, [&](std::size_t i) {
    const auto t0 = std::chrono::steady_clock::now();
    envs_[i]->set_episode(setups[i]);
    obs.col(static_cast<Eigen::Index>(i)) = envs_[i]->reset(std::nullopt);
    took[i] = seconds_since(t0);
  }, in_use_, more);
  for (std::size_t i = 0; i < envs_.size(); ++i) start_cost_[static_cast<std::size_t>(setups[i].design)] = took[i];
  return obs;
}

const rl::VecStepResult& ThreadEnvPool::step(const Eigen::MatrixXd& actions, bool restart) {
  if (actions.cols() != static_cast<Eigen::Index>(envs_.size()))
    throw std::invalid_argument("ThreadEnvPool::step: one action column per environment");
  order_by_cost(step_cost_);
  const std::function<std::size_t()> more = recount();
  pool_.parallel_for_ordered(order_, [&](std::size_t i) {
    const auto t0 = std::chrono::steady_clock::now();
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
    step_cost_[i] = seconds_since(t0);
  }, in_use_, more);
  return result_;
}

std::vector<double> ThreadEnvPool::work_since_start() const {
  std::vector<double> w(envs_.size());
  for (std::size_t i = 0; i < envs_.size(); ++i)
    w[i] = envs_[i]->settle_seconds() + envs_[i]->step_seconds() - work_mark_[i];
  return w;
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
