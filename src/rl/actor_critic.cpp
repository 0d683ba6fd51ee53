#include "rl/actor_critic.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "rl/gaussian.hpp"
#include "rl/layer_sizes.hpp"

namespace codesign::rl {

template <class S>
ActorCriticT<S>::ActorCriticT(int obs_dim, int act_dim, const std::vector<int>& actor_hidden,
                              const std::vector<int>& critic_hidden, S log_std_init, int privileged_dim)
    : actor_(layer_sizes(obs_dim, actor_hidden, act_dim)),
      critic_(layer_sizes(obs_dim + privileged_dim, critic_hidden, 1)),
      log_std_(Vec::Constant(act_dim, log_std_init)),
      log_std_init_(log_std_init) {}

template <class S>
void ActorCriticT<S>::init_orthogonal(Rng& rng) {
  actor_.init_orthogonal(S(0.01), rng);
  critic_.init_orthogonal(S(1), rng);
  log_std_.setConstant(log_std_init_);
}

template <class S>
typename ActorCriticT<S>::ActResult ActorCriticT<S>::act(const Eigen::Ref<const Mat>& obs,
                                                         Rng& rng) const {
  InferenceCache cache;
  return act(obs, rng, cache);
}

template <class S>
typename ActorCriticT<S>::ActResult ActorCriticT<S>::act(const Eigen::Ref<const Mat>& obs,
                                                         Rng& rng, InferenceCache& cache) const {
  if (obs.rows() != critic_input_dim())
    throw std::invalid_argument("ActorCritic::act: observation has " + std::to_string(obs.rows()) +
                                " rows, expected " + std::to_string(critic_input_dim()));
  return act_with(obs, standard_normals(log_std_.size(), obs.cols(), rng), cache);
}

template <class S>
typename ActorCriticT<S>::ActResult ActorCriticT<S>::act_with(const Eigen::Ref<const Mat>& obs,
                                                              const Eigen::Ref<const Eigen::MatrixXd>& normals,
                                                              InferenceCache& cache) const {
  ActResult r;
  if (obs.rows() != critic_input_dim())
    throw std::invalid_argument("ActorCritic::act: observation has " + std::to_string(obs.rows()) +
                                " rows, expected " + std::to_string(critic_input_dim()));
  const Mat& mean = privileged_dim() == 0 ? actor_.forward(obs, cache.actor)
                                          : actor_.forward(actor_rows(obs), cache.actor);
  r.actions = gaussian_sample_with<S>(mean, log_std_, normals);
  r.log_probs = gaussian_log_prob<S>(mean, log_std_, r.actions);
  r.values = critic_.forward(obs, cache.critic).row(0);
  return r;
}

template <class S>
typename ActorCriticT<S>::RowVec ActorCriticT<S>::value(const Eigen::Ref<const Mat>& obs) const {
  InferenceCache cache;
  return value(obs, cache);
}

template <class S>
typename ActorCriticT<S>::RowVec ActorCriticT<S>::value(const Eigen::Ref<const Mat>& obs,
                                                        InferenceCache& cache) const {
  return critic_.forward(obs, cache.critic).row(0);
}

template <class S>
typename ActorCriticT<S>::Vec ActorCriticT<S>::deterministic_action(
    const Eigen::Ref<const Vec>& obs) const {
  return actor_.predict(obs).col(0);
}

template <class S>
typename ActorCriticT<S>::Mat ActorCriticT<S>::deterministic_actions(
    const Eigen::Ref<const Mat>& obs) const {
  return actor_.predict(obs);
}

template <class S>
typename ActorCriticT<S>::Grad ActorCriticT<S>::zero_grad() const {
  return Grad{Vec::Zero(actor_.num_params()), Vec::Zero(critic_.num_params()),
              Vec::Zero(log_std_.size())};
}

template <class S>
std::vector<AdamBlock<S>> ActorCriticT<S>::adam_blocks(const Grad& grad) {
  if (grad.actor.size() != actor_.num_params() || grad.critic.size() != critic_.num_params() ||
      grad.log_std.size() != log_std_.size())
    throw std::invalid_argument("ActorCritic::adam_blocks: gradient sizes do not match");
  return {{actor_.params().data(), grad.actor.data(), grad.actor.size()},
          {critic_.params().data(), grad.critic.data(), grad.critic.size()},
          {log_std_.data(), grad.log_std.data(), grad.log_std.size()}};
}

template class ActorCriticT<float>;
template class ActorCriticT<double>;

}  // namespace codesign::rl
