// `codesign verify` on a tiny finished run: its nominal condition at the run's own test phases
// reproduces result.toml's [best] test return to the bit (the same deterministic episodes); every
// condition of the suite gets a row; a second call resumes with nothing left to run; a folder
// that is no finished run is one clear message and exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "run/verify_run.hpp"
#include "file_text.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;
using codesign::test::slurp;

// The value of `key = ` in the [best] table of result.toml.
std::string best_value(const std::string& result, const std::string& key) {
  const std::size_t table = result.find("[best]");
  const std::size_t at = result.find("\n" + key + " = ", table);
  const std::size_t from = at + key.size() + 4;
  return result.substr(from, result.find_first_of(" \n", from) - from);
}

TEST(VerifyCommand, NominalReproducesTheRunsTestAndTheSuiteResumes) {
  const fs::path d = fs::temp_directory_path() / ("codesign_verify_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  codesign::test::TinyRun tiny = codesign::test::TinyRun::minimal();
  tiny.total_timesteps = 16;
  tiny.exploration_end = 8;
  tiny.exploitation_start = 12;
  tiny.eval_episodes = 2;
  tiny.fixed_theta_phases = 0;
  std::ofstream(d / "r.toml") << tiny.toml();
  const fs::path run = d / "run";
  auto r = run_codesign("--config " + (d / "r.toml").string() + " -o " + run.string() + " --quiet --no-figures");
  ASSERT_EQ(r.status, 0) << r.output;

  r = run_codesign("verify --run " + run.string() + " --phases 2 --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verify: 9 conditions run now, 0 before"), std::string::npos) << r.output;
  const std::string csv = slurp(run / "verify" / "conditions.csv");
  const std::size_t rows = static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) - 1;
  EXPECT_EQ(rows, codesign::run::verify_suite().size());
  // Both print doubles to round-trip exactly, so equal text is the same number.
  const std::string nominal = csv.substr(csv.find("\nnominal,") + 9);
  EXPECT_EQ(nominal.substr(0, nominal.find(',')), best_value(slurp(run / "result.toml"), "test_return"));
  EXPECT_TRUE(fs::exists(run / "verify" / "report.md"));

  r = run_codesign("verify --run " + run.string() + " --phases 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verify: 0 conditions run now, 9 before"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(run / "verify" / "conditions.csv"), csv);

  // Other settings on the same folder: refused without --force, nothing changed.
  r = run_codesign("verify --run " + run.string() + " --phases 3");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("holds a verify with other settings"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(run / "verify" / "conditions.csv"), csv);

  fs::remove(run / "policy.bin");
  r = run_codesign("verify --run " + run.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("policy.bin: not found; verify needs a finished co-design run folder"), std::string::npos)
      << r.output;
  fs::remove_all(d);
}

}  // namespace
