// `codesign verify` on a tiny finished run: the nominal cells of d* and the runner-up at the run's
// own test phases reproduce result.toml's test returns to the bit (the same deterministic
// episodes); every subject gets a row per condition of the suite; the force PID is blind to the
// gauge; a second call resumes with nothing left to run; other settings are refused without
// --force; a folder that is no finished run is one clear message and exit 2.
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

// The value of `key = ` in table `table` of result.toml.
std::string result_value(const std::string& result, const std::string& table, const std::string& key) {
  const std::size_t at = result.find("\n" + key + " = ", result.find("[" + table + "]"));
  const std::size_t from = at + key.size() + 4;
  return result.substr(from, result.find_first_of(" \n", from) - from);
}

// The mean_return cell of (subject, condition) in conditions.csv ("" if absent).
std::string mean_cell(const std::string& csv, const std::string& subject, const std::string& condition) {
  std::istringstream in(csv);
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> c = codesign::test::csv_cells(line);
    if (c.size() > 6 && c[0] == subject && c[5] == condition) return c[6];
  }
  return "";
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
  // d*, the runner-up, two next designs, two outside bodies and the two PIDs.
  const std::size_t cells = 8 * codesign::run::verify_suite().size();
  EXPECT_NE(r.output.find("verify: " + std::to_string(cells) + " cells run now, 0 before"), std::string::npos)
      << r.output;
  const std::string csv = slurp(run / "verify" / "conditions.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) - 1, cells);
  // Both print doubles to round-trip exactly, so equal text is the same number: the nominal cells
  // of d* and the runner-up are the run's own final tests (same policy, pressures and phases).
  const std::string result = slurp(run / "result.toml");
  EXPECT_EQ(mean_cell(csv, "d*", "nominal"), result_value(result, "best", "test_return"));
  EXPECT_EQ(mean_cell(csv, "runner_up", "nominal"), result_value(result, "runner_up", "test_return"));
  // The force PID reads the true contact force: the gauge's gain and noise cannot change it.
  for (const char* c : {"gain_-10%", "gain_+10%", "strain_noise"})
    EXPECT_EQ(mean_cell(csv, "pid_force", c), mean_cell(csv, "pid_force", "nominal")) << c;
  const std::string report = slurp(run / "verify" / "report.md");
  for (const auto& s : codesign::run::verify_suite())
    EXPECT_NE(report.find("\n- " + s.name + ": d* (j"), std::string::npos) << s.name << "\n" << report;
  EXPECT_TRUE(fs::exists(run / "verify" / "verify.png")) << r.output;

  r = run_codesign("verify --run " + run.string() + " --phases 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verify: 0 cells run now, " + std::to_string(cells) + " before"), std::string::npos)
      << r.output;
  EXPECT_EQ(slurp(run / "verify" / "conditions.csv"), csv);

  // The validation phases go to a folder of their own; without the next designs and the PIDs the
  // subjects are d*, the runner-up and the two outside bodies. Other phases, other returns.
  r = run_codesign("verify --run " + run.string() + " --phases 2 --phase-set validation --next 0 --no-baselines");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verify: 36 cells run now, 0 before"), std::string::npos) << r.output;
  const std::string validation = slurp(run / "verify_validation" / "conditions.csv");
  EXPECT_NE(mean_cell(validation, "d*", "nominal"), mean_cell(csv, "d*", "nominal"));
  EXPECT_EQ(mean_cell(validation, "next_1", "nominal"), "");
  EXPECT_EQ(mean_cell(validation, "pid_force", "nominal"), "");

  // Specialists: a fresh policy trained on each tested design of the run alone, in folders of their
  // own, then tested as subjects; the cells done before are kept.
  r = run_codesign("verify --run " + run.string() +
                   " --phases 2 --next 0 --no-baselines --specialists --specialist-timesteps 16 --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  // d*, the runner-up and the two outside bodies, each with its specialist (4 × 9 new cells).
  EXPECT_NE(r.output.find("verify: 36 cells run now, 36 before"), std::string::npos) << r.output;
  const std::string with_specialists = slurp(run / "verify" / "conditions.csv");
  EXPECT_EQ(with_specialists.substr(0, csv.size()), csv);  // the earlier cells as they were
  std::size_t own = 0;
  for (std::size_t at = with_specialists.find("\nown_j"); at != std::string::npos;
       at = with_specialists.find("\nown_j", at + 1))
    ++own;
  EXPECT_EQ(own, 36u);
  const std::string best = result_value(result, "best", "design");
  EXPECT_TRUE(fs::exists(run / "verify" / "specialists" / ("j" + best + "_s1") / "result.toml"));
  EXPECT_NE(slurp(run / "verify" / "report.md").find("; own_j" + best + "_s1 "), std::string::npos);

  // A subset of the suite: the cells it names, kept from before; an unknown name is refused before
  // anything is written.
  r = run_codesign("verify --run " + run.string() + " --phases 2 --no-baselines --next 0 --conditions modulus_+20% nominal");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("verify: 0 cells run now, 8 before"), std::string::npos) << r.output;
  const std::string subset = slurp(run / "verify" / "report.md");
  EXPECT_NE(subset.find("\n- modulus_+20%: d* (j"), std::string::npos) << subset;
  EXPECT_EQ(subset.find("\n- plate_x0.5:"), std::string::npos) << subset;
  r = run_codesign("verify --run " + run.string() + " --phases 2 --conditions modulus_+30%");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--conditions: \"modulus_+30%\" is not a condition of the suite; allowed: nominal, "),
            std::string::npos)
      << r.output;

  // Other settings on the same folder: refused without --force, nothing changed.
  r = run_codesign("verify --run " + run.string() + " --phases 3");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("holds a verify with other settings"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(run / "verify" / "conditions.csv"), with_specialists);

  fs::remove(run / "policy.bin");
  r = run_codesign("verify --run " + run.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("policy.bin: not found; verify needs a finished co-design run folder"), std::string::npos)
      << r.output;
  fs::remove_all(d);
}

}  // namespace
