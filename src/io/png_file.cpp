#include "io/png_file.hpp"

#include <csetjmp>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <png.h>

namespace codesign::io {

namespace {

// libpng reports errors by longjmp to the jmp_buf of its struct; every object the error branch
// touches is created before setjmp and not changed afterwards.
struct WriteHandles {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::FILE* file = nullptr;
  ~WriteHandles() {
    if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
    if (file) std::fclose(file);
  }
};

}  // namespace

void write_png(const std::string& path, const RgbImage& image, const PngOptions& options) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::runtime_error(path + ": cannot write an empty or inconsistent image");
  if (!png_range::compression.contains(options.compression))
    throw std::runtime_error(path + ": PNG compression level must be in [0, 9]");
  const std::string tmp = path + ".tmp";
  std::vector<png_const_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) rows[static_cast<std::size_t>(y)] = image.pixels.data() + image.offset(0, y);
  {
    WriteHandles h;
    h.file = std::fopen(tmp.c_str(), "wb");
    if (!h.file) throw std::runtime_error(tmp + ": cannot open for writing");
    h.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (!h.png) throw std::runtime_error(path + ": libpng: out of memory");
    h.info = png_create_info_struct(h.png);
    if (!h.info) throw std::runtime_error(path + ": libpng: out of memory");
    if (setjmp(png_jmpbuf(h.png))) {
      std::fclose(h.file);
      h.file = nullptr;
      std::remove(tmp.c_str());
      throw std::runtime_error(path + ": libpng failed to write the image");
    }
    png_init_io(h.png, h.file);
    png_set_IHDR(h.png, h.info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(h.png, options.compression);
    if (!options.adaptive_filter) png_set_filter(h.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
    png_write_info(h.png, h.info);
    png_write_image(h.png, const_cast<png_bytepp>(rows.data()));  // libpng does not write through them
    png_write_end(h.png, nullptr);
    if (std::fflush(h.file) != 0) {
      std::remove(tmp.c_str());
      throw std::runtime_error(tmp + ": write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename " + tmp + ": " + ec.message());
  }
}

RgbImage read_png(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str()))
    throw std::runtime_error(path + ": not a readable PNG: " + img.message);
  img.format = PNG_FORMAT_RGB;
  RgbImage out(static_cast<int>(img.width), static_cast<int>(img.height));
  if (!png_image_finish_read(&img, nullptr, out.pixels.data(), 0, nullptr)) {
    png_image_free(&img);
    throw std::runtime_error(path + ": PNG decoding failed: " + img.message);
  }
  return out;
}

}  // namespace codesign::io
