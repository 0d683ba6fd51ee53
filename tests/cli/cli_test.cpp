// End-to-end checks of the `codesign` binary: shipped configs are valid, and bad input stops
// with one message naming file, key and range, exit status 2, and no earlier output touched.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out;  // stdout and stderr together
};

Result run(const std::string& args) {
  const std::string cmd = std::string(CODESIGN_BINARY) + " " + args + " 2>&1";
  Result r;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p) != nullptr) r.out += buf;
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("codesign_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
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
    const Result r = run("--config " + cfg.string() + " -o " + (dir / name).string());
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_TRUE(fs::exists(dir / name / "trace.csv")) << r.out;
  }
}

TEST(Cli, BadValueStopsWithOneMessageAndKeepsEarlierOutput) {
  const fs::path dir = scratch("bad");
  write(dir / "good.toml", "[sim]\nsteps = 2\n");
  ASSERT_EQ(run("sim --config " + (dir / "good.toml").string() + " -o " + (dir / "out").string()).status, 0);
  const std::string before = slurp(dir / "out" / "trace.csv");
  ASSERT_FALSE(before.empty());

  write(dir / "bad.toml", "[material]\npoisson_ratio = 0.7\n");
  const Result r = run("sim --force --config " + (dir / "bad.toml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(count_lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("bad.toml: material.poisson_ratio"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[0, 0.49]"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(dir / "out" / "trace.csv"), before);
}

TEST(Cli, UnknownKeyIsRejected) {
  const fs::path dir = scratch("unknown");
  write(dir / "typo.toml", "[scene]\ninclinaton_deg = 30\n");
  const Result r = run("--config " + (dir / "typo.toml").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("typo.toml: scene.inclinaton_deg: unknown key"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "out" / "trace.csv"));
}

TEST(Cli, MissingConfigFile) {
  const Result r = run("--config /nonexistent/run.toml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("/nonexistent/run.toml: cannot open config file"), std::string::npos) << r.out;
}

TEST(Cli, BadFlagsExitNonZero) {
  EXPECT_EQ(run("mesh --design 110 -o /tmp/never.msh").status, 2);
  EXPECT_EQ(run("no-such-command").status, 2);
  EXPECT_EQ(run("").status, 2);
  EXPECT_EQ(run("--help").status, 0);
}

}  // namespace
