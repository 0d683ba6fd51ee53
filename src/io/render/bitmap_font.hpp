#pragma once
// A small fixed-width bitmap font for the text of rendered frames: 5 x 7 pixel glyphs drawn by
// hand for this project (printable ASCII plus θ ε ± ° µ – × Δ), each pixel drawn as a
// scale x scale square. One glyph cell is 6 x 9 units (one column and two rows of spacing).
// Text is UTF-8; a character without a glyph is drawn as '?'.
#include <string_view>

#include "io/formats/image.hpp"

namespace codesign::io {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
inline constexpr int kCellWidth = 6, kCellHeight = 9;

// Width and height in pixels of one line of `text` at `scale`.
int text_width(std::string_view text, int scale);
inline int text_height(int scale) { return kCellHeight * scale; }

// Draws `text` with its top-left corner at (x, y); pixels outside the image are skipped.
void draw_text(RgbImage& image, int x, int y, std::string_view text, int scale, Rgb colour);

// Whether glyph pixel (col, row) of code point `c` is set (for tests); c without a glyph: '?'.
bool glyph_pixel(char32_t c, int col, int row);

}  // namespace codesign::io
