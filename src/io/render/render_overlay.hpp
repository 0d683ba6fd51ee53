#pragma once
// The 2-D part of a rendered frame, drawn on the read-back image with io/bitmap_font: per panel
// a text band at the top (title; t, θ, F; the ±band state of F as a coloured chip) and a
// vertical colour bar of the strain scale at the right, labelled in percent of axial strain
// (five ticks, lowest value at the bottom). The rest of the panel is the 3-D viewport.
#include <string>

#include "io/render/colormap.hpp"
#include "io/formats/image.hpp"
#include "io/render/render_scene.hpp"

namespace codesign::io {

struct PanelLayout {
  Viewport panel;   // the whole panel
  Viewport scene;   // the 3-D view
  Viewport bar;     // the colour gradient (top row = scale.hi, bottom row = scale.lo)
  int scale = 1;    // font scale: pixels per font unit
};

// Panel `index` of `panels` side by side in a width x height image.
PanelLayout panel_layout(int index, int panels, int width, int height);

enum class BandState { NoContact, Below, In, Above };
BandState band_state(double force_mN, double target_mN, double band_fraction);
const char* to_string(BandState s);

void draw_overlay(RgbImage& image, const PanelLayout& layout, const FrameOverlay& text, const ColourScale& strain);

}  // namespace codesign::io
