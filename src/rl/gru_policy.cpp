#include "rl/gru_policy.hpp"

#include <stdexcept>

namespace codesign::rl {

RolloutPolicy::ActResult GruPolicy::act(const Eigen::MatrixXf& obs, const Eigen::RowVectorXf& episode_starts,
                                        Rng& rng) {
  return model_.act(obs, episode_starts, state_, rng);
}

float GruPolicy::value_of(const Eigen::VectorXf& obs, std::size_t env) {
  const auto e = static_cast<Eigen::Index>(env);
  if (e >= state_.critic.cols()) throw std::out_of_range("GruPolicy::value_of: no such environment");
  return model_.value_step(obs, state_.critic.col(e))(0);
}

Eigen::RowVectorXf GruPolicy::values(const Eigen::MatrixXf& obs) { return model_.value_step(obs, state_.critic); }

}  // namespace codesign::rl
