#pragma once
// Runs the built `codesign` binary (path from CMake) with the given arguments and captures
// its exit status and its stdout and stderr together.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace codesign::test {

// An empty scratch folder <tmp>/<prefix><name>_<pid> (the pid keeps concurrent test runs of other
// checkouts apart).
inline std::filesystem::path scratch_dir(const std::string& prefix, const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / (prefix + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

struct RunResult {
  int status = -1;     // exit status; -1 if the process did not exit normally
  std::string output;  // stdout and stderr together
};

// Runs a shell command line, stdout and stderr together.
inline RunResult run_shell(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline RunResult run_codesign(const std::string& args) { return run_shell(std::string(CODESIGN_BINARY) + " " + args); }

}  // namespace codesign::test
