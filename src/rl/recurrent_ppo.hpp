#pragma once
// The PPO update of the recurrent actor-critic (recurrent_actor_critic.hpp): the loss of
// ppo.hpp (ppo_loss_from_outputs: clipped surrogate, value loss, entropy, per-minibatch
// advantage normalisation) with minibatches of whole SEQUENCES instead of shuffled samples, and
// back-propagation through time over each sequence.
//
// A sequence is one environment's column of the rollout buffer: its n_steps transitions in order,
// the buffer's episode_starts as reset masks (an episode that begins inside the column starts
// from a zero state there, and no gradient flows across that point), and the hidden states the
// rollout started that column from (initial_state; zero in the co-design, whose columns are each
// one episode from reset, and whatever the previous rollout left in the gym trainer, whose
// environments continue across rollouts; SB3-contrib's RecurrentRolloutBuffer stores them too).
// SB3-contrib instead cuts columns at episode starts and pads the pieces; with the reset masks
// the gradient is the same and nothing needs padding.
//
// Each epoch draws a random permutation of the environments and cuts it into minibatches of
// sequences_per_minibatch() sequences (about batch_size samples; the last minibatch may hold
// fewer sequences). Everything else is ppo_update's: target_kl early stop before the step, one
// global gradient norm over all five parameter blocks clipped to max_grad_norm, one Adam step,
// the same logged statistics. The optimiser step is applied at once (no deferral: the GRU's
// sequential forward pass is not laid out for it).
#include <cstdint>

#include <Eigen/Core>

#include "rl/adam.hpp"
#include "rl/gru.hpp"
#include "rl/mlp.hpp"
#include "rl/ppo.hpp"
#include "rl/recurrent_actor_critic.hpp"
#include "rl/rng.hpp"
#include "rl/rollout_buffer.hpp"

namespace codesign::rl {

template <class S>
struct RecurrentMinibatchT {
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using RowVec = Eigen::Matrix<S, 1, Eigen::Dynamic>;
  PpoMinibatchT<S> samples;  // steps·B columns, column t·B + b = step t of sequence b
  RowVec starts;             // 1 x steps·B, 1 where an episode begins (the state is zeroed first)
  Mat h0_actor, h0_critic;   // H x B: the states each sequence started from
  Eigen::Index steps = 0;
};

template <class S>
struct RecurrentWorkspaceT {
  typename GruT<S>::Cache actor_gru_cache, critic_gru_cache;
  typename MlpT<S>::Cache actor_cache, critic_cache;
  PpoOutputGradT<S> outputs;
  typename MlpT<S>::Mat d_actor_h, d_critic_h;
  ThreadPool* pool = nullptr;  // as PpoWorkspaceT::pool: actor and critic side by side; not owned
};

// Loss of one minibatch of sequences and, if grad is non-null, its gradient w.r.t. every
// parameter (overwrites *grad, sized as model.zero_grad()); grad_squared_norm is set with it.
template <class S>
PpoLossT<S> recurrent_minibatch_loss(const RecurrentActorCriticT<S>& model, const RecurrentMinibatchT<S>& batch,
                                     const PpoLossCoefficients& coefs, RecurrentActorCriticGradT<S>* grad,
                                     RecurrentWorkspaceT<S>& workspace);

extern template PpoLossT<float> recurrent_minibatch_loss<float>(const RecurrentActorCriticT<float>&,
                                                                const RecurrentMinibatchT<float>&,
                                                                const PpoLossCoefficients&,
                                                                RecurrentActorCriticGradT<float>*,
                                                                RecurrentWorkspaceT<float>&);
extern template PpoLossT<double> recurrent_minibatch_loss<double>(const RecurrentActorCriticT<double>&,
                                                                  const RecurrentMinibatchT<double>&,
                                                                  const PpoLossCoefficients&,
                                                                  RecurrentActorCriticGradT<double>*,
                                                                  RecurrentWorkspaceT<double>&);

// Sequences per minibatch: batch_size / n_steps rounded down, at least 1, at most n_envs.
int sequences_per_minibatch(const PpoConfig& config, int n_envs);

// The whole optimisation phase on a full buffer (advantages and returns computed).
// pool: as ppo_update's (actor and critic side by side, bit-identical to null).
// initial_state: the hidden states (H x n_envs) the rollout began from.
PpoStats recurrent_ppo_update(RecurrentActorCritic& model, Adam& optimizer, const RolloutBuffer& buffer,
                              const RecurrentState& initial_state, const PpoConfig& config,
                              std::int64_t num_timesteps, Rng& rng, ThreadPool* pool = nullptr);

}  // namespace codesign::rl
