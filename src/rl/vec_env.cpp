#include "rl/vec_env.hpp"

#include <stdexcept>

namespace codesign::rl {

VecEnv::VecEnv(const EnvFactory& factory, std::size_t n_envs, std::uint64_t seed,
               std::size_t n_threads)
    : seed_(seed), pool_(n_threads) {
  if (n_envs == 0) throw std::invalid_argument("VecEnv: n_envs must be at least 1");
  envs_.reserve(n_envs);
  for (std::size_t i = 0; i < n_envs; ++i) {
    envs_.push_back(factory(i));
    if (!envs_.back()) throw std::invalid_argument("VecEnv: factory returned no environment");
  }
  const std::size_t obs_dim = spec().observation.dim();
  for (const auto& e : envs_) {
    if (e->spec().observation.dim() != obs_dim ||
        e->spec().action.dim() != spec().action.dim())
      throw std::invalid_argument("VecEnv: environments have different observation/action sizes");
  }
  result_ = VecStepResult(obs_dim, n_envs);
}

Eigen::MatrixXd VecEnv::reset() {
  const auto n = static_cast<Eigen::Index>(envs_.size());
  Eigen::MatrixXd obs(static_cast<Eigen::Index>(spec().observation.dim()), n);
  pool_.parallel_for(envs_.size(), [&](std::size_t i) {
    obs.col(static_cast<Eigen::Index>(i)) = envs_[i]->reset(seed_ + i);
  });
  return obs;
}

const VecStepResult& VecEnv::step(const Eigen::MatrixXd& actions) {
  if (actions.cols() != static_cast<Eigen::Index>(envs_.size()) ||
      actions.rows() != static_cast<Eigen::Index>(spec().action.dim()))
    throw std::invalid_argument("VecEnv::step: actions must be act_dim x n_envs");
  pool_.parallel_for(envs_.size(), [&](std::size_t i) {
    const auto c = static_cast<Eigen::Index>(i);
    StepResult r = envs_[i]->step(actions.col(c));
    result_.rewards(c) = r.reward;
    result_.terminated[i] = r.terminated;
    result_.truncated[i] = r.truncated;
    if (r.done()) {
      result_.terminal_obs[i] = std::move(r.obs);
      result_.reasons[i] = std::move(r.reason);
      result_.obs.col(c) = envs_[i]->reset(std::nullopt);
    } else {
      result_.terminal_obs[i].reset();
      result_.reasons[i].clear();
      result_.obs.col(c) = r.obs;
    }
  });
  return result_;
}

}  // namespace codesign::rl
