// Numerical failure injection end to end: a tiny co-design run with [faults] ends exactly the
// chosen episodes with a "numerical: ..." reason in episodes.csv, goes on to the end, and counts
// them in result.toml [run] numerical_failures and in its summary.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "file_text.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::csv_cells;
using codesign::test::run_codesign;

// 6 iterations of 4 environments x 2 decisions; faults before the first decision.
const std::string kRun = [] {
  codesign::test::TinyRun r = codesign::test::TinyRun::minimal();
  r.total_timesteps = 48;
  r.exploration_end = 16;
  r.exploitation_start = 32;
  r.eval_episodes = 2;
  r.checkpoint_every = 8;
  r.seed = 5;
  r.tables = "[faults]\nnan_pressure_every = 3\ninverted_element_every = 5\nat_decision = 0\n";
  return r.toml();
}();

TEST(FaultInjectionRun, InjectedFailuresEndOnlyTheirEpisodesAndAreCounted) {
  const fs::path d = fs::temp_directory_path() / ("codesign_faults_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream(d / "faults.toml") << kRun;
  const auto r = run_codesign("--config " + (d / "faults.toml").string() + " -o " + (d / "run").string() +
                              " --quiet --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;

  // Expected per iteration k: environment i's first episode is faulted when c = 4k + i + 1 is a
  // multiple of 3 (NaN pressure) or else of 5 (inverted element).
  std::map<int, int> nan_expected, inv_expected;
  int total_expected = 0;
  for (int k = 0; k < 6; ++k)
    for (int i = 0; i < 4; ++i) {
      const int c = 4 * k + i + 1;
      if (c % 3 == 0) ++nan_expected[k], ++total_expected;
      else if (c % 5 == 0) ++inv_expected[k], ++total_expected;
    }
  ASSERT_EQ(total_expected, 11);  // c = 3, 6, 9, 12, 15, 18, 21, 24 (NaN) and 5, 10, 20 (inverted)

  std::ifstream in(d / "run" / "episodes.csv");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_cells(line);
  ASSERT_EQ(header.back(), "reason");
  std::map<int, int> nan_seen, inv_seen;
  int rows = 0, numerical = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = csv_cells(line);
    ASSERT_EQ(c.size(), header.size()) << line;
    ++rows;
    const int k = std::stoi(c[1]);
    const std::string& reason = c.back();
    if (reason.rfind("numerical:", 0) != 0) continue;
    ++numerical;
    EXPECT_EQ(c[12], "1") << "only first episodes are faulted: " << line;
    EXPECT_EQ(c[10], "1") << "ends at its first decision: " << line;
    if (reason.rfind("numerical: non_finite: ", 0) == 0) ++nan_seen[k];
    else if (reason.rfind("numerical: inverted_element: ", 0) == 0) ++inv_seen[k];
    else ADD_FAILURE() << "unexpected reason " << reason;
  }
  EXPECT_EQ(nan_seen, nan_expected);
  EXPECT_EQ(inv_seen, inv_expected);
  EXPECT_EQ(numerical, total_expected);
  EXPECT_GT(rows, numerical);  // the faulted environments restarted and went on

  std::ifstream res(d / "run" / "result.toml");
  std::stringstream text;
  text << res.rdbuf();
  EXPECT_NE(text.str().find("numerical_failures = " + std::to_string(total_expected) + " "), std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("timesteps = 48\n"), std::string::npos) << text.str();
  EXPECT_NE(r.output.find("codesign: " + std::to_string(total_expected) + " training episodes ended by a numerical failure"),
            std::string::npos)
      << r.output;
  // The resolved config keeps the [faults] table, so a resume injects the same faults.
  std::ifstream cfg(d / "run" / "config.toml");
  std::stringstream ctext;
  ctext << cfg.rdbuf();
  EXPECT_NE(ctext.str().find("[faults]\nnan_pressure_every = 3\ninverted_element_every = 5\nat_decision = 0\n"),
            std::string::npos)
      << ctext.str();
  fs::remove_all(d);
}

}  // namespace
