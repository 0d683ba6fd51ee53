#pragma once
// Reading run-folder files in the binary's tests: a whole file as bytes, and result.toml
// without its wall-clock line (the one field that differs between reruns).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace codesign::test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string without_wall(const std::string& toml) {
  std::istringstream in(toml);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("wall_s", 0) != 0) out += line + "\n";
  return out;
}

}  // namespace codesign::test
