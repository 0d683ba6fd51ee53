#include "cluster/idle_pause.hpp"

#include <algorithm>
#include <cmath>

namespace codesign::cluster {

double idle_pause_seconds(double waited_s, const IdlePause& rule) {
  const double p = std::sqrt(2.0 * rule.wake_cost_s * std::max(0.0, waited_s));
  return std::clamp(p, rule.min_s, rule.max_s);
}

}  // namespace codesign::cluster
