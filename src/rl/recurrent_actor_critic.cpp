#include "rl/recurrent_actor_critic.hpp"

#include <stdexcept>
#include <string>

#include "rl/gaussian.hpp"
#include "rl/layer_sizes.hpp"

namespace codesign::rl {

template <class S>
RecurrentActorCriticT<S>::RecurrentActorCriticT(int obs_dim, int act_dim, int gru_hidden,
                                                const std::vector<int>& actor_hidden,
                                                const std::vector<int>& critic_hidden, S log_std_init,
                                                int privileged_dim)
    : actor_gru_(obs_dim, gru_hidden),
      actor_(layer_sizes(gru_hidden, actor_hidden, act_dim)),
      critic_gru_(obs_dim + privileged_dim, gru_hidden),
      critic_(layer_sizes(gru_hidden, critic_hidden, 1)),
      log_std_(Vec::Constant(act_dim, log_std_init)),
      log_std_init_(log_std_init) {
  if (privileged_dim < 0) throw std::invalid_argument("RecurrentActorCritic: negative privileged_dim");
}

template <class S>
void RecurrentActorCriticT<S>::init(Rng& rng) {
  actor_gru_.init_uniform(rng);
  actor_.init_orthogonal(S(0.01), rng);
  critic_gru_.init_uniform(rng);
  critic_.init_orthogonal(S(1), rng);
  log_std_.setConstant(log_std_init_);
}

template <class S>
typename RecurrentActorCriticT<S>::State RecurrentActorCriticT<S>::zero_state(Eigen::Index n) const {
  return State{Mat::Zero(gru_hidden(), n), Mat::Zero(gru_hidden(), n)};
}

template <class S>
typename RecurrentActorCriticT<S>::ActResult RecurrentActorCriticT<S>::act(const Eigen::Ref<const Mat>& obs,
                                                                           const Eigen::Ref<const RowVec>& starts,
                                                                           State& state, Rng& rng) const {
  if (obs.rows() != critic_input_dim())
    throw std::invalid_argument("RecurrentActorCritic::act: observation has " + std::to_string(obs.rows()) +
                                " rows, expected " + std::to_string(critic_input_dim()));
  if (state.actor.cols() != obs.cols() || state.critic.cols() != obs.cols())
    throw std::invalid_argument("RecurrentActorCritic::act: one state column per observation column expected");
  actor_gru_.step(obs.topRows(obs_dim()), starts, state.actor);
  critic_gru_.step(obs, starts, state.critic);
  ActResult r;
  const Mat mean = actor_.predict(state.actor);
  r.actions = gaussian_sample<S>(mean, log_std_, rng);
  r.log_probs = gaussian_log_prob<S>(mean, log_std_, r.actions);
  r.values = critic_.predict(state.critic).row(0);
  return r;
}

template <class S>
typename RecurrentActorCriticT<S>::RowVec RecurrentActorCriticT<S>::value_step(const Eigen::Ref<const Mat>& obs,
                                                                               const Eigen::Ref<const Mat>& h) const {
  Mat next = h;
  critic_gru_.step(obs, RowVec::Zero(obs.cols()), next);
  return critic_.predict(next).row(0);
}

template <class S>
typename RecurrentActorCriticT<S>::Mat RecurrentActorCriticT<S>::deterministic_step(
    const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const RowVec>& starts, Mat& h) const {
  actor_gru_.step(obs, starts, h);
  return actor_.predict(h);
}

template <class S>
typename RecurrentActorCriticT<S>::Grad RecurrentActorCriticT<S>::zero_grad() const {
  return Grad{Vec::Zero(actor_gru_.num_params()), Vec::Zero(actor_.num_params()),
              Vec::Zero(critic_gru_.num_params()), Vec::Zero(critic_.num_params()), Vec::Zero(log_std_.size())};
}

template <class S>
std::vector<AdamBlock<S>> RecurrentActorCriticT<S>::adam_blocks(const Grad& g) {
  if (g.actor_gru.size() != actor_gru_.num_params() || g.actor.size() != actor_.num_params() ||
      g.critic_gru.size() != critic_gru_.num_params() || g.critic.size() != critic_.num_params() ||
      g.log_std.size() != log_std_.size())
    throw std::invalid_argument("RecurrentActorCritic::adam_blocks: gradient sizes do not match");
  return {{actor_gru_.params().data(), g.actor_gru.data(), g.actor_gru.size()},
          {actor_.params().data(), g.actor.data(), g.actor.size()},
          {critic_gru_.params().data(), g.critic_gru.data(), g.critic_gru.size()},
          {critic_.params().data(), g.critic.data(), g.critic.size()},
          {log_std_.data(), g.log_std.data(), g.log_std.size()}};
}

template class RecurrentActorCriticT<float>;
template class RecurrentActorCriticT<double>;

}  // namespace codesign::rl
