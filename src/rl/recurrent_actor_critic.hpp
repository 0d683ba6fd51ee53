#pragma once
// Recurrent actor-critic: a GRU in front of each of the feed-forward heads of actor_critic.hpp.
//   actor:  obs -> GRU(H) -> tanh hidden layers -> linear -> action mean   (head gain 0.01)
//   critic: obs -> GRU(H) -> tanh hidden layers -> linear -> V             (head gain 1)
//   log_std: act_dim free parameters (state-independent), as the feed-forward model.
// Two GRUs, one per network, as SB3-contrib's RecurrentPPO by default (shared_lstm = False,
// enable_critic_lstm = True). Why not one shared: the actor and critic MLPs are separate here
// too (net_arch pi/vf), the value loss then cannot pull the actor's memory towards what predicts
// the return, and a privileged critic (privileged_dim > 0) simply gives the critic's GRU more
// inputs while the actor's GRU reads the task's observation only. The cost is a second GRU
// forward per step (H = 64: ~40k multiply-adds per sample, small beside the MLPs).
// The MLPs get SB3's orthogonal init, the GRUs PyTorch's default (gru.hpp).
//
// Memory: RecurrentState holds each network's hidden state, H x n_envs. act() and
// value_step() first zero the columns whose `starts` flag is 1 (an episode begins), then run one
// GRU step. The PPO update runs whole sequences through forward_sequence (recurrent_ppo.hpp).
#include <vector>

#include <Eigen/Core>

#include "rl/actor_critic.hpp"
#include "rl/adam.hpp"
#include "rl/gru.hpp"
#include "rl/mlp.hpp"
#include "rl/rng.hpp"

namespace codesign::rl {

template <class S>
struct RecurrentActorCriticGradT {
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  Vec actor_gru, actor, critic_gru, critic, log_std;  // layouts of the model's parts
};

template <class S>
struct RecurrentStateT {
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  Mat actor, critic;  // H x n_envs each
};

template <class S>
class RecurrentActorCriticT {
 public:
  using Scalar = S;
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using RowVec = Eigen::Matrix<S, 1, Eigen::Dynamic>;
  using Grad = RecurrentActorCriticGradT<S>;
  using State = RecurrentStateT<S>;
  using ActResult = typename ActorCriticT<S>::ActResult;

  RecurrentActorCriticT() = default;
  // Parameters are zero and log_std = log_std_init until init() is called.
  RecurrentActorCriticT(int obs_dim, int act_dim, int gru_hidden, const std::vector<int>& actor_hidden,
                        const std::vector<int>& critic_hidden, S log_std_init = S(0), int privileged_dim = 0);

  // Actor GRU (PyTorch init), actor MLP (orthogonal, head 0.01), critic GRU, critic MLP (head 1),
  // log_std = log_std_init; in that order from the same rng.
  void init(Rng& rng);

  int obs_dim() const { return actor_gru_.input_dim(); }
  int critic_input_dim() const { return critic_gru_.input_dim(); }
  int privileged_dim() const { return critic_input_dim() - obs_dim(); }
  int act_dim() const { return actor_.output_dim(); }
  int gru_hidden() const { return actor_gru_.hidden_dim(); }
  Eigen::Index num_params() const {
    return actor_gru_.num_params() + actor_.num_params() + critic_gru_.num_params() + critic_.num_params() +
           log_std_.size();
  }

  GruT<S>& actor_gru() { return actor_gru_; }
  const GruT<S>& actor_gru() const { return actor_gru_; }
  MlpT<S>& actor() { return actor_; }
  const MlpT<S>& actor() const { return actor_; }
  GruT<S>& critic_gru() { return critic_gru_; }
  const GruT<S>& critic_gru() const { return critic_gru_; }
  MlpT<S>& critic() { return critic_; }
  const MlpT<S>& critic() const { return critic_; }
  Vec& log_std() { return log_std_; }
  const Vec& log_std() const { return log_std_; }
  S log_std_init() const { return log_std_init_; }

  // A zero state for n environments.
  State zero_state(Eigen::Index n) const;

  // One step of every environment: obs (critic_input_dim x n), starts (1 x n); advances `state`.
  ActResult act(const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const RowVec>& starts, State& state,
                Rng& rng) const;
  // V of one step from the critic's state without changing it (obs: critic_input_dim x n, h:
  // H x n, no reset: the observation continues the episode of h).
  RowVec value_step(const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const Mat>& h) const;
  // The deterministic policy's step: the mean action (act_dim x n) from obs (obs_dim x n);
  // advances the actor's state h (H x n).
  Mat deterministic_step(const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const RowVec>& starts, Mat& h) const;

  void set_matmul_precision(MatmulPrecision p) {
    actor_.set_matmul_precision(p);
    critic_.set_matmul_precision(p);
  }

  Grad zero_grad() const;
  // Blocks in the order actor GRU, actor MLP, critic GRU, critic MLP, log_std.
  std::vector<AdamBlock<S>> adam_blocks(const Grad& grad);

 private:
  GruT<S> actor_gru_;
  MlpT<S> actor_;
  GruT<S> critic_gru_;
  MlpT<S> critic_;
  Vec log_std_;
  S log_std_init_ = S(0);
};

using RecurrentActorCritic = RecurrentActorCriticT<float>;
using RecurrentState = RecurrentStateT<float>;

extern template class RecurrentActorCriticT<float>;
extern template class RecurrentActorCriticT<double>;

}  // namespace codesign::rl
