#pragma once
// The values of a range {from, to, step}: from + k·step for k = 0, 1, … up to `to`, which is
// included when it lies on the grid to within 1e-9 of a step. Each value is computed from k, so
// no rounding error accumulates along the range.
#include <cmath>
#include <stdexcept>
#include <vector>

namespace codesign {

inline constexpr int kGridValuesMax = 10000;

// std::invalid_argument with the problem ("step must be > 0", "from must not exceed to", "more
// than 10000 values") for a range that gives no finite list.
inline std::vector<double> grid_values(double from, double to, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) throw std::invalid_argument("step must be > 0");
  if (!std::isfinite(from) || !std::isfinite(to) || !(from <= to)) throw std::invalid_argument("from must not exceed to");
  const double k_last = std::floor((to - from) / step + 1e-9);
  if (k_last >= kGridValuesMax) throw std::invalid_argument("more than 10000 values");
  std::vector<double> v;
  for (int k = 0; k <= static_cast<int>(k_last); ++k) v.push_back(from + step * k);
  return v;
}

}  // namespace codesign
