// End-to-end checks of the `codesign` binary: shipped configs are valid, and bad input stops
// with one message naming file, key and range, exit status 2, and no earlier output touched.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "run_binary.hpp"

namespace {

namespace fs = std::filesystem;

using codesign::test::run_codesign;
using Result = codesign::test::RunResult;

fs::path scratch(const std::string& name) {
  return codesign::test::scratch_dir("codesign_cli_", name);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(Cli, ShippedRunConfigsAreValid) {
  const fs::path dir = scratch("configs");
  for (const std::string name : {"paper", "quick"}) {
    // A copy with a short scenario keeps the test fast; only [sim].steps differs.
    std::string text = slurp(fs::path(CODESIGN_SOURCE_DIR) / "configs" / (name + ".toml"));
    ASSERT_FALSE(text.empty()) << name;
    const auto pos = text.find("\nsteps = ");
    ASSERT_NE(pos, std::string::npos) << name;
    text.replace(pos, text.find('\n', pos + 1) - pos, "\nsteps = 3");
    if (const auto v = text.find("vtk_every = 25"); v != std::string::npos) {
      text.replace(v, 14, "vtk_every = 0");
    }
    const fs::path cfg = dir / (name + ".toml");
    write(cfg, text);
    // `sim` reads and validates every table of a run config (the main job is a long run).
    const Result r = run_codesign("sim --config " + cfg.string() + " -o " + (dir / name).string());
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / name / "trace.csv")) << r.output;
  }
}

TEST(Cli, BadValueStopsWithOneMessageAndKeepsEarlierOutput) {
  const fs::path dir = scratch("bad");
  write(dir / "good.toml", "[sim]\nsteps = 2\n");
  ASSERT_EQ(run_codesign("sim --config " + (dir / "good.toml").string() + " -o " + (dir / "out").string()).status, 0);
  const std::string before = slurp(dir / "out" / "trace.csv");
  ASSERT_FALSE(before.empty());

  write(dir / "bad.toml", "[material]\npoisson_ratio = 0.7\n");
  const Result r = run_codesign("sim --force --config " + (dir / "bad.toml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("bad.toml: material.poisson_ratio"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[0, 0.49]"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir / "out" / "trace.csv"), before);
}

TEST(Cli, UnknownKeyIsRejected) {
  const fs::path dir = scratch("unknown");
  write(dir / "typo.toml", "[scene]\ninclinaton_deg = 30\n");
  const Result r = run_codesign("--config " + (dir / "typo.toml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("typo.toml: scene.inclinaton_deg: unknown key"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "trace.csv"));
}

TEST(Cli, MissingConfigFile) {
  const Result r = run_codesign("--config /nonexistent/run.toml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("/nonexistent/run.toml: cannot open config file"), std::string::npos) << r.output;
}

TEST(Cli, BadFlagsExitNonZero) {
  EXPECT_EQ(run_codesign("mesh --design 110 -o /tmp/never.msh").status, 2);
  EXPECT_EQ(run_codesign("no-such-command").status, 2);
  EXPECT_EQ(run_codesign("").status, 2);
  EXPECT_EQ(run_codesign("--help").status, 0);
}

}  // namespace
