// The main job end to end: `codesign --config X -o DIR` writes a run folder, refuses to start
// over an earlier run, and after `kill -9` at random moments `--resume` ends with the same
// policy.bin and result.toml (wall-clock line aside) as an uninterrupted run.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "file_text.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;

// A run small enough for a test: 4 designs x 5 decisions per iteration, small networks, all
// three phases of Algorithm 2, a checkpoint every 2 iterations.
const std::string kTinyRun = [] {
  codesign::test::TinyRun r;
  r.beta_end = "2.0";
  return r.toml();
}();

fs::path scratch(const std::string& name) {
  return codesign::test::scratch_dir("codesign_runcmd_", name);
}

using codesign::test::slurp;
using codesign::test::without_wall;

// Starts the binary with `args` (stdout/stderr to /dev/null), waits `ms` milliseconds, sends
// SIGKILL; returns true if the process had already finished by itself.
bool run_and_kill(const std::vector<std::string>& args, int ms) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    std::vector<char*> argv{const_cast<char*>(CODESIGN_BINARY)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(CODESIGN_BINARY, argv.data());
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  int status = 0;
  const bool done = ::waitpid(pid, &status, WNOHANG) == pid;
  if (!done) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  return done;
}

TEST(RunCommand, MainJobWritesTheRunFolderAndRefusesToStartOverIt) {
  const fs::path d = scratch("main");
  std::ofstream(d / "tiny.toml") << kTinyRun;
  const std::string out = (d / "run").string();
  const auto r = run_codesign("--config " + (d / "tiny.toml").string() + " -o " + out + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("codesign: d* = j"), std::string::npos) << r.output;
  const std::string result = slurp(fs::path(out) / "result.toml");
  EXPECT_NE(result.find("[best]"), std::string::npos);
  EXPECT_EQ(slurp(fs::path(out) / "config.input.toml"), kTinyRun);
  // config.toml is the resolved config: every table, and it runs as it is.
  const std::string resolved = slurp(fs::path(out) / "config.toml");
  for (const char* t : {"[material]", "[scene]", "[solver]", "[task]", "[codesign]", "[ppo]"})
    EXPECT_NE(resolved.find(t), std::string::npos) << t;
  const std::string policy = slurp(fs::path(out) / "policy.bin");
  ASSERT_FALSE(policy.empty());

  const auto again = run_codesign("--config " + (d / "tiny.toml").string() + " -o " + out);
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.output.find("already holds"), std::string::npos) << again.output;
  EXPECT_EQ(std::count(again.output.begin(), again.output.end(), '\n'), 1) << again.output;
  EXPECT_EQ(slurp(fs::path(out) / "result.toml"), result);
  EXPECT_EQ(slurp(fs::path(out) / "policy.bin"), policy);
}

TEST(RunCommand, KilledAtRandomMomentsThenResumedEndsLikeAnUninterruptedRun) {
  const fs::path d = scratch("kill");
  std::ofstream(d / "tiny.toml") << kTinyRun;
  const std::string cfg = (d / "tiny.toml").string();
  const fs::path whole = d / "whole", killed = d / "killed";
  ASSERT_EQ(run_codesign("--config " + cfg + " -o " + whole.string() + " --quiet").status, 0);

  std::mt19937 rng(20261126);  // fixed: the kill moments are reproducible
  std::uniform_int_distribution<int> when(200, 4000);
  std::vector<std::string> args{"--config", cfg, "-o", killed.string(), "--quiet", "--threads", "2"};
  bool started = false, finished = false;
  for (int kill = 0; kill < 4 && !finished; ++kill) {
    std::vector<std::string> a = args;
    if (started) a.push_back("--resume");
    finished = run_and_kill(a, when(rng));
    started = started || fs::exists(killed / "config.toml");
  }
  std::vector<std::string> last = args;
  if (started) last.push_back("--resume");
  std::string cmd;
  for (const std::string& s : last) cmd += " " + s;
  const auto r = run_codesign(cmd);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(slurp(whole / "policy.bin"), slurp(killed / "policy.bin"));
  EXPECT_EQ(without_wall(slurp(whole / "result.toml")), without_wall(slurp(killed / "result.toml")));
  EXPECT_EQ(slurp(whole / "episodes.csv"), slurp(killed / "episodes.csv"));
}

}  // namespace
