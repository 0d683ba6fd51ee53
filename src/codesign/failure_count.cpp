#include "codesign/failure_count.hpp"

#include <fstream>

namespace codesign::core {

std::int64_t count_numerical_failures(const std::string& episodes_csv) {
  std::ifstream in(episodes_csv, std::ios::binary);
  std::string line;
  std::int64_t n = 0;
  bool header = true;
  while (std::getline(in, line)) {
    if (header) {
      header = false;
      continue;
    }
    const auto comma = line.rfind(',');
    if (comma != std::string::npos && is_numerical_failure(std::string_view(line).substr(comma + 1))) ++n;
  }
  return n;
}

}  // namespace codesign::core
