// End-to-end checks of `codesign baseline pid`, `codesign sweep`, `codesign refine` and
// `codesign evaluate`: bad input is one message naming file, key and range with exit status 2 and
// no earlier output touched; refine on a finished (tiny) run appends [refined] to result.toml and
// keeps every other byte; evaluate ranks designs of a finished run at T2 into RUN/evaluate/t2/.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;

// 2 designs x 5 decisions per iteration, tiny networks: a finished run folder in seconds.
const std::string kTinyRun = [] {
  codesign::test::TinyRun r;
  r.batch_size = 5;
  r.n_epochs = 1;
  r.hidden = "[8]";
  r.total_timesteps = 40;
  r.designs_per_update = 2;
  r.exploration_end = 10;
  r.exploitation_start = 20;
  r.eval_episodes = 2;
  r.seed = 5;
  return r.toml();
}();

fs::path scratch(const std::string& name) {
  return codesign::test::scratch_dir("codesign_baselines_", name);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

TEST(BaselinesCli, BadPidOrSweepConfigIsOneMessageAndWritesNothing) {
  const fs::path dir = scratch("badcfg");
  write(dir / "bad_pid.toml", "[pid]\nkd_range = [0.3, 0.1]\n");
  auto r = run_codesign("baseline pid --config " + (dir / "bad_pid.toml").string() + " -o " + (dir / "b").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "codesign: error: " + (dir / "bad_pid.toml").string() +
                          ": pid.kd_range: lower bound 0.300000 is above upper bound 0.100000\n");
  EXPECT_FALSE(fs::exists(dir / "b"));
  // An earlier sweep's output stays as it was.
  fs::create_directories(dir / "s");
  write(dir / "s" / "sweep.csv", "earlier\n");
  write(dir / "bad_sweep.toml", "[sweep]\nfixed_theta_scan_points = 2\n");
  r = run_codesign("sweep --config " + (dir / "bad_sweep.toml").string() + " -o " + (dir / "s").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("sweep.fixed_theta_scan_points: value 2 is out of range; allowed [3, 1001]"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(slurp(dir / "s" / "sweep.csv"), "earlier\n");
  r = run_codesign("baseline pid --config " + (dir / "bad_pid.toml").string() + " --design 110 -o x");
  EXPECT_EQ(r.status, 2);
}

TEST(BaselinesCli, BadEstimatorFitEpisodesIsOneMessageAndWritesNothing) {
  const fs::path dir = scratch("badfit");
  write(dir / "bad_fit.toml", "[pid]\nestimator_fit_episodes = 0\n");
  const auto r = run_codesign("baseline pid --config " + (dir / "bad_fit.toml").string() + " -o " + (dir / "b").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "codesign: error: " + (dir / "bad_fit.toml").string() +
                          ": pid.estimator_fit_episodes: value 0 is out of range; allowed [1, 1000]\n");
  EXPECT_FALSE(fs::exists(dir / "b"));
}

TEST(BaselinesCli, RefineNeedsARunFolder) {
  const fs::path dir = scratch("norun");
  const auto r = run_codesign("refine --run " + dir.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "codesign: error: " + dir.string() +
                          ": has no config.toml; refine needs a finished co-design run folder\n");
}

TEST(BaselinesCli, RefineAppendsItsTableAndKeepsEveryOtherByte) {
  const fs::path dir = scratch("refine");
  write(dir / "tiny.toml", kTinyRun);
  const fs::path run = dir / "run";
  auto r = run_codesign("run --config " + (dir / "tiny.toml").string() + " -o " + run.string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string before = slurp(run / "result.toml");
  const std::string policy = slurp(run / "policy.bin");
  r = run_codesign("refine --run " + run.string() + " --phases 1 --starts 1 --max-evals 2 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("refine: before p = ["), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("refine: after  p = ["), std::string::npos) << r.output;
  const std::string after = slurp(run / "result.toml");
  ASSERT_GT(after.size(), before.size());
  EXPECT_EQ(after.substr(0, before.size()), before);
  EXPECT_EQ(after.substr(before.size(), 10), "\n[refined]");
  EXPECT_EQ(slurp(run / "policy.bin"), policy);
  // Refining again replaces the table instead of adding a second one.
  r = run_codesign("refine --run " + run.string() + " --phases 1 --starts 1 --max-evals 2 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string again = slurp(run / "result.toml");
  EXPECT_EQ(again, after);  // deterministic: the same search, the same table
}

TEST(BaselinesCli, EvaluateRanksARunsDesignsAndRefusesBadInput) {
  const fs::path dir = scratch("evaluate");
  auto r = run_codesign("evaluate --run " + dir.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "codesign: error: " + dir.string() +
                          ": has no config.toml; evaluate needs a co-design run folder\n");
  write(dir / "tiny.toml", kTinyRun);
  const fs::path run = dir / "run";
  r = run_codesign("run --config " + (dir / "tiny.toml").string() + " -o " + run.string() + " --quiet --no-figures");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"checkpoint_t1.bin", "checkpoint_t2.bin"}) EXPECT_TRUE(fs::exists(run / f)) << f;
  r = run_codesign("evaluate --run " + run.string() + " --at t3");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--at"), std::string::npos) << r.output;
  r = run_codesign("evaluate --run " + run.string() + " --designs 3-2");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--designs"), std::string::npos) << r.output;
  r = run_codesign("evaluate --run " + run.string() + " --phases 1");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_FALSE(fs::exists(run / "evaluate"));
  r = run_codesign("evaluate --run " + run.string() + " --at t2 --designs 20-22 --phases 2 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("evaluate: t = 20;"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("evaluate: d* (leading design) j"), std::string::npos) << r.output;
  const std::string ranking = slurp(run / "evaluate" / "t2" / "ranking.csv");
  EXPECT_EQ(ranking.substr(0, ranking.find('\n')),
            "rank,design,n,l_mm,w_mm,p1_kPa,p2_kPa,q,score,samples,mean_return,std_return,ci95,band_fraction,"
            "episodes,seconds,role");
  EXPECT_EQ(std::count(ranking.begin(), ranking.end(), '\n'), 4);  // header + 3 designs
  // --pressures-of: a folder that is no run is one message, exit 2, nothing written; the run's own
  // folder gives the same rows as the plain evaluation, in a folder of their own.
  r = run_codesign("evaluate --run " + run.string() + " --at t2 --designs 20-22 --phases 2 --threads 1 --pressures-of " +
                   (dir / "nothing").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("codesign: error: --pressures-of: " + (dir / "nothing").string() + " has no config.toml"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(run / "evaluate" / "t2_pressures_of_nothing"));
  r = run_codesign("evaluate --run " + run.string() + " --at t2 --designs 20-22 --phases 2 --threads 1 --pressures-of " +
                   run.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("evaluate: d* of " + run.string() + " (its leading design at t2) j"), std::string::npos)
      << r.output;
  const std::string crossed = slurp(run / "evaluate" / "t2_pressures_of_run" / "ranking.csv");
  const auto without_seconds = [](const std::string& csv) {  // the seconds column is wall time
    std::istringstream in(csv);
    std::string line, out;
    while (std::getline(in, line)) {
      const std::size_t last = line.rfind(','), before = line.rfind(',', last - 1);
      out += line.substr(0, before) + line.substr(last) + "\n";
    }
    return out;
  };
  EXPECT_EQ(without_seconds(crossed), without_seconds(ranking));
}

}  // namespace
