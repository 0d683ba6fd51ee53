#include "fem/design.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace codesign::fem {
namespace {

constexpr double kLMin = 20.0, kLStep = 2.0, kWMin = 2.0, kWStep = 0.5;
constexpr double kGridTol = 1e-9;

// The grid position of `v` on {lo, lo+step, ...} with `count` values, or -1 if off the grid.
int grid_position(double v, double lo, double step, int count) {
  const double k = (v - lo) / step;
  const double r = std::round(k);
  if (std::abs(k - r) * step > kGridTol || r < 0 || r >= count) return -1;
  return static_cast<int>(r);
}

}  // namespace

std::string design_label(int j) {
  const Design d = design_from_index(j);
  char buf[64];
  std::snprintf(buf, sizeof buf, "j%d {%d, %g mm, %g mm}", j, d.n, d.chamber_length_mm, d.wall_mm);
  return buf;
}

Design design_from_index(int j) {
  if (j < 0 || j >= kDesignCount) {
    throw std::out_of_range("design index " + std::to_string(j) + " outside 0.." +
                            std::to_string(kDesignCount - 1));
  }
  const int per_n = kChamberLengthCount * kWallCount;
  Design d;
  d.n = 1 + j / per_n;
  const int rest = j % per_n;
  d.chamber_length_mm = kLMin + kLStep * (rest / kWallCount);
  d.wall_mm = kWMin + kWStep * (rest % kWallCount);
  return d;
}

int index_of(const Design& d) {
  const int il = grid_position(d.chamber_length_mm, kLMin, kLStep, kChamberLengthCount);
  const int iw = grid_position(d.wall_mm, kWMin, kWStep, kWallCount);
  if ((d.n != 1 && d.n != 2) || il < 0 || iw < 0) {
    throw std::invalid_argument("design {n=" + std::to_string(d.n) +
                                ", l=" + std::to_string(d.chamber_length_mm) +
                                " mm, w=" + std::to_string(d.wall_mm) +
                                " mm} is not on the grid n∈{1,2}, l∈{20,22,…,40}, w∈{2,2.5,…,4}");
  }
  return (d.n - 1) * kChamberLengthCount * kWallCount + il * kWallCount + iw;
}

std::array<double, 3> normalised(const Design& d) {
  auto to_pm1 = [](double v, double lo, double hi) { return 2.0 * (v - lo) / (hi - lo) - 1.0; };
  const double l_max = kLMin + kLStep * (kChamberLengthCount - 1);
  const double w_max = kWMin + kWStep * (kWallCount - 1);
  return {to_pm1(d.n, 1.0, 2.0), to_pm1(d.chamber_length_mm, kLMin, l_max),
          to_pm1(d.wall_mm, kWMin, w_max)};
}

}  // namespace codesign::fem
