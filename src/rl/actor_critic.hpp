#pragma once
// Actor-critic policy as SB3's ActorCriticPolicy with separate networks (share_features_extractor
// = False, net_arch = dict(pi=[...], vf=[...])) and a state-independent log-std:
//   actor:  obs -> tanh hidden layers -> linear -> action mean     (head init gain 0.01)
//   critic: obs -> tanh hidden layers -> linear -> V(obs)          (head init gain 1)
//   log_std: act_dim free parameters, initialised to log_std_init (SB3 default 0).
// Hidden layers use orthogonal init with gain sqrt(2); all biases start at zero (SB3 ortho_init).
//
// Privileged critic (asymmetric actor-critic, ours: PpoConfig::privileged_critic): with
// privileged_dim = m > 0 the critic reads obs_dim + m inputs, the actor's obs_dim followed by m
// features only the training environment knows. Batches given to act(), value() and the PPO
// loss then have obs_dim + m rows (critic_input_dim()) and the actor reads the first obs_dim;
// the deterministic policy reads obs_dim rows, so evaluation never sees the extra features.
//
// Batches are column-per-sample: observations (obs_dim x B), actions (act_dim x B).
// Actions are returned UNCLIPPED (SB3 stores the unclipped sample in the rollout buffer; the
// collector clips to the action bounds before stepping the environment).
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rl/adam.hpp"
#include "rl/mlp.hpp"
#include "rl/rng.hpp"

namespace codesign::rl {

// Gradient of a scalar loss with respect to every parameter of an ActorCriticT.
template <class S>
struct ActorCriticGradT {
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  Vec actor;    // same layout as ActorCriticT::actor().params()
  Vec critic;   // same layout as ActorCriticT::critic().params()
  Vec log_std;  // act_dim
  // (Its squared norm comes from MlpT::backward; clipping is folded into the Adam step.)
};

template <class S>
class ActorCriticT {
 public:
  using Scalar = S;
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using RowVec = Eigen::Matrix<S, 1, Eigen::Dynamic>;
  using Grad = ActorCriticGradT<S>;

  struct ActResult {
    Mat actions;     // act_dim x B, unclipped samples
    RowVec values;   // 1 x B, V(obs)
    RowVec log_probs;  // 1 x B, log pi(actions | obs)
  };

  ActorCriticT() = default;
  // Networks have the given hidden sizes; parameters are zero and log_std = log_std_init until
  // init_orthogonal() is called.
  ActorCriticT(int obs_dim, int act_dim, const std::vector<int>& actor_hidden,
               const std::vector<int>& critic_hidden, S log_std_init = S(0), int privileged_dim = 0);

  // SB3's orthogonal init (see top of file); also resets log_std to log_std_init. The actor is
  // initialised first, then the critic, from the same rng.
  void init_orthogonal(Rng& rng);

  int obs_dim() const { return actor_.input_dim(); }
  // Rows of a batch for act(), value() and the PPO loss: obs_dim() + privileged_dim().
  int critic_input_dim() const { return critic_.input_dim(); }
  int privileged_dim() const { return critic_.input_dim() - actor_.input_dim(); }
  // A copy of the actor's rows of a batch of critic_input_dim() rows (callers use it only when
  // privileged_dim() > 0; otherwise the batch is the actor's input as it is).
  Mat actor_rows(const Eigen::Ref<const Mat>& obs) const { return obs.topRows(obs_dim()); }
  int act_dim() const { return actor_.output_dim(); }
  Eigen::Index num_params() const {
    return actor_.num_params() + critic_.num_params() + log_std_.size();
  }

  MlpT<S>& actor() { return actor_; }
  const MlpT<S>& actor() const { return actor_; }
  MlpT<S>& critic() { return critic_; }
  const MlpT<S>& critic() const { return critic_; }
  Vec& log_std() { return log_std_; }
  const Vec& log_std() const { return log_std_; }
  S log_std_init() const { return log_std_init_; }

  // Scratch of the forward passes of act()/value(), reused across calls: activations are not
  // reallocated and the packed bf16 weights are kept between calls. Call weights_changed()
  // whenever the parameters change (the trainer does at the start of every rollout).
  struct InferenceCache {
    InferenceCache() {
      actor.keep_transposed_weights = critic.keep_transposed_weights = false;
      actor.reuse_packed_weights = critic.reuse_packed_weights = true;
    }
    void weights_changed() {
      actor.weights_changed();
      critic.weights_changed();
    }
    typename MlpT<S>::Cache actor, critic;
  };

  // Samples actions for a batch of observations (rng draws as in gaussian_sample).
  ActResult act(const Eigen::Ref<const Mat>& obs, Rng& rng) const;
  ActResult act(const Eigen::Ref<const Mat>& obs, Rng& rng, InferenceCache& cache) const;
  // The same with the standard normals given (gaussian_sample_with): act(obs, rng, cache) equals
  // act_with(obs, standard_normals(act_dim, B, rng), cache).
  ActResult act_with(const Eigen::Ref<const Mat>& obs, const Eigen::Ref<const Eigen::MatrixXd>& normals,
                     InferenceCache& cache) const;
  // V(obs) for a batch (1 x B).
  RowVec value(const Eigen::Ref<const Mat>& obs) const;
  RowVec value(const Eigen::Ref<const Mat>& obs, InferenceCache& cache) const;
  // Mean action (the deterministic policy), unclipped.
  Vec deterministic_action(const Eigen::Ref<const Vec>& obs) const;
  Mat deterministic_actions(const Eigen::Ref<const Mat>& obs) const;

  // Enables/disables the fast float32 GEMM in both networks (see MlpT::set_fast_gemm).
  void set_fast_gemm(bool on) {
    actor_.set_fast_gemm(on);
    critic_.set_fast_gemm(on);
  }

  // Arithmetic of the large products in both networks (see MlpT::set_matmul_precision).
  void set_matmul_precision(MatmulPrecision p) {
    actor_.set_matmul_precision(p);
    critic_.set_matmul_precision(p);
  }

  // A zero gradient of the right sizes.
  Grad zero_grad() const;
  // Parameter/gradient blocks for AdamT::step, in the order actor, critic, log_std.
  std::vector<AdamBlock<S>> adam_blocks(const Grad& grad);

 private:
  MlpT<S> actor_;
  MlpT<S> critic_;
  Vec log_std_;
  S log_std_init_ = S(0);
};

using ActorCritic = ActorCriticT<float>;
using ActorCriticGrad = ActorCriticGradT<float>;

extern template class ActorCriticT<float>;
extern template class ActorCriticT<double>;

}  // namespace codesign::rl
