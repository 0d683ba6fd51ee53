// The run folder's result files (run_folder.hpp): result.toml written and read back, the
// evaluation CSVs' columns with and without an estimator, the [refined] table written in place,
// and bad input naming the file and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/errors.hpp"
#include "io/formats/csv_table.hpp"
#include "run/run_folder.hpp"
#include "test_files.hpp"

namespace codesign::run {
namespace {

using namespace core;  // the core types these tests build

namespace fs = std::filesystem;

using codesign::test_files::slurp;

// A fresh folder that exists (the writers below expect their run folder).
fs::path fresh_dir(const std::string& name) {
  const fs::path d = test_files::fresh_dir("run_folder_" + name);
  fs::create_directories(d);
  return d;
}

DesignEvaluation sample_evaluation(int design, double p1, double p2) {
  DesignEvaluation e;
  e.setup = {design, p1, p2, 0.0, 0.0};
  e.returns = {10.5, 11.5};
  e.band_fraction = {0.5, 0.75};
  e.decisions = {50, 50};
  e.reasons = {"truncated", "truncated"};
  e.mean_return = 11.0;
  e.std_return = 0.5;
  e.mean_band_fraction = 0.625;
  for (int k = 0; k < 3; ++k) {
    TraceRow r;
    r.decision = k;
    r.t_s = 0.01 * k;
    r.theta_rad = 0.001 * k;
    r.force_mN = 20.0 + k;
    r.strain = 1e-4 * (k + 1);
    r.tip_mm = Eigen::Vector3d(1.0 + k, 2.0, 3.0);
    r.plate_z_mm = -4.0;
    r.action = 0.25;
    e.trace.push_back(r);
  }
  return e;
}

ResultFile sample_result() {
  ResultFile r;
  r.eval_episodes = 2;
  r.best = result_design(sample_evaluation(21, 0.069, 0.0));
  r.runner_up = result_design(sample_evaluation(63, 10.0, 10.0));
  r.fixed_theta = ResultFixedTheta{0.01, 8, 4.5, 0.25, 0.3};
  r.run = {6000, 3, 7, "proprioceptive", "none", 1, 12.5};
  return r;
}

TEST(RunFolder, ResultTomlRoundTripsItsDesigns) {
  const fs::path d = fresh_dir("round_trip");
  const ResultFile r = sample_result();
  write_result(d, r);
  const std::string text = slurp(d / run_file::kResult);
  // The tables and keys every reader of the file relies on.
  for (const char* key : {"[best]\ndesign = 21\nn = 1\n", "[runner_up]\ndesign = 63\nn = 2\n", "[best_fixed_theta]",
                          "[run]\ntimesteps = 6000\niterations = 3\nseed = 7\nobservation = \"proprioceptive\"\n"
                          "baseline = \"none\"\nnumerical_failures = 1"})
    EXPECT_NE(text.find(key), std::string::npos) << key << " missing from:\n" << text;
  const std::optional<ResultDesign> best = read_result_design(d, "best");
  ASSERT_TRUE(best);
  EXPECT_EQ(best->setup.design, 21);
  EXPECT_EQ(best->setup.p1_kPa, 0.069);  // CsvLog::num keeps the bits
  EXPECT_EQ(best->setup.p2_kPa, 0.0);
  EXPECT_EQ(best->test_return, 11.0);
  EXPECT_EQ(best->test_return_std, 0.5);
  EXPECT_EQ(best->test_episodes, 2);
  EXPECT_EQ(best->band_fraction, 0.625);
  const std::optional<ResultDesign> runner = read_result_design(d, "runner_up");
  ASSERT_TRUE(runner);
  EXPECT_EQ(runner->setup.design, 63);
  EXPECT_EQ(runner->setup.p2_kPa, 10.0);
  // A single-design run has no runner-up: no table, no error.
  ResultFile single = r;
  single.runner_up.reset();
  write_result(d, single);
  EXPECT_FALSE(read_result_design(d, "runner_up"));
}

TEST(RunFolder, BadResultNamesTheFileAndTheKey) {
  const fs::path d = fresh_dir("bad");
  auto message = [&](const std::string& text) {
    std::ofstream(d / run_file::kResult, std::ios::binary) << text;
    try {
      read_result_design(d, "best");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return std::string();
  };
  const std::string range = message("[best]\ndesign = 110\npressures_kPa = [1, 0]\n");
  EXPECT_NE(range.find("result.toml"), std::string::npos) << range;
  EXPECT_NE(range.find("best.design"), std::string::npos) << range;
  EXPECT_NE(range.find("109"), std::string::npos) << range;
  const std::string missing = message("[best]\npressures_kPa = [1, 0]\n");
  EXPECT_NE(missing.find("best.design"), std::string::npos) << missing;
  const std::string one = message("[best]\ndesign = 3\npressures_kPa = [1]\n");
  EXPECT_NE(one.find("best.pressures_kPa"), std::string::npos) << one;
  // A caller's pressure bound (refine: the run's task.pressure_max_kPa) is the reader's range.
  std::ofstream(d / run_file::kResult, std::ios::binary) << "[best]\ndesign = 3\npressures_kPa = [25, 0]\n";
  EXPECT_EQ(read_result_design(d, "best")->setup.p1_kPa, 25.0);
  try {
    read_result_design(d, "best", 20.0);
    ADD_FAILURE() << "no error for p1 = 25 kPa above a bound of 20";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("best.pressures_kPa"), std::string::npos) << m;
    EXPECT_NE(m.find("20"), std::string::npos) << m;
  }
  fs::remove(d / run_file::kResult);
  EXPECT_THROW(read_result_design(d, "best"), InputError);
}

TEST(RunFolder, EvaluationCsvsHaveOneLayoutAndTheEstimatorColumnLast) {
  const fs::path d = fresh_dir("eval") / run_file::kEvalDir;  // created by the writer
  const DesignEvaluation e = sample_evaluation(21, 1.0, 0.0);
  write_evaluation(d, "best", e);
  const io::CsvTable episodes = io::read_csv((d / "best.csv").string());
  EXPECT_EQ(episodes.columns(), (std::vector<std::string>{"episode", "phase_rad", "return", "decisions",
                                                          "band_fraction", "reason"}));
  ASSERT_EQ(episodes.rows(), 2u);
  EXPECT_EQ(episodes.number(1, episodes.column("return")), 11.5);
  EXPECT_EQ(episodes.number(1, episodes.column("phase_rad")), evaluation_phase(1, 2));
  const std::vector<std::string> trace_columns{"decision", "t_s",      "theta_rad",  "F_mN",   "strain",
                                               "tip_x_mm", "tip_y_mm", "tip_z_mm",   "plate_z_mm", "action"};
  const io::CsvTable trace = io::read_csv((d / "best_trace.csv").string());
  EXPECT_EQ(trace.columns(), trace_columns);
  ASSERT_EQ(trace.rows(), 3u);
  EXPECT_EQ(trace.number(2, trace.column("tip_x_mm")), 3.0);
  // With an estimator (the PI on F̂), the same columns and F̂ = (ε − c0 − c2 θ)/c1 last.
  const ForceEstimator est{1e-5, 1e-5, 0.01};
  write_evaluation(d, "pid_estimate", e, &est);
  const io::CsvTable with = io::read_csv((d / "pid_estimate_trace.csv").string());
  std::vector<std::string> more = trace_columns;
  more.push_back("F_hat_mN");
  EXPECT_EQ(with.columns(), more);
  for (std::size_t r = 0; r < with.rows(); ++r)
    EXPECT_DOUBLE_EQ(with.number(r, with.column("F_hat_mN")), est.force_mN(e.trace[r].strain, e.trace[r].theta_rad));
}

TEST(RunFolder, RefinedTableIsWrittenIntoResultTomlAtomically) {
  const fs::path d = fresh_dir("refined");
  write_result(d, sample_result());
  const std::string before = slurp(d / run_file::kResult);
  RefineResult r;
  r.design = 21;
  r.p_before = {0.069, 0.0};
  r.p_after = {1.25, 0.0};
  r.test_after.returns = {4.8, 5.0};
  write_refined_result(d, r);
  EXPECT_EQ(slurp(d / run_file::kResult), with_refined_table(before, r));
  EXPECT_FALSE(fs::exists(d / (std::string(run_file::kResult) + ".tmp")));
  EXPECT_THROW(write_refined_result(fresh_dir("refined_none"), r), InputError);
}

}  // namespace
}  // namespace codesign::run
