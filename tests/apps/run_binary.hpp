#pragma once
// Runs the built `codesign` binary (path from CMake) with the given arguments and captures
// its exit status and its stdout and stderr together.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace codesign::test {

struct RunResult {
  int status = -1;     // exit status; -1 if the process did not exit normally
  std::string output;  // stdout and stderr together
};

inline RunResult run_codesign(const std::string& args) {
  const std::string cmd = std::string(CODESIGN_BINARY) + " " + args + " 2>&1";
  RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace codesign::test
