#include "io/formats/png_file.hpp"

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <png.h>

#include "base/errors.hpp"
#include "base/file_write.hpp"

namespace codesign::io {

namespace {

// Where libpng's output goes, and why it stopped: libpng's own error and warning handlers would
// print "libpng error: Write Error" on stderr and say nothing of the cause. The write callback
// keeps errno of a failed fwrite; the error callback keeps libpng's message and jumps back to
// write_png, which throws one FileError naming the file.
struct PngSink {
  std::FILE* file = nullptr;
  int write_errno = 0;       // errno of the fwrite that failed (0: none)
  std::string message;       // libpng's message, if it stopped
};

extern "C" void png_sink_error(png_structp png, png_const_charp message) {
  static_cast<PngSink*>(png_get_error_ptr(png))->message = message ? message : "";
  png_longjmp(png, 1);
}

extern "C" void png_sink_warning(png_structp, png_const_charp) {}  // nothing libpng warns of on writing is ours

extern "C" void png_sink_write(png_structp png, png_bytep data, png_size_t size) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  if (std::fwrite(data, 1, size, sink->file) != size) {
    sink->write_errno = errno != 0 ? errno : EIO;
    png_error(png, "write failed");
  }
}

extern "C" void png_sink_flush(png_structp png) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  if (std::fflush(sink->file) != 0) {
    sink->write_errno = errno != 0 ? errno : EIO;
    png_error(png, "write failed");
  }
}

// libpng reports errors by longjmp to the jmp_buf of its struct; every object the error branch
// touches is created before setjmp and not changed afterwards (the sink lives on the heap).
struct WriteHandles {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::unique_ptr<PngSink> sink = std::make_unique<PngSink>();
  ~WriteHandles() {
    if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
    if (sink->file) std::fclose(sink->file);
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
  const std::string unchanged = " (" + path + " left as it was)";
  std::vector<png_const_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) rows[static_cast<std::size_t>(y)] = image.pixels.data() + image.offset(0, y);
  {
    WriteHandles h;
    PngSink* const sink = h.sink.get();
    sink->file = std::fopen(tmp.c_str(), "wb");
    if (!sink->file) throw FileError(file_error_text(tmp, "cannot create", errno) + unchanged);
    h.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, png_sink_error, png_sink_warning);
    if (!h.png) throw std::runtime_error(path + ": libpng: out of memory");
    h.info = png_create_info_struct(h.png);
    if (!h.info) throw std::runtime_error(path + ": libpng: out of memory");
    if (setjmp(png_jmpbuf(h.png))) {
      std::fclose(sink->file);
      sink->file = nullptr;
      std::remove(tmp.c_str());
      if (sink->write_errno != 0) throw FileError(file_error_text(tmp, "cannot write", sink->write_errno) + unchanged);
      throw std::runtime_error(path + ": libpng failed to write the image: " + sink->message);
    }
    png_set_write_fn(h.png, sink, png_sink_write, png_sink_flush);
    png_set_IHDR(h.png, h.info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(h.png, options.compression);
    if (!options.adaptive_filter) png_set_filter(h.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
    png_write_info(h.png, h.info);
    png_write_image(h.png, const_cast<png_bytepp>(rows.data()));  // libpng does not write through them
    png_write_end(h.png, nullptr);
    // stdio's buffer goes out at fclose: its error is the write error of the last bytes.
    std::FILE* const f = sink->file;
    sink->file = nullptr;
    if (std::fclose(f) != 0) {
      const int e = errno;
      std::remove(tmp.c_str());
      throw FileError(file_error_text(tmp, "cannot write", e) + unchanged);
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw FileError(file_error_text(path, "cannot rename " + tmp + " to it", e) + unchanged);
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
