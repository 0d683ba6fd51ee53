#include "io/render/render_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "io/render/bitmap_font.hpp"

namespace codesign::io {

namespace {

constexpr Rgb kText{30, 34, 40};
constexpr Rgb kWhite{255, 255, 255};

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

Rgb chip_colour(BandState s) {
  switch (s) {
    case BandState::In: return {40, 150, 60};
    case BandState::Below:
    case BandState::Above: return {225, 120, 20};
    case BandState::NoContact: return {200, 40, 40};
  }
  return kText;
}

}  // namespace

PanelLayout panel_layout(int index, int panels, int width, int height) {
  PanelLayout l;
  l.scale = std::max(1, static_cast<int>(std::lround(height / 360.0)));
  const int s = l.scale;
  const int pw = width / panels;
  l.panel = {index * pw, 0, index == panels - 1 ? width - index * pw : pw, height};
  const int text_h = 3 * kCellHeight * s + 6 * s;
  const int bar_w = 56 * s;
  l.scene = {l.panel.x0, text_h, std::max(1, l.panel.width - bar_w), std::max(1, height - text_h)};
  // The bar starts below its two-line title and half a line more (room for the top tick label).
  l.bar = {l.panel.x0 + l.panel.width - bar_w + 4 * s, text_h + 5 * kCellHeight * s / 2 + 4 * s, 8 * s, 0};
  l.bar.height = std::max(1, height - l.bar.y0 - 8 * s);
  return l;
}

BandState band_state(double force_mN, double target_mN, double band_fraction) {
  if (!(force_mN > 0.0)) return BandState::NoContact;
  const double d = force_mN - target_mN, tol = band_fraction * target_mN;
  // In band exactly when |F − F_t| < band·F_t (as the task's reward counts it).
  if (d <= -tol) return BandState::Below;
  if (d >= tol) return BandState::Above;
  return BandState::In;
}

const char* to_string(BandState s) {
  switch (s) {
    case BandState::NoContact: return "no contact";
    case BandState::Below: return "below band";
    case BandState::In: return "in band";
    case BandState::Above: return "above band";
  }
  return "?";
}

void draw_overlay(RgbImage& image, const PanelLayout& l, const FrameOverlay& o, const ColourScale& strain) {
  const int s = l.scale;
  const int x = l.panel.x0 + 4 * s;
  int y = 2 * s;
  const int line = kCellHeight * s;
  draw_text(image, x, y, o.title, s, kText);
  y += line;
  const double theta_deg = o.theta_rad * 180.0 / std::numbers::pi;
  const std::string state = format("t = %5.2f s   ", o.t_s) + "\xce\xb8 = " + format("%+6.2f", theta_deg) +
                            "\xc2\xb0   F = " + format("%6.2f mN", o.force_mN);
  draw_text(image, x, y, state, s, kText);
  y += line;
  const double lo = o.target_mN * (1.0 - o.band_fraction), hi = o.target_mN * (1.0 + o.band_fraction);
  const std::string band = format("band %.1f", lo) + format("\xe2\x80\x93%.1f mN", hi) + " (F_t " + "\xc2\xb1" +
                           format(" %.0f %%): ", 100.0 * o.band_fraction);
  draw_text(image, x, y, band, s, kText);
  const BandState bs = band_state(o.force_mN, o.target_mN, o.band_fraction);
  const int cx = x + text_width(band, s);
  const std::string label = to_string(bs);
  image.fill_rect(cx - s, y, cx + text_width(label, s) + s, y + line, chip_colour(bs));
  draw_text(image, cx, y, label, s, kWhite);

  // Colour bar: gradient, frame, ticks and labels in percent.
  const Viewport& b = l.bar;
  for (int row = 0; row < b.height; ++row) {
    const double f = 1.0 - (row + 0.5) / b.height;
    image.fill_rect(b.x0, b.y0 + row, b.x0 + b.width, b.y0 + row + 1, to_rgb(strain_colour(f)));
  }
  const int title_y = b.y0 - 5 * line / 2 - 2 * s;
  draw_text(image, b.x0 - 2 * s, title_y, "strain", s, kText);
  draw_text(image, b.x0 - 2 * s, title_y + line, "[%]", s, kText);
  const double step_pct = 100.0 * (strain.hi - strain.lo) / 4.0;
  const int decimals = std::clamp(1 - static_cast<int>(std::floor(std::log10(std::max(step_pct, 1e-12)))), 0, 4);
  char fmt[16];
  std::snprintf(fmt, sizeof fmt, "%%.%df", decimals);
  for (int k = 0; k <= 4; ++k) {
    const int ty = b.y0 + static_cast<int>(std::lround((1.0 - k / 4.0) * (b.height - 1)));
    image.fill_rect(b.x0 + b.width, ty, b.x0 + b.width + 3 * s, ty + std::max(1, s / 2), kText);
    const std::string v = format(fmt, 100.0 * (strain.lo + k * (strain.hi - strain.lo) / 4.0));
    draw_text(image, b.x0 + b.width + 4 * s, ty - line / 2, v, s, kText);
  }
}

}  // namespace codesign::io
