// SIGTERM and SIGINT during `codesign run`: the run stops after the iteration it is in, writes
// its checkpoint, says so in one line and exits with 128 + the signal; `--resume` then ends with
// the same files as an uninterrupted run. A second signal ends the process at once.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "file_text.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::Child;
using codesign::test::run_codesign;

// The run of the kill -9 test (run_command_test.cpp): 12 iterations of 20 timesteps, a
// checkpoint every 2 iterations.
const std::string kTinyRun = [] {
  codesign::test::TinyRun r;
  r.beta_end = "2.0";
  return r.toml();
}();

using codesign::test::slurp;
using codesign::test::without_wall;

// The timestep a checkpoint file holds (i64 at byte 28, checkpoint.hpp), or -1 without one.
std::int64_t checkpoint_t(const fs::path& run) {
  const std::string b = slurp(run / "checkpoint.bin");
  if (b.size() < 36) return -1;
  std::int64_t t = 0;
  std::memcpy(&t, b.data() + 28, sizeof t);
  return t;
}

// A checkpoint's run state: everything before its table of log lengths (that table holds the
// length of ppo.csv, whose timing columns differ between sessions; the logs themselves are
// compared as files), with wall_s (f64 at byte 36) zeroed.
std::string checkpoint_state(const fs::path& run) {
  std::string b = slurp(run / "checkpoint.bin");
  std::size_t table = 8 + 8;  // log count ... checksum
  for (const char* log : {"episodes.csv", "ppo.csv", "distribution.csv", "q_disc.csv", "sampled.csv"})
    table += 8 + std::strlen(log) + 8;
  if (b.size() < 44 + table) return b;
  std::memset(b.data() + 36, 0, 8);
  return b.substr(0, b.size() - table);
}

// ppo.csv without its timing columns (15-18), as scripts/kill_campaign.sh compares it.
std::string ppo_without_timings(const fs::path& run) {
  std::istringstream in(slurp(run / "ppo.csv"));
  std::string line, out;
  while (std::getline(in, line)) {
    std::size_t at = 0;
    for (int c = 0; c < 14 && at != std::string::npos; ++c) at = line.find(',', at + 1);
    out += line.substr(0, at) + "\n";
  }
  return out;
}

struct Round {
  int signo;
  std::int64_t after_t;  // send once checkpoint.bin holds at least this t (-1: once .lock exists)
};

TEST(RunSignals, StopAtSeveralMomentsThenResumeEndsLikeAnUninterruptedRun) {
  const fs::path d = codesign::test::scratch_dir("codesign_runsig_", "resume");
  std::ofstream(d / "tiny.toml") << kTinyRun;
  const std::string cfg = (d / "tiny.toml").string();
  const fs::path whole = d / "whole", stopped = d / "stopped";
  const auto w = run_codesign("--config " + cfg + " -o " + whole.string() + " --quiet --threads 2 --no-figures");
  ASSERT_EQ(w.status, 0) << w.output;

  // Mid-way between checkpoints (the stop writes one at t = 60), at start-up before the first
  // iteration, later in training, and once training is complete (the final evaluation).
  const std::vector<Round> rounds{{SIGTERM, 40}, {SIGINT, -1}, {SIGTERM, 160}, {SIGINT, 240}};
  const std::vector<std::string> base{"--config", cfg, "-o", stopped.string(), "--quiet", "--threads", "2",
                                      "--no-figures"};
  bool finished = false;
  int stops = 0;
  for (std::size_t i = 0; i < rounds.size() && !finished; ++i) {
    std::vector<std::string> args = base;
    if (i > 0) args.push_back("--resume");
    Child c(args, d / ("round" + std::to_string(i) + ".log"));
    const Round& r = rounds[i];
    const bool ready = c.wait_until([&] {
      return r.after_t < 0 ? fs::exists(stopped / ".lock") : checkpoint_t(stopped) >= r.after_t;
    });
    c.signal(r.signo);
    const int st = c.wait();
    ASSERT_TRUE(WIFEXITED(st)) << "round " << i << ": ended by a signal: " << c.output();
    const std::string out = c.output();
    if (WEXITSTATUS(st) == 0) {  // the run had ended before the signal came: only in the last round
      EXPECT_EQ(i + 1, rounds.size()) << out;
      finished = true;
      continue;
    }
    ASSERT_TRUE(ready) << "round " << i << ": " << out;
    EXPECT_EQ(WEXITSTATUS(st), 128 + r.signo) << out;
    const std::string name = r.signo == SIGTERM ? "SIGTERM" : "SIGINT";
    EXPECT_NE(out.find("codesign: " + name + ": "), std::string::npos) << out;
    EXPECT_NE(out.find("-o " + stopped.string() + " --resume"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_FALSE(fs::exists(stopped / ".lock"));
    // The line names the timestep the checkpoint holds.
    EXPECT_NE(out.find("checkpoint.bin holds t = " + std::to_string(checkpoint_t(stopped)) + " of 240"),
              std::string::npos)
        << out;
    ++stops;
  }
  EXPECT_GE(stops, 3);
  if (!finished) {
    std::string cmd;
    for (const std::string& s : base) cmd += " " + s;
    const auto r = run_codesign(cmd + " --resume");
    ASSERT_EQ(r.status, 0) << r.output;
  }
  for (const char* f : {"policy.bin", "episodes.csv", "distribution.csv", "q_disc.csv", "sampled.csv",
                        "eval/best.csv", "eval/runner_up.csv", "eval/best_trace.csv", "eval/runner_up_trace.csv"})
    EXPECT_EQ(slurp(whole / f), slurp(stopped / f)) << f;
  EXPECT_EQ(without_wall(slurp(whole / "result.toml")), without_wall(slurp(stopped / "result.toml")));
  EXPECT_EQ(ppo_without_timings(whole), ppo_without_timings(stopped));
  const std::string state = checkpoint_state(whole);
  EXPECT_GT(state.size(), 1000u);
  EXPECT_TRUE(state == checkpoint_state(stopped)) << "checkpoint.bin: the run states differ";
  if (!HasFailure()) fs::remove_all(d);
}

TEST(RunSignals, SecondSignalEndsTheProcessAtOnce) {
  const fs::path d = codesign::test::scratch_dir("codesign_runsig_", "twice");
  std::ofstream(d / "tiny.toml") << kTinyRun;
  const fs::path run = d / "run";
  Child c({"--config", (d / "tiny.toml").string(), "-o", run.string(), "--quiet", "--threads", "2", "--no-figures"},
          d / "run.log");
  ASSERT_TRUE(c.wait_until([&] { return fs::exists(run / ".lock"); })) << c.output();
  c.signal(SIGTERM);
  c.signal(SIGINT);
  const int st = c.wait();
  ASSERT_TRUE(WIFSIGNALED(st)) << "exited with " << (WIFEXITED(st) ? WEXITSTATUS(st) : -1) << ": " << c.output();
  EXPECT_TRUE(WTERMSIG(st) == SIGINT || WTERMSIG(st) == SIGTERM) << WTERMSIG(st);
  if (!HasFailure()) fs::remove_all(d);
}

}  // namespace
