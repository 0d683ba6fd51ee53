#pragma once
// What one PPO update logs (ppo_update, recurrent_ppo_update).
namespace codesign::rl {

// Averages over all minibatches processed (as SB3 logs them), except approx_kl, which is the mean
// over the minibatches of the LAST epoch (SB3 resets its list every epoch), and
// explained_variance, which is over the whole buffer: 1 - Var(returns - values) / Var(returns)
// (NaN if Var(returns) = 0). The early-stopping minibatch is included (SB3 logs before breaking).
struct PpoStats {
  double pg_loss = 0.0;
  double value_loss = 0.0;
  double entropy_loss = 0.0;  // -mean entropy, as SB3 logs "train/entropy_loss"
  double approx_kl = 0.0;
  double clip_fraction = 0.0;
  double loss = 0.0;  // loss of the last minibatch (SB3 logs that one)
  double explained_variance = 0.0;
  double ent_coef = 0.0;  // coefficient used in this update
  double grad_norm = 0.0;  // mean pre-clip global gradient norm
  int epochs_done = 0;     // epochs started (the one that early-stopped counts, as SB3's n_updates)
  int minibatches_applied = 0;  // Adam steps taken
  bool early_stopped = false;
};

}  // namespace codesign::rl
