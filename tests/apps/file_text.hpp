#pragma once
// Reading run-folder files in the binary's tests: a whole file as bytes, result.toml without its
// wall-clock line (the one field that differs between reruns), and the cells of a CSV line.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

// The cells of one line of a run's CSV logs (no quoting: the writers never put a comma in a cell).
inline std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> c;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) c.push_back(cell);
  return c;
}

}  // namespace codesign::test
