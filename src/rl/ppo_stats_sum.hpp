#pragma once
// The running sums behind PpoStats, shared by ppo_update (ppo.cpp) and recurrent_ppo_update
// (recurrent_ppo.cpp) so both log the same way: losses averaged over every minibatch processed
// (the early-stopping one included, as SB3 logs before breaking), approx_kl over the minibatches
// of the last epoch only (SB3 resets its list every epoch), grad_norm over the applied steps.
#include "rl/ppo_stats.hpp"

namespace codesign::rl {

struct PpoStatsSum {
  double pg = 0, value = 0, entropy = 0, kl = 0, clip = 0, norm = 0;
  int losses = 0, kls = 0;

  void begin_epoch() {
    kl = 0;
    kls = 0;
  }
  template <class Loss>
  void add(const Loss& l) {
    pg += l.pg_loss;
    value += l.value_loss;
    entropy += l.entropy_loss;
    kl += l.approx_kl;
    ++kls;
    clip += l.clip_fraction;
    ++losses;
  }
  // Writes the averages into stats (minibatches_applied must already be counted there).
  void finish(PpoStats& stats) const {
    if (losses > 0) {
      stats.pg_loss = pg / losses;
      stats.value_loss = value / losses;
      stats.entropy_loss = entropy / losses;
      stats.approx_kl = kl / kls;
      stats.clip_fraction = clip / losses;
    }
    if (stats.minibatches_applied > 0) stats.grad_norm = norm / stats.minibatches_applied;
  }
};

}  // namespace codesign::rl
