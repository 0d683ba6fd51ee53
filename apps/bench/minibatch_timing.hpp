#pragma once
// Timing helpers shared by `bench ppo` and `bench cluster`: the median of a list of times, and the
// wall time of one PPO minibatch's loss and gradient (rl::ppo_minibatch_loss), on one thread.
#include <algorithm>
#include <chrono>
#include <vector>

#include "base/seconds_since.hpp"
#include "rl/ppo.hpp"

namespace codesign::app {

// The middle value (the mean of the two middle ones for an even count); `v` must not be empty.
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Median wall seconds of `reps` calls of `pass`, after `warmup` untimed ones.
template <class Pass>
double median_seconds(Pass&& pass, int warmup, int reps) {
  for (int r = 0; r < warmup; ++r) pass();
  std::vector<double> times;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    pass();
    times.push_back(seconds_since(t0));
  }
  return median(times);
}

// Median wall seconds of `reps` passes of the minibatch's loss and gradient w.r.t. all parameters,
// after `warmup` untimed passes with the same workspace (its caches then hold their sizes).
template <class S>
double minibatch_loss_seconds(const rl::ActorCriticT<S>& model, const rl::PpoMinibatchT<S>& batch,
                              const rl::PpoLossCoefficients& coefs, int warmup, int reps) {
  rl::PpoWorkspaceT<S> ws;
  auto grad = model.zero_grad();
  return median_seconds([&] { rl::ppo_minibatch_loss<S>(model, batch, coefs, &grad, ws); }, warmup, reps);
}

}  // namespace codesign::app
