#include "io/formats/atomic_file.hpp"

#include <sstream>
#include <utility>

#include "base/file_write.hpp"

namespace codesign::io {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary) {
  // The whole content is made in memory first: the file is then written with plain write(2)
  // calls, whose errno says why a write failed (an ofstream only says that it failed).
  std::ostringstream content(binary ? std::ios::out | std::ios::binary : std::ios::out);
  write(content);
  write_bytes_atomically(path, std::move(content).str());
}

}  // namespace codesign::io
