#pragma once
// Files for the tests of several folders (tests/core, tests/run): a fresh folder under the test
// temp dir and a file's bytes. tests/support/ is on every test executable's include path.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace codesign::test_files {

// TempDir()/codesign_<name>_<pid>, removed if it exists and not created (a run refuses to start
// over an existing folder). The process id keeps concurrent test runs (other build trees on the
// machine) apart.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::path(::testing::TempDir()) / ("codesign_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d;
}

// The whole file, byte for byte ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace codesign::test_files
