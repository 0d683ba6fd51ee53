#include "run/distribution_summary.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace codesign::run {

DistributionSummary summarize(const core::DesignDistribution& dist, std::int64_t t) {
  DistributionSummary s;
  s.phase = dist.phase(t);
  s.entropy = dist.entropy(t);
  s.target_entropy = dist.target_entropy(t);
  s.q = dist.probabilities(t);
  std::vector<int> order(static_cast<std::size_t>(s.q.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return s.q[a] > s.q[b]; });
  for (std::size_t i = 0; i < s.top.size() && i < order.size(); ++i) s.top[i] = order[i];
  s.best = dist.leading_design();
  s.best_score = dist.state().score[s.best];
  s.mu = dist.mean_pressures_kPa(s.best);
  s.sigma = dist.sigma_pressures_kPa(s.best);
  return s;
}

}  // namespace codesign::run
