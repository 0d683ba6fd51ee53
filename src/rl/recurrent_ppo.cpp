#include "rl/recurrent_ppo.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "rl/ppo_stats_sum.hpp"

namespace codesign::rl {

template <class S>
PpoLossT<S> recurrent_minibatch_loss(const RecurrentActorCriticT<S>& model, const RecurrentMinibatchT<S>& batch,
                                     const PpoLossCoefficients& coefs, RecurrentActorCriticGradT<S>* grad,
                                     RecurrentWorkspaceT<S>& ws) {
  const PpoMinibatchT<S>& mb = batch.samples;
  const Eigen::Index n = mb.obs.cols();
  if (batch.steps < 1 || n % batch.steps != 0 || batch.starts.size() != n ||
      batch.h0_actor.cols() * batch.steps != n || batch.h0_critic.cols() != batch.h0_actor.cols())
    throw std::invalid_argument("recurrent_minibatch_loss: sequences, masks and initial states disagree");
  if (mb.obs.rows() != model.critic_input_dim())
    throw std::invalid_argument("recurrent_minibatch_loss: observations have " + std::to_string(mb.obs.rows()) +
                                " rows, the model takes " + std::to_string(model.critic_input_dim()));
  // The actor's GRU reads the first obs_dim rows, the critic's all of them. The actor's and the
  // critic's passes share no data: side by side when ws.pool has two threads.
  using Mat = typename MlpT<S>::Mat;
  const Mat* mean_action = nullptr;
  const Mat* values = nullptr;
  run_pair(
      ws.pool,
      [&] {
        const auto& h = model.actor_gru().forward(mb.obs.topRows(model.obs_dim()), batch.starts, batch.h0_actor,
                                                  batch.steps, ws.actor_gru_cache);
        mean_action = &model.actor().forward(h, ws.actor_cache);
      },
      [&] {
        const auto& h = model.critic_gru().forward(mb.obs, batch.starts, batch.h0_critic, batch.steps,
                                                   ws.critic_gru_cache);
        values = &model.critic().forward(h, ws.critic_cache);
      });
  PpoLossT<S> out =
      ppo_loss_from_outputs<S>(*mean_action, *values, model.log_std(), mb, coefs, grad ? &ws.outputs : nullptr);
  if (grad != nullptr) {
    grad->log_std = ws.outputs.d_log_std;
    double actor_sq = 0.0, actor_gru_sq = 0.0, critic_sq = 0.0, critic_gru_sq = 0.0;
    run_pair(
        ws.pool,
        [&] {
          actor_sq = model.actor().backward(ws.actor_cache, ws.outputs.d_mean, grad->actor, &ws.d_actor_h);
          actor_gru_sq = model.actor_gru().backward(ws.actor_gru_cache, ws.d_actor_h, grad->actor_gru);
        },
        [&] {
          critic_sq = model.critic().backward(ws.critic_cache, ws.outputs.d_value, grad->critic, &ws.d_critic_h);
          critic_gru_sq = model.critic_gru().backward(ws.critic_gru_cache, ws.d_critic_h, grad->critic_gru);
        });
    out.grad_squared_norm =
        actor_sq + actor_gru_sq + critic_sq + critic_gru_sq + static_cast<double>(grad->log_std.squaredNorm());
  }
  return out;
}

template PpoLossT<float> recurrent_minibatch_loss<float>(const RecurrentActorCriticT<float>&,
                                                         const RecurrentMinibatchT<float>&,
                                                         const PpoLossCoefficients&,
                                                         RecurrentActorCriticGradT<float>*,
                                                         RecurrentWorkspaceT<float>&);
template PpoLossT<double> recurrent_minibatch_loss<double>(const RecurrentActorCriticT<double>&,
                                                           const RecurrentMinibatchT<double>&,
                                                           const PpoLossCoefficients&,
                                                           RecurrentActorCriticGradT<double>*,
                                                           RecurrentWorkspaceT<double>&);

namespace {

// Adam's step over the blocks on two threads of `pool` (or on the caller): the update is element
// by element, so splitting the blocks into two groups of about equal size changes no result.
void adam_step_in_pair(Adam& optimizer, std::span<const AdamBlock<float>> blocks, double lr, double grad_scale,
                       ThreadPool* pool) {
  optimizer.begin_step(blocks, lr, grad_scale);
  Eigen::Index total = 0;
  for (const auto& b : blocks) total += b.size;
  std::size_t split = 0;
  for (Eigen::Index first = 0; split < blocks.size() && 2 * (first + blocks[split].size) <= total; ++split)
    first += blocks[split].size;
  run_pair(
      pool,
      [&] {
        for (std::size_t i = 0; i < split; ++i) optimizer.apply(blocks, i, 0, blocks[i].size);
      },
      [&] {
        for (std::size_t i = split; i < blocks.size(); ++i) optimizer.apply(blocks, i, 0, blocks[i].size);
      });
}

}  // namespace

int sequences_per_minibatch(const PpoConfig& config, int n_envs) {
  return std::clamp(config.batch_size / std::max(config.n_steps, 1), 1, std::max(n_envs, 1));
}

PpoStats recurrent_ppo_update(RecurrentActorCritic& model, Adam& optimizer, const RolloutBuffer& buffer,
                              const RecurrentState& initial_state, const PpoConfig& config,
                              std::int64_t num_timesteps, Rng& rng, ThreadPool* pool) {
  validate(config);
  if (!buffer.full()) throw std::logic_error("recurrent_ppo_update: rollout buffer is not full");
  const int n_envs = buffer.n_envs(), steps = buffer.n_steps();
  const Eigen::Index h = model.gru_hidden();
  if (initial_state.actor.rows() != h || initial_state.actor.cols() != n_envs ||
      initial_state.critic.rows() != h || initial_state.critic.cols() != n_envs)
    throw std::invalid_argument("recurrent_ppo_update: one initial state column per environment expected");
  PpoStats stats;
  stats.ent_coef = entropy_coef_at(config, num_timesteps);
  const double lr = learning_rate_at(config, num_timesteps);
  stats.explained_variance = explained_variance(buffer.values(), buffer.returns());
  const PpoLossCoefficients coefs{config.clip_range, stats.ent_coef, config.vf_coef, config.normalize_advantage};
  const int per_batch = sequences_per_minibatch(config, n_envs);

  std::vector<int> perm(static_cast<std::size_t>(n_envs));
  RecurrentMinibatchT<float> mb;
  mb.steps = steps;
  RecurrentWorkspaceT<float> ws;
  ws.pool = pool;
  RecurrentActorCritic::Grad grad = model.zero_grad();
  const auto blocks = model.adam_blocks(grad);
  PpoStatsSum sums;

  for (int epoch = 0; epoch < config.n_epochs && !stats.early_stopped; ++epoch) {
    ++stats.epochs_done;
    sums.begin_epoch();  // the logged approx_kl is the last epoch's (SB3)
    std::iota(perm.begin(), perm.end(), 0);
    for (int i = n_envs - 1; i > 0; --i)  // Fisher-Yates over the environments
      std::swap(perm[static_cast<std::size_t>(i)], perm[rng.uniform_index(static_cast<std::uint64_t>(i) + 1)]);
    for (int start = 0; start < n_envs; start += per_batch) {
      const int b = std::min(per_batch, n_envs - start);
      const Eigen::Index cols = Eigen::Index{b} * steps;
      PpoMinibatchT<float>& s = mb.samples;
      s.obs.resize(buffer.obs_dim(), cols);
      s.actions.resize(buffer.act_dim(), cols);
      s.old_log_prob.resize(cols);
      s.advantages.resize(cols);
      s.returns.resize(cols);
      mb.starts.resize(cols);
      mb.h0_actor.resize(h, b);
      mb.h0_critic.resize(h, b);
      for (int j = 0; j < b; ++j) {
        const int e = perm[static_cast<std::size_t>(start + j)];
        mb.h0_actor.col(j) = initial_state.actor.col(e);
        mb.h0_critic.col(j) = initial_state.critic.col(e);
        for (int t = 0; t < steps; ++t) {
          const Eigen::Index k = Eigen::Index{t} * n_envs + e, c = Eigen::Index{t} * b + j;
          s.obs.col(c) = buffer.observations().col(k);
          s.actions.col(c) = buffer.actions().col(k);
          s.old_log_prob(c) = buffer.log_probs()(k);
          s.advantages(c) = buffer.advantages()(k);
          s.returns(c) = buffer.returns()(k);
          mb.starts(c) = buffer.episode_starts()(k);
        }
      }
      const PpoLossT<float> l = recurrent_minibatch_loss<float>(model, mb, coefs, &grad, ws);
      sums.add(l);
      stats.loss = l.loss;
      if (config.target_kl && l.approx_kl > 1.5 * *config.target_kl) {
        stats.early_stopped = true;  // this minibatch is not applied
        break;
      }
      const double norm = std::sqrt(l.grad_squared_norm);
      sums.norm += norm;
      const double clip_coef = config.max_grad_norm / (norm + 1e-6);
      adam_step_in_pair(optimizer, blocks, lr, std::min(clip_coef, 1.0), pool);
      apply_log_std_floor(config, model.log_std());
      ++stats.minibatches_applied;
    }
  }
  sums.finish(stats);
  return stats;
}

}  // namespace codesign::rl
