#include "rl/ppo.hpp"

#include "base/config_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

#include "rl/gaussian.hpp"
#include "rl/ppo_stats_sum.hpp"

namespace codesign::rl {

PpoConfig paper_ppo_config() {
  PpoConfig c;
  c.learning_rate = 3e-3;
  c.n_steps = 50;
  c.batch_size = 256;
  c.n_epochs = 10;
  c.gamma = 0.99;
  c.gae_lambda = 0.95;
  c.clip_range = 0.2;
  c.ent_coef = 0.01;
  c.ent_decay_start = 220'000;
  c.ent_decay_end = 800'000;
  c.vf_coef = 0.6;
  c.max_grad_norm = 0.5;
  c.target_kl = 0.02;
  c.actor_hidden = {512, 512, 512};
  c.critic_hidden = {512, 512, 512};
  return c;
}

double entropy_coef_at(const PpoConfig& config, std::int64_t num_timesteps) {
  if (!config.ent_decay_start || !config.ent_decay_end) return config.ent_coef;
  const auto t0 = *config.ent_decay_start, t1 = *config.ent_decay_end;
  if (num_timesteps <= t0) return config.ent_coef;
  if (num_timesteps >= t1) return 0.0;
  return config.ent_coef * static_cast<double>(t1 - num_timesteps) / static_cast<double>(t1 - t0);
}

double learning_rate_at(const PpoConfig& config, std::int64_t num_timesteps) {
  if (!config.lr_decay_start || !config.lr_decay_end) return config.learning_rate;
  const auto t0 = *config.lr_decay_start, t1 = *config.lr_decay_end;
  if (num_timesteps <= t0) return config.learning_rate;
  if (num_timesteps >= t1) return config.learning_rate_final;
  const double f = static_cast<double>(num_timesteps - t0) / static_cast<double>(t1 - t0);
  return config.learning_rate + f * (config.learning_rate_final - config.learning_rate);
}

void validate(const PpoConfig& config) {
  PpoConfig c = config;  // the description takes the fields by reference
  if (const auto p = config::first_problem([&](auto& v) { describe_ppo_table(v, c); }))
    throw std::invalid_argument("PpoConfig: " + *p);
}

template <class S>
PpoLossT<S> ppo_loss_from_outputs(const Eigen::Ref<const typename PpoMinibatchT<S>::Mat>& mean_action,
                                  const Eigen::Ref<const typename PpoMinibatchT<S>::Mat>& values,
                                  const Eigen::Ref<const typename PpoMinibatchT<S>::Vec>& log_std,
                                  const PpoMinibatchT<S>& batch, const PpoLossCoefficients& coefs,
                                  PpoOutputGradT<S>* grad) {
  using RowVec = typename PpoMinibatchT<S>::RowVec;
  const Eigen::Index n = batch.actions.cols();
  if (n < 1 || batch.old_log_prob.size() != n || batch.advantages.size() != n || batch.returns.size() != n ||
      mean_action.cols() != n || values.rows() != 1 || values.cols() != n)
    throw std::invalid_argument("ppo_minibatch_loss: minibatch arrays disagree in length");
  const S inv_n = S(1) / S(n);

  // Advantages, normalised per minibatch with torch's unbiased std (SB3).
  RowVec adv = batch.advantages;
  if (coefs.normalize_advantage && n > 1) {
    const S mean = adv.mean();
    const S stddev = std::sqrt((adv.array() - mean).square().sum() / S(n - 1));
    adv = (adv.array() - mean) / (stddev + S(1e-8));
  }

  const RowVec log_prob = gaussian_log_prob<S>(mean_action, log_std, batch.actions);
  const RowVec log_ratio = log_prob - batch.old_log_prob;
  const RowVec ratio = log_ratio.array().exp();

  const S lo = S(1 - coefs.clip_range), hi = S(1 + coefs.clip_range);
  PpoLossT<S> out;
  RowVec d_logp(n);
  S pg_sum = 0, kl_sum = 0;
  Eigen::Index clipped = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const S r = ratio(j);
    const S surr1 = adv(j) * r;
    const S surr2 = adv(j) * std::clamp(r, lo, hi);
    // min(surr1, surr2): where surr1 is the smaller (or equal) one the gradient w.r.t. r is A;
    // otherwise the clipped branch is selected, which is constant in r outside [lo, hi] and equal
    // to surr1 inside it.
    pg_sum += std::min(surr1, surr2);
    d_logp(j) = surr1 <= surr2 ? -adv(j) * r * inv_n : S(0);
    if (std::abs(r - S(1)) > S(coefs.clip_range)) ++clipped;
    kl_sum += (r - S(1)) - log_ratio(j);
  }
  out.pg_loss = -pg_sum * inv_n;
  out.value_loss = (batch.returns - values.row(0)).squaredNorm() * inv_n;
  const S entropy = gaussian_entropy<S>(log_std);
  out.entropy_loss = -entropy;  // -mean(entropy); the entropy is the same for every sample
  out.loss = out.pg_loss + S(coefs.ent_coef) * out.entropy_loss + S(coefs.vf_coef) * out.value_loss;
  out.approx_kl = kl_sum * inv_n;
  out.clip_fraction = S(clipped) * inv_n;

  if (grad != nullptr) {
    grad->d_log_std.resize(log_std.size());
    grad->d_log_std.setZero();
    gaussian_log_prob_backward<S>(mean_action, log_std, batch.actions, d_logp, grad->d_mean, grad->d_log_std);
    gaussian_entropy_backward<S>(-S(coefs.ent_coef), grad->d_log_std);
    grad->d_value = (S(2 * coefs.vf_coef) * inv_n) * (values.row(0) - batch.returns);
  }
  return out;
}

template <class S>
PpoLossT<S> ppo_minibatch_loss(const ActorCriticT<S>& model, const PpoMinibatchT<S>& batch,
                               const PpoLossCoefficients& coefs, ActorCriticGradT<S>* grad,
                               PpoWorkspaceT<S>& ws) {
  const Eigen::Index n = batch.obs.cols();
  if (n < 1 || batch.actions.cols() != n)
    throw std::invalid_argument("ppo_minibatch_loss: minibatch arrays disagree in length");
  if (batch.obs.rows() != model.critic_input_dim())
    throw std::invalid_argument("ppo_minibatch_loss: observations have " + std::to_string(batch.obs.rows()) +
                                " rows, the model takes " + std::to_string(model.critic_input_dim()));
  // The actor reads the first obs_dim rows; the critic all (a privileged critic reads more).
  // The two networks' passes share no data: side by side when ws.pool has two threads.
  using Mat = typename MlpT<S>::Mat;
  const Mat* mean_action = nullptr;
  const Mat* values = nullptr;
  run_pair(
      ws.pool,
      [&] {
        mean_action = model.privileged_dim() == 0
                          ? &model.actor().forward(batch.obs, ws.actor_cache,
                                                   ws.actor_pending ? &ws.actor_pending : nullptr)
                          : &model.actor().forward(model.actor_rows(batch.obs), ws.actor_cache,
                                                   ws.actor_pending ? &ws.actor_pending : nullptr);
      },
      [&] {
        values = &model.critic().forward(batch.obs, ws.critic_cache, ws.critic_pending ? &ws.critic_pending : nullptr);
      });
  if (ws.log_std_pending) ws.log_std_pending();
  PpoLossT<S> out = ppo_loss_from_outputs<S>(*mean_action, *values, model.log_std(), batch, coefs,
                                             grad ? &ws.outputs : nullptr);
  if (grad != nullptr) {
    grad->log_std = ws.outputs.d_log_std;
    double actor_sq = 0.0, critic_sq = 0.0;
    run_pair(
        ws.pool, [&] { actor_sq = model.actor().backward(ws.actor_cache, ws.outputs.d_mean, grad->actor); },
        [&] { critic_sq = model.critic().backward(ws.critic_cache, ws.outputs.d_value, grad->critic); });
    out.grad_squared_norm = actor_sq + critic_sq + static_cast<double>(grad->log_std.squaredNorm());
  }
  return out;
}

template PpoLossT<float> ppo_loss_from_outputs<float>(
    const Eigen::Ref<const PpoMinibatchT<float>::Mat>&, const Eigen::Ref<const PpoMinibatchT<float>::Mat>&,
    const Eigen::Ref<const PpoMinibatchT<float>::Vec>&, const PpoMinibatchT<float>&, const PpoLossCoefficients&,
    PpoOutputGradT<float>*);
template PpoLossT<double> ppo_loss_from_outputs<double>(
    const Eigen::Ref<const PpoMinibatchT<double>::Mat>&, const Eigen::Ref<const PpoMinibatchT<double>::Mat>&,
    const Eigen::Ref<const PpoMinibatchT<double>::Vec>&, const PpoMinibatchT<double>&, const PpoLossCoefficients&,
    PpoOutputGradT<double>*);
template PpoLossT<float> ppo_minibatch_loss<float>(const ActorCriticT<float>&,
                                                   const PpoMinibatchT<float>&,
                                                   const PpoLossCoefficients&,
                                                   ActorCriticGradT<float>*, PpoWorkspaceT<float>&);
template PpoLossT<double> ppo_minibatch_loss<double>(const ActorCriticT<double>&,
                                                     const PpoMinibatchT<double>&,
                                                     const PpoLossCoefficients&,
                                                     ActorCriticGradT<double>*,
                                                     PpoWorkspaceT<double>&);

double explained_variance(const Eigen::RowVectorXf& y_pred, const Eigen::RowVectorXf& y_true) {
  const Eigen::RowVectorXd t = y_true.cast<double>();
  const Eigen::RowVectorXd d = t - y_pred.cast<double>();
  const double var_y = (t.array() - t.mean()).square().mean();
  if (var_y == 0) return std::numeric_limits<double>::quiet_NaN();
  return 1.0 - (d.array() - d.mean()).square().mean() / var_y;
}

PpoStats ppo_update(ActorCritic& model, Adam& optimizer, const RolloutBuffer& buffer,
                    const PpoConfig& config, std::int64_t num_timesteps, Rng& rng,
                    bool defer_optimizer_step, ThreadPool* pool) {
  validate(config);
  if (!buffer.full()) throw std::logic_error("ppo_update: rollout buffer is not full");
  const Eigen::Index n = buffer.size();
  PpoStats stats;
  stats.ent_coef = entropy_coef_at(config, num_timesteps);
  const double lr = learning_rate_at(config, num_timesteps);
  stats.explained_variance = explained_variance(buffer.values(), buffer.returns());
  const PpoLossCoefficients coefs{config.clip_range, stats.ent_coef, config.vf_coef,
                                  config.normalize_advantage};

  std::vector<Eigen::Index> perm(static_cast<std::size_t>(n));
  PpoMinibatchT<float> mb;
  PpoWorkspaceT<float> ws;
  ws.pool = pool;
  ActorCriticGrad grad = model.zero_grad();
  const auto blocks = model.adam_blocks(grad);
  PpoStatsSum sums;

  for (int epoch = 0; epoch < config.n_epochs && !stats.early_stopped; ++epoch) {
    ++stats.epochs_done;
    sums.begin_epoch();  // the logged approx_kl is the last epoch's (SB3)
    std::iota(perm.begin(), perm.end(), Eigen::Index{0});
    for (Eigen::Index i = n - 1; i > 0; --i)  // Fisher-Yates
      std::swap(perm[static_cast<std::size_t>(i)],
                perm[rng.uniform_index(static_cast<std::uint64_t>(i) + 1)]);
    for (Eigen::Index start = 0; start < n; start += config.batch_size) {
      const Eigen::Index b = std::min<Eigen::Index>(config.batch_size, n - start);
      mb.obs.resize(buffer.obs_dim(), b);
      mb.actions.resize(buffer.act_dim(), b);
      mb.old_log_prob.resize(b);
      mb.advantages.resize(b);
      mb.returns.resize(b);
      for (Eigen::Index j = 0; j < b; ++j) {
        const Eigen::Index k = perm[static_cast<std::size_t>(start + j)];
        mb.obs.col(j) = buffer.observations().col(k);
        mb.actions.col(j) = buffer.actions().col(k);
        mb.old_log_prob(j) = buffer.log_probs()(k);
        mb.advantages(j) = buffer.advantages()(k);
        mb.returns(j) = buffer.returns()(k);
      }
      const PpoLossT<float> l = ppo_minibatch_loss<float>(model, mb, coefs, &grad, ws);
      if (optimizer.pending())  // the forward passes applied the previous step everywhere
        throw std::logic_error("ppo_update: optimiser step not fully applied by the forward pass");
      ws.actor_pending = nullptr;
      ws.critic_pending = nullptr;
      ws.log_std_pending = nullptr;
      sums.add(l);
      stats.loss = l.loss;
      if (config.target_kl && l.approx_kl > 1.5 * *config.target_kl) {
        stats.early_stopped = true;  // this minibatch is not applied (SB3 breaks before step)
        break;
      }
      const double norm = std::sqrt(l.grad_squared_norm);
      sums.norm += norm;
      const double clip_coef = config.max_grad_norm / (norm + 1e-6);
      // clip_grad_norm_ scales by clip_coef when it is < 1; Adam applies the factor as it reads
      // each gradient (one pass over memory instead of two).
      if (defer_optimizer_step) {
        optimizer.begin_step(blocks, lr, std::min(clip_coef, 1.0));
        ws.actor_pending = [&](Eigen::Index b, Eigen::Index e) { optimizer.apply(blocks, 0, b, e); };
        ws.critic_pending = [&](Eigen::Index b, Eigen::Index e) { optimizer.apply(blocks, 1, b, e); };
        ws.log_std_pending = [&] {
          optimizer.apply(blocks, 2, 0, blocks[2].size);
          apply_log_std_floor(config, model.log_std());
        };
      } else {
        optimizer.step(blocks, lr, std::min(clip_coef, 1.0));
        apply_log_std_floor(config, model.log_std());
      }
      ++stats.minibatches_applied;
    }
  }
  if (optimizer.pending()) {  // the last step: no forward pass follows
    for (std::size_t i = 0; i < blocks.size(); ++i) optimizer.apply(blocks, i, 0, blocks[i].size);
    apply_log_std_floor(config, model.log_std());
  }
  sums.finish(stats);
  return stats;
}

}  // namespace codesign::rl
