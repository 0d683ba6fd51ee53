#include "io/atomic_file.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace codesign::io {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, binary ? std::ios::trunc | std::ios::binary : std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open " + tmp + " for writing");
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp);
      throw;
    }
    if (!out) {
      out.close();
      std::filesystem::remove(tmp);
      throw std::runtime_error("writing " + tmp + " failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + ec.message());
  }
}

}  // namespace codesign::io
