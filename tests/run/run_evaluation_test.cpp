// `codesign evaluate`'s core: a run's policy at a kept state tested on a range of designs,
// ranked, resumable, and bad input refused with a message naming what is wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "base/errors.hpp"
#include "run/checkpoint.hpp"
#include "run/codesign_tables_writer.hpp"
#include "run/run_evaluation.hpp"
#include "test_files.hpp"
#include "io/formats/csv_table.hpp"
#include "io/config/toml_reader.hpp"
#include "test_setup.hpp"

namespace {

namespace fs = std::filesystem;
using namespace codesign;
using namespace codesign::core;
using namespace codesign::run;
using codesign::test_files::slurp;

fs::path run_tiny(const std::string& name, std::uint64_t seed) {
  const fs::path d = fs::path(::testing::TempDir()) / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  RunOptions o;
  o.dir = d.string();
  o.threads = 2;
  o.progress = false;
  EXPECT_TRUE(run_codesign(test::tiny_run(seed), o).completed);
  return d;
}

// One finished tiny run shared by the tests (T1 = 40, T2 = 80, 120 decisions).
const fs::path& finished_run() {
  static const fs::path dir = run_tiny("codesign_evaluate_run", 7);
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

// --pressures-of: each design at the pressures another run's state gives it. With the run's own
// folder as the other run, the rows are the plain evaluation's to the bit (same policy, same
// pressures, same phases). The other run here is a copy of the finished run whose T2 checkpoint
// has the latent means of designs 30-33 moved and design 31 made the leader (the one it fixed) (the tiny run's
// distribution hardly moves in 120 decisions): each row's pressures are then the ones that
// state's own evaluation uses, p_max·sigmoid(μ'), and design 31 is named as its d*.
TEST(RunEvaluation, AnotherRunsPressuresAreThePressuresOfThatRunsState) {
  RunEvaluationOptions plain = options("t2", 30, 33);
  plain.force = true;
  plain.phases = 2;
  const RunEvaluationSummary own = evaluate_run(test::tiny_run(), plain);
  RunEvaluationOptions self = plain;
  self.pressures_of = finished_run().string();
  const RunEvaluationSummary same = evaluate_run(test::tiny_run(), self);
  EXPECT_EQ(same.folder, (finished_run() / "evaluate" / ("t2_pressures_of_" + finished_run().filename().string())).string());
  EXPECT_EQ(same.pressures_t, own.t);
  EXPECT_EQ(same.pressures_leading_design, own.leading_design);
  ASSERT_EQ(same.ranking.size(), own.ranking.size());
  for (std::size_t i = 0; i < own.ranking.size(); ++i) {
    EXPECT_EQ(same.ranking[i].design, own.ranking[i].design);
    EXPECT_EQ(same.ranking[i].p1_kPa, own.ranking[i].p1_kPa);
    EXPECT_EQ(same.ranking[i].mean_return, own.ranking[i].mean_return);
  }
  EXPECT_NE(slurp(fs::path(same.folder) / "evaluate.toml").find("pressures_of = "), std::string::npos);
  EXPECT_EQ(slurp(fs::path(own.folder) / "evaluate.toml").find("pressures_of"), std::string::npos);

  // The other run: the same folder with its T2 state's distribution changed.
  const fs::path moved = fs::path(::testing::TempDir()) / ("codesign_evaluate_moved_" + std::to_string(::getpid()));
  fs::remove_all(moved);
  fs::create_directories(moved);
  for (const char* f : {"config.toml", "checkpoint_t2.bin"}) fs::copy_file(finished_run() / f, moved / f);
  const RunSettings tiny = test::tiny_run();
  const std::uint64_t fp = fingerprint(resolved_run_config(tiny.spec, tiny.scene, tiny.solver, tiny.loop));
  Checkpoint c = load_checkpoint((moved / "checkpoint_t2.bin").string(), fp);
  for (int j = 30; j <= 33; ++j) c.loop.distribution.mu[static_cast<std::size_t>(j)] += Eigen::Vector2d(0.3 * (j - 29), -0.5);
  c.loop.distribution.score[31] = 1.0 + c.loop.distribution.score.maxCoeff();
  if (c.loop.distribution.collapsed) {  // the tiny run collapses at T2: make 31 the design it fixed
    c.loop.distribution.best_design = 31;
    c.loop.distribution.best_latent = c.loop.distribution.mu[31];
  }
  save_checkpoint((moved / "checkpoint_t2.bin").string(), c);
  RunEvaluationOptions theirs = plain;
  theirs.dir = moved.string();
  const RunEvaluationSummary other_own = evaluate_run(tiny, theirs);
  ASSERT_EQ(other_own.leading_design, 31);

  RunEvaluationOptions cross = plain;
  cross.pressures_of = moved.string();
  const RunEvaluationSummary crossed = evaluate_run(tiny, cross);
  EXPECT_EQ(crossed.t, own.t);
  EXPECT_EQ(crossed.pressures_leading_design, 31);
  const auto row_of = [](const RunEvaluationSummary& s, int j) {
    for (const RunEvaluationRow& r : s.ranking)
      if (r.design == j) return r;
    ADD_FAILURE() << "no row for design " << j;
    return RunEvaluationRow{};
  };
  const double p_max = tiny.loop.codesign.distribution.pressure_max_kPa;
  for (int j = 30; j <= 33; ++j) {
    const Eigen::Vector2d mu = c.loop.distribution.mu[static_cast<std::size_t>(j)];
    const double p1 = p_max / (1.0 + std::exp(-mu(0)));
    EXPECT_NEAR(row_of(crossed, j).p1_kPa, p1, 1e-12 * p_max) << j;
    EXPECT_NE(row_of(crossed, j).p1_kPa, row_of(own, j).p1_kPa) << j;
    EXPECT_EQ(row_of(crossed, j).p1_kPa, row_of(other_own, j).p1_kPa) << j;
    EXPECT_EQ(row_of(crossed, j).p2_kPa, row_of(other_own, j).p2_kPa) << j;
    EXPECT_EQ(row_of(crossed, j).q, row_of(own, j).q) << j;  // the columns of the policy's run stay its own
    EXPECT_EQ(row_of(crossed, j).mean_return == row_of(own, j).mean_return, false) << j;
  }
  if (own.leading_design != 31 && own.runner_up != 31) {
    EXPECT_EQ(row_of(crossed, 31).role, "pressures_d*");
  }
}

TEST(RunEvaluation, PressuresOfAFolderThatIsNoRunIsRefused) {
  const auto message = [](const RunEvaluationOptions& o) -> std::string {
    try {
      evaluate_run(test::tiny_run(), o);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  RunEvaluationOptions o = options("t2", 0, 0);
  o.pressures_of = (finished_run() / "no_such_run").string();
  const std::string m = message(o);
  EXPECT_NE(m.find("--pressures-of: "), std::string::npos) << m;
  EXPECT_NE(m.find("no_such_run has no config.toml"), std::string::npos) << m;
  EXPECT_FALSE(fs::exists(finished_run() / "evaluate" / "t2_pressures_of_no_such_run"));
}

}  // namespace
