// `codesign evaluate`'s core: a run's policy at a kept state tested on a range of designs,
// ranked, resumable, and bad input refused with a message naming what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "base/errors.hpp"
#include "run/checkpoint.hpp"
#include "run/run_evaluation.hpp"
#include "test_files.hpp"
#include "io/csv_table.hpp"
#include "io/toml_reader.hpp"
#include "test_setup.hpp"

namespace {

namespace fs = std::filesystem;
using namespace codesign;
using namespace codesign::core;
using namespace codesign::run;
using codesign::test_files::slurp;

// One finished tiny run shared by the tests (T1 = 40, T2 = 80, 120 decisions).
const fs::path& finished_run() {
  static const fs::path dir = [] {
    const fs::path d = fs::path(::testing::TempDir()) / ("codesign_evaluate_run_" + std::to_string(::getpid()));
    fs::remove_all(d);
    RunOptions o;
    o.dir = d.string();
    o.threads = 2;
    o.progress = false;
    EXPECT_TRUE(run_codesign(test::tiny_run(), o).completed);
    return d;
  }();
  return dir;
}

RunEvaluationOptions options(const std::string& at, int first, int last) {
  RunEvaluationOptions o;
  o.dir = finished_run().string();
  o.at = at;
  o.first_design = first;
  o.last_design = last;
  o.threads = 2;
  o.progress = false;
  return o;
}

// The d* row of the final state is the run's own final evaluation of d*: the same policy, the
// same p* (the collapsed latent) and the same plate phases, so the same number to the bit.
TEST(RunEvaluation, FinalStateGivesDStarTheRunsOwnTestReturn) {
  io::TableReader best = io::TableReader::from_file((finished_run() / "result.toml").string()).table("best");
  const int dstar = static_cast<int>(best.integer("design", 0, 0, 109));
  const double run_return = best.number("test_return", 0.0, -1e9, 1e9);
  RunEvaluationOptions o = options("final", dstar, dstar);
  o.force = true;
  const RunEvaluationSummary s = evaluate_run(test::tiny_run(), o);
  EXPECT_EQ(s.t, 120);
  EXPECT_EQ(s.leading_design, dstar);
  ASSERT_EQ(s.ranking.size(), 1u);
  EXPECT_EQ(s.ranking[0].design, dstar);
  EXPECT_EQ(s.ranking[0].role, "d*");
  EXPECT_EQ(s.ranking[0].episodes, test::tiny_run().loop.codesign.eval_episodes);
  // result.toml prints 17 significant digits: the double read back is the double written.
  EXPECT_EQ(s.ranking[0].mean_return, run_return);
  const std::vector<double> p = best.numbers("pressures_kPa", {0.0, 0.0}, 0.0, 20.0, 2, 2);
  EXPECT_EQ(s.ranking[0].p1_kPa, p[0]);
  EXPECT_EQ(s.ranking[0].p2_kPa, p[1]);
}

// At T2: the kept state's t; rows by test return with ranks 1..n; the 95 % interval from the
// sample std; a stopped evaluation continues after its last whole row and ends with the same rows.
TEST(RunEvaluation, RanksTheRangeAndContinuesAfterItsLastWholeRow) {
  RunEvaluationOptions o = options("t2", 10, 13);
  o.force = true;
  o.phases = 4;
  const RunEvaluationSummary whole = evaluate_run(test::tiny_run(), o);
  EXPECT_EQ(whole.t, 80);
  EXPECT_EQ(whole.designs_run, 4);
  ASSERT_EQ(whole.ranking.size(), 4u);
  for (std::size_t i = 0; i < whole.ranking.size(); ++i) {
    const RunEvaluationRow& r = whole.ranking[i];
    EXPECT_EQ(r.rank, static_cast<int>(i) + 1);
    if (i > 0) {
      EXPECT_GE(whole.ranking[i - 1].mean_return, r.mean_return);
    }
    // n = 4 phases: population std s_p, sample std s_p·sqrt(4/3), interval 1.96·s/sqrt(4).
    EXPECT_NEAR(r.ci95, 1.96 * r.std_return * std::sqrt(4.0 / 3.0) / 2.0, 1e-12 * (1.0 + r.ci95));
    EXPECT_EQ(r.episodes, 4);
  }
  const fs::path folder = finished_run() / "evaluate" / "t2";
  for (const char* f : {"evaluate.toml", "designs.csv", "ranking.csv", "ranking.dat"})
    EXPECT_TRUE(fs::exists(folder / f)) << f;
  EXPECT_FALSE(fs::exists(folder / ".lock"));
  // Keep the header and the first row, and half of the second: as a kill would leave it.
  const std::string csv = slurp(folder / "designs.csv");
  const std::size_t row1 = csv.find('\n', csv.find('\n') + 1) + 1;
  {
    std::ofstream out(folder / "designs.csv", std::ios::binary | std::ios::trunc);
    out << csv.substr(0, row1) << csv.substr(row1, 12);
  }
  o.force = false;
  const RunEvaluationSummary resumed = evaluate_run(test::tiny_run(), o);
  EXPECT_EQ(resumed.designs_before, 1);
  EXPECT_EQ(resumed.designs_run, 3);
  ASSERT_EQ(resumed.ranking.size(), whole.ranking.size());
  for (std::size_t i = 0; i < whole.ranking.size(); ++i) {
    EXPECT_EQ(resumed.ranking[i].design, whole.ranking[i].design);
    EXPECT_EQ(resumed.ranking[i].mean_return, whole.ranking[i].mean_return);
    EXPECT_EQ(resumed.ranking[i].role, whole.ranking[i].role);
  }
  EXPECT_EQ(io::read_csv((folder / "designs.csv").string()).rows(), 4u);
}

TEST(RunEvaluation, BadInputNamesTheDefectAndChangesNothing) {
  const auto message = [](const RunEvaluationOptions& o, const RunSettings& s = test::tiny_run()) -> std::string {
    try {
      evaluate_run(s, o);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(message(options("t3", 0, 0)).find("--at: 't3' is not one of final, t1, t2"), std::string::npos);
  EXPECT_NE(message(options("final", 5, 4)).find("--designs: 5-4"), std::string::npos);
  EXPECT_NE(message(options("final", 0, 110)).find("--designs: 0-110"), std::string::npos);
  RunEvaluationOptions one = options("final", 0, 0);
  one.phases = 1;
  EXPECT_NE(message(one).find("--phases: 1 is not in [2, 100000]"), std::string::npos);
  RunEvaluationOptions missing = options("final", 0, 0);
  missing.dir = (finished_run() / "no_such_folder").string();
  EXPECT_NE(message(missing).find("no such run folder"), std::string::npos);
  // A checkpoint of another config (another seed): refused by its fingerprint.
  EXPECT_NE(message(options("t1", 0, 0), test::tiny_run(8)).find("checkpoint_t1.bin"), std::string::npos);
  // A run stopped before T1 has no checkpoint_t1.bin.
  const fs::path early = fs::path(::testing::TempDir()) / ("codesign_evaluate_early_" + std::to_string(::getpid()));
  fs::remove_all(early);
  RunOptions ro;
  ro.dir = early.string();
  ro.threads = 2;
  ro.progress = false;
  ro.stop_after = 20;
  ASSERT_FALSE(run_codesign(test::tiny_run(), ro).completed);
  RunEvaluationOptions before_t1 = options("t1", 0, 0);
  before_t1.dir = early.string();
  const std::string m = message(before_t1);
  EXPECT_NE(m.find("checkpoint_t1.bin: no such checkpoint"), std::string::npos) << m;
  EXPECT_FALSE(fs::exists(early / "evaluate"));
  // Another evaluation of the same state with other settings: refused unless forced, the folder
  // left as it was.
  RunEvaluationOptions first = options("t1", 20, 20);
  first.force = true;
  first.phases = 2;
  evaluate_run(test::tiny_run(), first);
  const fs::path folder = finished_run() / "evaluate" / "t1";
  const std::string before = slurp(folder / "designs.csv") + slurp(folder / "ranking.csv");
  RunEvaluationOptions other = options("t1", 20, 20);
  other.phases = 3;
  EXPECT_NE(message(other).find("holds an evaluation with other settings"), std::string::npos);
  EXPECT_EQ(slurp(folder / "designs.csv") + slurp(folder / "ranking.csv"), before);
  other.force = true;
  EXPECT_EQ(evaluate_run(test::tiny_run(), other).ranking.at(0).episodes, 3);
}

}  // namespace
