#include "io/render/colormap.hpp"

#include <algorithm>
#include <cmath>

namespace codesign::io {

namespace {

struct Stop {
  double at;
  ColourF c;
};

constexpr Stop kStops[] = {
    {0.00, {0.20f, 0.07f, 0.52f}},  // indigo
    {0.15, {0.16f, 0.35f, 0.85f}},  // blue
    {0.35, {0.10f, 0.70f, 0.80f}},  // cyan
    {0.50, {0.30f, 0.80f, 0.40f}},  // green
    {0.65, {0.82f, 0.85f, 0.20f}},  // yellow
    {0.82, {0.96f, 0.55f, 0.12f}},  // orange
    {1.00, {0.72f, 0.08f, 0.08f}},  // dark red
};

}  // namespace

ColourF strain_colour(double s) {
  if (!(s > 0.0)) return kStops[0].c;
  if (s >= 1.0) return kStops[std::size(kStops) - 1].c;
  std::size_t k = 1;
  while (kStops[k].at < s) ++k;
  const Stop& a = kStops[k - 1];
  const Stop& b = kStops[k];
  const auto u = static_cast<float>((s - a.at) / (b.at - a.at));
  return {a.c.r + u * (b.c.r - a.c.r), a.c.g + u * (b.c.g - a.c.g), a.c.b + u * (b.c.b - a.c.b)};
}

Rgb to_rgb(ColourF c) {
  auto q = [](float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.f, 1.f) * 255.f)); };
  return {q(c.r), q(c.g), q(c.b)};
}

}  // namespace codesign::io
