#pragma once
// An 8-bit RGB raster, rows stored top row first (the order of PNG files and of screen
// coordinates: pixel (x, y) has y growing downwards).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace codesign::io {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3, row-major, top row first

  RgbImage() = default;
  RgbImage(int w, int h, Rgb fill = {})
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3) {
    for (std::size_t i = 0; i < pixels.size(); i += 3) {
      pixels[i] = fill.r;
      pixels[i + 1] = fill.g;
      pixels[i + 2] = fill.b;
    }
  }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  std::size_t offset(int x, int y) const {
    return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
  }
  Rgb at(int x, int y) const {
    const std::size_t o = offset(x, y);
    return {pixels[o], pixels[o + 1], pixels[o + 2]};
  }
  void set(int x, int y, Rgb c) {
    if (!contains(x, y)) return;
    const std::size_t o = offset(x, y);
    pixels[o] = c.r;
    pixels[o + 1] = c.g;
    pixels[o + 2] = c.b;
  }
  // Fills the rectangle [x0, x1) x [y0, y1), clipped to the image.
  void fill_rect(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = y0 < 0 ? 0 : y0; y < y1 && y < height; ++y)
      for (int x = x0 < 0 ? 0 : x0; x < x1 && x < width; ++x) set(x, y, c);
  }
};

}  // namespace codesign::io
