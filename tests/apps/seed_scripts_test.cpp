// The seed-study scripts whose figures docs/journal/results.md quotes: scripts/seed_table.sh
// with its 95 % interval column and scripts/training_seeds.sh, on run folders written here with
// hand-chosen numbers, against statistics worked out by hand.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "run_binary.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::RunResult;

std::string script(const std::string& name) { return std::string(CODESIGN_SOURCE_DIR) + "/scripts/" + name; }

// RUNS/arm-s<seed>/episodes.csv with the given rows (t, return, first; the other columns filler).
void write_episodes(const fs::path& runs, int seed, const std::string& rows) {
  const fs::path d = runs / ("arm-s" + std::to_string(seed));
  fs::create_directories(d);
  std::ofstream(d / "episodes.csv") << "t,k,j,n,l_mm,w_mm,p1_kPa,p2_kPa,phase_rad,return,decisions,in_band,first,reason\n"
                                    << rows;
}

std::string row(int t, double ret, int first) {
  return std::to_string(t) + ",0,4,1,20,4,18.5,0,0.5," + std::to_string(ret) + ",50,40," + std::to_string(first) +
         ",rollout_end\n";
}

// Seed figures 2, 4, 6 in the window (20, 40]: mean 4, sample std 2, and the 95 % interval
// 4 ± 4.303 · 2 / √3 = 4 ± 4.9687, i.e. -0.97 to 8.97. Episodes outside the window or with
// first = 0 (not fed to Algorithm 2) must not count.
TEST(SeedScripts, TrainingSeedsAveragesTheWindowAcrossSeeds) {
  const fs::path runs = codesign::test::scratch_dir("codesign_scripts_", "training");
  write_episodes(runs, 1, row(20, 100.0, 1) + row(40, 1.0, 1) + row(40, 3.0, 1) + row(40, 50.0, 0) + row(60, 100.0, 1));
  write_episodes(runs, 2, row(30, 4.0, 1));
  write_episodes(runs, 3, row(40, 6.0, 1) + row(41, -100.0, 1));
  const RunResult r = codesign::test::run_shell("bash " + script("training_seeds.sh") + " " + runs.string() +
                                                " arm \"1 2 3 4\" 20 40");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("| arm | 2.00 (2 ep.) | 4.00 (1 ep.) | 6.00 (1 ep.) | — | 4.00 ± 2.00 (3 seeds) | 4.00 ± 4.97 (-0.97 to 8.97) |"),
            std::string::npos)
      << r.output;
}

// The same three seed figures as test returns in result.toml: the interval column of seed_table.sh.
TEST(SeedScripts, SeedTableIntervalColumn) {
  const fs::path runs = codesign::test::scratch_dir("codesign_scripts_", "seed_table");
  int seed = 1;
  for (double m : {2.0, 4.0, 6.0}) {
    const fs::path d = runs / ("arm-s" + std::to_string(seed++));
    fs::create_directories(d);
    std::ofstream(d / "result.toml") << "[best]\ndesign = 4\ntest_return = " << m
                                     << "\ntest_return_std = 0.5\ntest_episodes = 100\nband_fraction = 0.99\n";
  }
  RunResult r = codesign::test::run_shell("bash " + script("seed_table.sh") + " " + runs.string() + " arm \"1 2 3\" interval");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("| 4.00 ± 2.00 (3 seeds) | 4.00 ± 4.97 (-0.97 to 8.97) |"), std::string::npos) << r.output;
  r = codesign::test::run_shell("bash " + script("seed_table.sh") + " " + runs.string() + " arm \"1 2 3\" intervals");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("the fourth argument is 'interval' or nothing"), std::string::npos) << r.output;
}

}  // namespace
