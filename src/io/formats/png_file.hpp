#pragma once
// PNG files through libpng: 8-bit RGB, no interlacing.
//
// write_png writes PATH.tmp and renames it onto PATH, so a reader never sees half a frame.
// `compression` is zlib's level 0..9 (png_range::compression); rendered frames are mostly flat
// background, so level 1 with the "up" row filter is both fast and small (measured sizes and
// times: docs/journal/rendering.md). Errors (unwritable path, libpng failure) throw
// std::runtime_error naming the file.
#include <string>

#include "base/range.hpp"
#include "io/formats/image.hpp"

namespace codesign::io {

namespace png_range {
inline constexpr Range<int> compression{0, 9};
}

struct PngOptions {
  int compression = 1;      // zlib level, in png_range::compression
  bool adaptive_filter = false;  // libpng's per-row filter choice (slower); false: the "up" filter
};

void write_png(const std::string& path, const RgbImage& image, const PngOptions& options = {});
// Reads an 8-bit RGB or RGBA PNG (alpha dropped); throws std::runtime_error for anything else.
RgbImage read_png(const std::string& path);

}  // namespace codesign::io
