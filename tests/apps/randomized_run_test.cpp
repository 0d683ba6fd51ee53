// A tiny co-design run under [randomize] end to end: config.toml carries the table, episodes.csv
// every episode's draw (inside its range; the first episodes of iteration k hold the draws
// core::draw_physics gives for the run's seed, k and its environments), and the run is the same
// on 1 and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/physics_randomization.hpp"
#include "file_text.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::csv_cells;
using codesign::test::run_codesign;
using codesign::test::slurp;

const std::string kRun = [] {
  codesign::test::TinyRun r = codesign::test::TinyRun::minimal();
  r.total_timesteps = 32;
  r.exploration_end = 16;
  r.exploitation_start = 24;
  r.eval_episodes = 2;
  r.checkpoint_every = 8;
  r.seed = 3;
  r.tables =
      "[randomize]\nyoungs_modulus = 0.25\nplate_height_mm = 0.2\npressure_error = 0.05\nstrain_gain = 0.1\n"
      "strain_noise = 0.00002\nactuation_delay = true\n";
  return r.toml();
}();

TEST(RandomizedRun, EpisodesLogTheirDrawsAndThreadsDoNotMatter) {
  const fs::path d = fs::temp_directory_path() / ("codesign_randomize_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream(d / "r.toml") << kRun;
  for (const char* threads : {"1", "2"}) {
    const auto r = run_codesign("--config " + (d / "r.toml").string() + " -o " + (d / (std::string("t") + threads)).string() +
                                " --quiet --no-figures --threads " + threads);
    ASSERT_EQ(r.status, 0) << r.output;
  }
  const std::string config = slurp(d / "t1" / "config.toml");
  EXPECT_NE(config.find("[randomize]\nyoungs_modulus = 0.25\n"), std::string::npos) << config;

  std::ifstream in(d / "t1" / "episodes.csv");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_cells(line);
  ASSERT_EQ(header.back(), "reason");
  const auto col = [&](const char* name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    ADD_FAILURE() << "no column " << name;
    return std::size_t{0};
  };
  int rows = 0;
  double lo = 2.0, hi = 0.0;
  std::map<int, std::vector<double>> first_e;  // iteration -> E scales of its first episodes
  while (std::getline(in, line)) {
    const std::vector<std::string> c = csv_cells(line);
    ASSERT_EQ(c.size(), header.size()) << line;
    const double e = std::stod(c[col("E_scale")]);
    lo = std::min(lo, e), hi = std::max(hi, e);
    EXPECT_GE(e, 0.75);
    EXPECT_LE(e, 1.25);
    EXPECT_LE(std::abs(std::stod(c[col("plate_height_offset_mm")])), 0.2);
    EXPECT_EQ(std::stod(c[col("fibre_scale")]), 1.0);  // no range given: nominal
    EXPECT_EQ(c[col("actuation_delay")], "1");
    if (c[col("first")] == "1") first_e[std::stoi(c[col("k")])].push_back(e);
    ++rows;
  }
  EXPECT_GE(rows, 16);  // 4 iterations of 4 environments at least
  EXPECT_LT(lo, hi);    // the draws differ between episodes
  codesign::core::RandomizeConfig cfg;
  cfg.youngs_modulus = 0.25, cfg.plate_height_mm = 0.2, cfg.pressure_error = 0.05, cfg.strain_gain = 0.1;
  cfg.strain_noise = 0.00002, cfg.actuation_delay = true;
  ASSERT_EQ(first_e.size(), 4u);
  for (auto& [k, got] : first_e) {
    std::vector<double> want;
    for (std::size_t env = 0; env < 4; ++env) want.push_back(codesign::core::draw_physics(cfg, 3, k, env).youngs_scale);
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    EXPECT_EQ(got, want) << "iteration " << k;  // episodes.csv prints doubles to round-trip exactly
  }
  // Threads change nothing: the logs and the result are the same files.
  for (const char* f : {"episodes.csv", "sampled.csv", "q_disc.csv", "policy.bin"})
    EXPECT_EQ(slurp(d / "t1" / f), slurp(d / "t2" / f)) << f;
  fs::remove_all(d);
}

}  // namespace
