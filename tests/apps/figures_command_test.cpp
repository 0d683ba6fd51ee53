// `codesign figures` and the figures drawn at the end of `codesign run`: the PNGs of a tiny run,
// a missing gnuplot as one warning (the run still succeeds), and bad input as one message with
// exit status 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "io/formats/gnuplot.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;

// A run small enough for a test (as in run_command_test.cpp): all three phases, 3 evaluation episodes.
const std::string kTinyRun = [] {
  codesign::test::TinyRun r;
  r.observation = "";
  r.beta_end = "2.0";
  r.seed = 5;
  return r.toml();
}();

fs::path scratch(const std::string& name) {
  return codesign::test::scratch_dir("codesign_figcmd_", name);
}

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// The binary with PATH pointing nowhere: gnuplot cannot be found.
codesign::test::RunResult run_without_gnuplot(const std::string& args) {
  const std::string cmd = "/usr/bin/env PATH=/nonexistent " + std::string(CODESIGN_BINARY) + " " + args + " 2>&1";
  codesign::test::RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

const char* const kPngs[] = {"fig2a.png", "fig2b.png", "fig2c.png", "fig2d.png", "fig3.png"};

}  // namespace

TEST(FiguresCommand, RunDrawsFiguresAndFiguresCommandRedrawsThem) {
  const fs::path d = scratch("run");
  std::ofstream(d / "tiny.toml") << kTinyRun;
  const fs::path out = d / "run";
  const auto r = run_codesign("--config " + (d / "tiny.toml").string() + " -o " + out.string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "figures" / "data" / "fig2a_samples.dat"));
  if (!codesign::io::gnuplot_available()) GTEST_SKIP() << "gnuplot not installed";
  EXPECT_NE(r.output.find("codesign: figures: 5 PNGs in " + out.string() + "/figures/"), std::string::npos) << r.output;
  for (const char* png : kPngs) {
    EXPECT_GT(fs::file_size(out / "figures" / png), 1000u) << png;
    fs::remove(out / "figures" / png);
  }
  // Again with the command, this run compared with itself under another label.
  const auto f = run_codesign("figures --run " + out.string() + " --compare again=" + out.string());
  ASSERT_EQ(f.status, 0) << f.output;
  EXPECT_NE(f.output.find("figures: 5 of 5 drawn"), std::string::npos) << f.output;
  for (const char* png : kPngs) EXPECT_TRUE(fs::exists(out / "figures" / png)) << png;
}

TEST(FiguresCommand, MissingGnuplotIsOneWarningAndTheRunSucceeds) {
  const fs::path d = scratch("nognuplot");
  std::ofstream(d / "tiny.toml") << kTinyRun;
  const fs::path out = d / "run";
  const auto r = run_without_gnuplot("--config " + (d / "tiny.toml").string() + " -o " + out.string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "result.toml"));
  const std::string warning = "codesign: warning: figures not drawn: gnuplot not found (install gnuplot-nox)";
  EXPECT_NE(r.output.find(warning), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning", r.output.find(warning) + warning.size()), std::string::npos) << r.output;  // one
  EXPECT_TRUE(fs::exists(out / "figures" / "data" / "fig3.dat"));
  EXPECT_FALSE(fs::exists(out / "figures" / "fig2a.png"));

  // The command itself: exit status 1, every figure named.
  const auto f = run_without_gnuplot("figures --run " + out.string());
  EXPECT_EQ(f.status, 1) << f.output;
  EXPECT_NE(f.output.find("figures: fig3 not drawn: gnuplot not found"), std::string::npos) << f.output;
  EXPECT_NE(f.output.find("figures: 0 of 5 drawn"), std::string::npos) << f.output;
}

TEST(FiguresCommand, BadInputIsOneMessageAndExitStatus2) {
  const fs::path d = scratch("bad");
  auto r = run_codesign("figures --run " + (d / "absent").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.output), 1u) << r.output;
  EXPECT_NE(r.output.find("codesign: error: " + (d / "absent").string() + ": no such run folder"), std::string::npos)
      << r.output;

  fs::create_directories(d / "empty");
  r = run_codesign("figures --run " + (d / "empty").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.output), 1u) << r.output;
  EXPECT_NE(r.output.find("config.toml: missing"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "empty" / "figures"));

  r = run_codesign("figures --run " + (d / "empty").string() + " --compare runs/x");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--compare 'runs/x': expected LABEL=DIR"), std::string::npos) << r.output;

  r = run_codesign("figures --run " + (d / "empty").string() + " --plots " + (d / "noplots").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("noplots/fig2a.gp: gnuplot script missing"), std::string::npos) << r.output;

  r = run_codesign("figures --run " + (d / "empty").string() + " --window 0");
  EXPECT_EQ(r.status, 2) << r.output;
}
