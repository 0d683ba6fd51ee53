// PNG files and the bitmap font.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/render/bitmap_font.hpp"
#include "io/formats/png_file.hpp"

using namespace codesign;

TEST(PngFile, WrittenPixelsReadBackExactlyAtEveryLevel) {
  io::RgbImage img(37, 23);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.set(x, y, {static_cast<std::uint8_t>(7 * x), static_cast<std::uint8_t>(11 * y), static_cast<std::uint8_t>(x * y)});
  const auto dir = std::filesystem::temp_directory_path() / "codesign_png_test";
  std::filesystem::create_directories(dir);
  for (int level : {0, 1, 9})
    for (bool adaptive : {false, true}) {
      const std::string path = (dir / "frame_0000.png").string();
      io::write_png(path, img, {level, adaptive});
      const io::RgbImage back = io::read_png(path);
      EXPECT_EQ(back.width, img.width);
      EXPECT_EQ(back.height, img.height);
      EXPECT_EQ(back.pixels, img.pixels) << "level " << level;
      EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    }
  std::filesystem::remove_all(dir);
}

TEST(PngFile, ErrorsNameTheFile) {
  const io::RgbImage img(8, 8);
  try {
    io::write_png("/nonexistent_dir_codesign/x.png", img);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir_codesign/x.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::read_png("/nonexistent_dir_codesign/x.png"), std::runtime_error);
  EXPECT_THROW(io::write_png("/tmp/x.png", io::RgbImage{}), std::runtime_error);
}

TEST(BitmapFont, GlyphsLandWhereTheFontSays) {
  io::RgbImage img(100, 40, {255, 255, 255});
  const int scale = 2;
  io::draw_text(img, 10, 5, "A\xce\xb8", scale, {0, 0, 0});  // "Aθ"
  EXPECT_EQ(io::text_width("A\xce\xb8", scale), 2 * io::kCellWidth * scale);  // two code points
  int set = 0;
  for (int k = 0; k < 2; ++k) {
    const char32_t c = k == 0 ? U'A' : U'\u03b8';
    for (int row = 0; row < io::kGlyphHeight; ++row)
      for (int col = 0; col < io::kGlyphWidth; ++col) {
        // One blank font row above each glyph; every font pixel is a scale x scale square.
        const int x = 10 + k * io::kCellWidth * scale + col * scale, y = 5 + (row + 1) * scale;
        const bool on = img.at(x, y) == io::Rgb{0, 0, 0};
        EXPECT_EQ(on, io::glyph_pixel(c, col, row)) << "glyph " << k << " at " << col << "," << row;
        EXPECT_EQ((img.at(x + 1, y + 1) == io::Rgb{0, 0, 0}), on);
        set += on;
      }
  }
  EXPECT_GT(set, 20);
  // An unknown character is drawn as '?'.
  for (int row = 0; row < io::kGlyphHeight; ++row)
    for (int col = 0; col < io::kGlyphWidth; ++col)
      EXPECT_EQ(io::glyph_pixel(U'\u4e2d', col, row), io::glyph_pixel(U'?', col, row));
}
