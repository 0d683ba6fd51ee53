#include "bench/scaling_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cluster/env_assignment.hpp"

namespace codesign::cluster {

std::size_t collection_rounds(std::size_t environments, int ranks, int threads) {
  if (threads < 1) throw std::invalid_argument("collection_rounds: threads < 1");
  const std::size_t busiest = env_slice(environments, 0, ranks).count;  // rank 0 holds a largest slice
  // ⌈busiest / t⌉ rounds of one environment each when busiest ≥ t, else one round on `busiest` threads.
  const auto t = static_cast<std::size_t>(threads);
  return (busiest + t - 1) / t;
}

double iteration_seconds(const ScalingCosts& c, int ranks) {
  if (c.threads_per_rank < 1) throw std::invalid_argument("iteration_seconds: threads_per_rank < 1");
  if (c.env_collect_s < 0 || c.exchange_s < 0 || c.update_s < 0 || c.policy_s < 0 || c.distribution_s < 0 ||
      c.exchanges < 0 || !(c.collect_factor >= 0.0) || !(c.update_minibatches >= 0.0) ||
      !(c.gradient_transfer_s >= 0.0) || !(c.update_share_cost >= 0.0) || !(c.prestart_s >= 0.0))
    throw std::invalid_argument("iteration_seconds: a negative cost");
  const double rounds = static_cast<double>(collection_rounds(c.environments, ranks, c.threads_per_rank));
  const double collect = c.collect_factor * rounds * c.env_collect_s + (ranks - 1) * c.exchanges * c.exchange_s;
  const double gradient_messages =
      c.update_minibatches * 2.0 * static_cast<double>(ranks - 1) / ranks * c.gradient_transfer_s;
  const double update = c.update_spread ? c.update_share_cost * c.update_s / ranks + gradient_messages : c.update_s;
  return collect + std::max(update, ranks > 1 ? c.prestart_s : 0.0) + c.policy_s + c.distribution_s;
}

double projected_run_seconds(const std::vector<RunIteration>& run, std::size_t environments, int run_threads,
                             int ranks, int threads, double F, double P) {
  if (run.empty()) throw std::invalid_argument("projected_run_seconds: no iterations");
  if (!(F >= 0.0) || !(P >= 0.0) || !std::isfinite(F) || !std::isfinite(P))
    throw std::invalid_argument("projected_run_seconds: F or P negative or not finite");
  if (ranks < 1 || static_cast<std::size_t>(ranks) > environments)
    throw std::invalid_argument("projected_run_seconds: ranks outside 1 .. environments");
  const double scale = static_cast<double>(collection_rounds(environments, ranks, threads)) /
                       static_cast<double>(collection_rounds(environments, 1, run_threads));
  double total = 0.0;
  for (const RunIteration& i : run) {
    if (!(i.collect_s >= 0.0) || !(i.policy_s >= 0.0) || !(i.update_s >= 0.0) || !std::isfinite(i.collect_s) ||
        !std::isfinite(i.policy_s) || !std::isfinite(i.update_s))
      throw std::invalid_argument("projected_run_seconds: a negative or non-finite time");
    const double s = scale * std::max(0.0, i.collect_s - i.policy_s);
    total += F * s + i.policy_s + std::max(i.update_s, ranks > 1 ? P * s : 0.0);
  }
  return total;
}

}  // namespace codesign::cluster
