#pragma once
// The strain colour map of rendered frames: dark indigo (low) through blue, cyan, green,
// yellow and orange to dark red (high), piecewise linear between seven control colours chosen
// for this project. Hue changes monotonically, so the two ends are told apart by hue alone
// (lighting only scales a colour; tests/io/render/render_scene_test.cpp relies on that).
#include "io/formats/image.hpp"

namespace codesign::io {

struct ColourF {
  float r = 0.f, g = 0.f, b = 0.f;
};

// s in [0, 1] (clamped; NaN gives the low end).
ColourF strain_colour(double s);
Rgb to_rgb(ColourF c);

// Maps a value onto [0, 1] of the colour map with the range [lo, hi] (lo < hi).
struct ColourScale {
  double lo = 0.0;
  double hi = 1.0;
  double fraction(double v) const { return (v - lo) / (hi - lo); }
};

}  // namespace codesign::io
