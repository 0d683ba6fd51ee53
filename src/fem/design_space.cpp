#include "fem/design_space.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace codesign::fem {

namespace {

constexpr double kMatchTol = 1e-9;

template <class T>
void check_increasing(const std::vector<T>& v, const char* axis) {
  if (v.empty()) throw std::invalid_argument(std::string("design space: ") + axis + ": no values");
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1]))
      throw std::invalid_argument(std::string("design space: ") + axis + ": values must be strictly increasing");
}

// Position of v in the axis (within kMatchTol), or -1.
int position(const std::vector<double>& axis, double v) {
  for (std::size_t i = 0; i < axis.size(); ++i)
    if (std::abs(axis[i] - v) <= kMatchTol) return static_cast<int>(i);
  return -1;
}

// v on [lo, hi] → [−1, 1] (the formula of design.cpp's normalised); 0 for a one-value axis.
double to_pm1(double v, double lo, double hi) { return hi > lo ? 2.0 * (v - lo) / (hi - lo) - 1.0 : 0.0; }

}  // namespace

DesignSpace DesignSpace::paper() {
  // The axes as design.hpp's index lays them out (w innermost, then l, then n): one definition.
  DesignAxes a;
  for (int n = 0; n < kDesignCount / (kChamberLengthCount * kWallCount); ++n)
    a.chambers.push_back(design_from_index(n * kChamberLengthCount * kWallCount).n);
  for (int k = 0; k < kChamberLengthCount; ++k) a.lengths_mm.push_back(design_from_index(k * kWallCount).chamber_length_mm);
  for (int k = 0; k < kWallCount; ++k) a.walls_mm.push_back(design_from_index(k).wall_mm);
  return DesignSpace(std::move(a));
}

DesignSpace::DesignSpace(DesignAxes axes) : axes_(std::move(axes)) {
  check_increasing(axes_.chambers, "chambers");
  for (const int n : axes_.chambers)
    if (n != 1 && n != 2) throw std::invalid_argument("design space: chambers: " + std::to_string(n) + " is not 1 or 2");
  check_increasing(axes_.lengths_mm, "chamber_length_mm");
  check_increasing(axes_.walls_mm, "wall_mm");
  for (const auto* axis : {&axes_.lengths_mm, &axes_.walls_mm})
    for (const double v : *axis)
      if (!(v > 0.0) || !std::isfinite(v))
        throw std::invalid_argument(std::string("design space: ") +
                                    (axis == &axes_.lengths_mm ? "chamber_length_mm" : "wall_mm") +
                                    ": values must be finite and > 0");
}

int DesignSpace::size() const {
  return static_cast<int>(axes_.chambers.size() * axes_.lengths_mm.size() * axes_.walls_mm.size());
}

bool DesignSpace::is_paper() const { return axes_ == paper().axes_; }

Design DesignSpace::design(int j) const {
  if (j < 0 || j >= size())
    throw std::out_of_range("design index " + std::to_string(j) + " outside 0.." + std::to_string(size() - 1));
  const int nl = static_cast<int>(axes_.lengths_mm.size()), nw = static_cast<int>(axes_.walls_mm.size());
  Design d;
  d.n = axes_.chambers[static_cast<std::size_t>(j / (nl * nw))];
  const int rest = j % (nl * nw);
  d.chamber_length_mm = axes_.lengths_mm[static_cast<std::size_t>(rest / nw)];
  d.wall_mm = axes_.walls_mm[static_cast<std::size_t>(rest % nw)];
  return d;
}

int DesignSpace::index_of(const Design& d) const {
  int in = -1;
  for (std::size_t i = 0; i < axes_.chambers.size(); ++i)
    if (axes_.chambers[i] == d.n) in = static_cast<int>(i);
  const int il = position(axes_.lengths_mm, d.chamber_length_mm), iw = position(axes_.walls_mm, d.wall_mm);
  if (in < 0 || il < 0 || iw < 0) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "design {n=%d, l=%g mm, w=%g mm} is not in the design space", d.n,
                  d.chamber_length_mm, d.wall_mm);
    throw std::invalid_argument(buf);
  }
  const int nl = static_cast<int>(axes_.lengths_mm.size()), nw = static_cast<int>(axes_.walls_mm.size());
  return (in * nl + il) * nw + iw;
}

std::array<double, 3> DesignSpace::normalised(int j) const {
  const Design d = design(j);
  return {to_pm1(d.n, axes_.chambers.front(), axes_.chambers.back()),
          to_pm1(d.chamber_length_mm, axes_.lengths_mm.front(), axes_.lengths_mm.back()),
          to_pm1(d.wall_mm, axes_.walls_mm.front(), axes_.walls_mm.back())};
}

std::string DesignSpace::label(int j) const {
  const Design d = design(j);
  char buf[64];
  std::snprintf(buf, sizeof buf, "j%d {%d, %g mm, %g mm}", j, d.n, d.chamber_length_mm, d.wall_mm);
  return buf;
}

}  // namespace codesign::fem
