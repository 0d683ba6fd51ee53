// The sweep's folder (run/sweep_folder.hpp): sweep.csv read back exactly, rows resumed, another
// config refused, heat maps written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.hpp"
#include "core/design_sweep.hpp"
#include "run/sweep_folder.hpp"
#include "test_files.hpp"

namespace codesign::run {
namespace {

using namespace core;
namespace fs = std::filesystem;
using codesign::test_files::slurp;

TEST(SweepFolder, CsvRowsReadBackExactly) {
  const fs::path dir = test_files::fresh_dir("sweep_csv");
  fs::create_directories(dir);
  SweepRow a;
  a.point = {63, 1.0 / 3.0, 20.0};
  a.controller = SweepController::PidStrain;
  a.gains = {0.1, 0.07086, 1e-17};
  a.setpoint = 4.25235e-4;
  a.tuning_return = 44.94;
  a.evaluations = 24;
  a.test_return = 45.55;
  a.test_std = 0.86;
  a.test_episodes = 10;
  a.band_fraction = 0.98;
  a.seconds = 12.5;
  SweepRow b = a;
  b.controller = SweepController::FixedTheta;
  b.theta0_rad = 0.020735;
  SweepRow e = a;
  e.controller = SweepController::PidEstimate;
  e.setpoint = 20.0;
  e.fit_r2 = 0.9973;
  e.fit_rms_mN = 0.6125;
  const fs::path csv = dir / "sweep.csv";
  // The last line lacks its newline: a row cut by a kill, which must be ignored.
  std::ofstream(csv, std::ios::binary) << sweep_csv_header() << '\n'
                                       << sweep_csv_line(a) << '\n'
                                       << sweep_csv_line(b) << '\n'
                                       << sweep_csv_line(e) << '\n'
                                       << sweep_csv_line(a).substr(0, 20);
  const std::vector<SweepRow> r = read_sweep_csv(csv.string());
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(sweep_csv_line(r[0]), sweep_csv_line(a));
  EXPECT_EQ(sweep_csv_line(r[1]), sweep_csv_line(b));
  EXPECT_EQ(sweep_csv_line(r[2]), sweep_csv_line(e));
  EXPECT_TRUE(std::isnan(r[0].fit_r2));  // only the estimate PID has a fit
  EXPECT_EQ(r[2].controller, SweepController::PidEstimate);
  EXPECT_EQ(r[2].fit_r2, 0.9973);
  EXPECT_EQ(r[2].fit_rms_mN, 0.6125);
  EXPECT_EQ(r[0].point.p1_kPa, 1.0 / 3.0);  // %.17g: bit-identical
  EXPECT_EQ(r[0].gains.kd, 1e-17);
  std::ofstream(csv, std::ios::binary) << "j,n\n1,1\n";
  EXPECT_THROW(read_sweep_csv(csv.string()), InputError);
  // A sweep.csv of the previous version (19 columns, no fit): read, the fit NaN.
  const std::string old_line = sweep_csv_line(b).substr(0, sweep_csv_line(b).rfind(',', sweep_csv_line(b).rfind(',') - 1));
  std::ofstream(csv, std::ios::binary | std::ios::trunc) << sweep_csv_header_without_fit() << '\n' << old_line << '\n';
  const std::vector<SweepRow> old = read_sweep_csv(csv.string());
  ASSERT_EQ(old.size(), 1u);
  EXPECT_EQ(old[0].theta0_rad, 0.020735);
  EXPECT_TRUE(std::isnan(old[0].fit_rms_mN));
}

TEST(SweepFolder, EstimatePidRowsCarryTheFitAndGetAHeatMap) {
  // The estimate PID through the sweep on a shortened task (10 decisions): its row holds the
  // fit's R² and rms, and its heat-map table is written beside the others.
  const fs::path dir = test_files::fresh_dir("sweep_estimate");
  fem::SceneConfig scene;
  scene.settle_steps = 5;
  auto sims = std::make_shared<SimulatorPool>(fem::WhiskerModelSpec{}, scene, fem::SolverConfig{});
  TaskConfig task;
  task.episode_steps = 50;
  SweepConfig sweep;
  sweep.first_design = sweep.last_design = 21;
  sweep.controllers = {SweepController::PidEstimate};
  PidTuningConfig pid;
  pid.tuning_phases = 1;
  pid.test_episodes = 1;
  pid.estimator_fit_episodes = 4;
  pid.search.starts = 1;
  pid.search.max_evals = 2;
  SweepOptions o;
  o.dir = dir.string();
  o.config_text = "# estimate sweep\n";
  o.threads = 1;
  o.progress = false;
  const SweepSummary s = run_sweep(sims, task, sweep, pid, o);
  ASSERT_EQ(s.rows.size(), 1u);
  EXPECT_EQ(s.rows[0].controller, SweepController::PidEstimate);
  EXPECT_EQ(s.rows[0].setpoint, task.target_force_mN);
  EXPECT_GT(s.rows[0].fit_r2, 0.5);
  EXPECT_LE(s.rows[0].fit_r2, 1.0);
  EXPECT_GT(s.rows[0].fit_rms_mN, 0.0);
  EXPECT_TRUE(fs::exists(dir / "heatmap_n1_pid_estimate.dat"));
}

TEST(SweepFolder, RestartSkipsFinishedRowsAndRefusesAnotherConfig) {
  const fs::path dir = test_files::fresh_dir("sweep_resume");
  fem::SceneConfig scene;
  scene.settle_steps = 5;
  auto sims = std::make_shared<SimulatorPool>(fem::WhiskerModelSpec{}, scene, fem::SolverConfig{});
  TaskConfig task;
  task.episode_steps = 25;  // 5 decisions
  SweepConfig sweep;
  sweep.first_design = sweep.last_design = 21;
  sweep.controllers = {SweepController::FixedTheta, SweepController::PidForce};
  sweep.fixed_theta = {3, 1};
  PidTuningConfig pid;
  pid.tuning_phases = 1;
  pid.test_episodes = 1;
  pid.search.starts = 1;
  pid.search.max_evals = 2;
  SweepOptions o;
  o.dir = dir.string();
  o.config_text = "# test sweep\n";
  o.threads = 1;
  o.progress = false;
  const SweepSummary first = run_sweep(sims, task, sweep, pid, o);
  EXPECT_EQ(first.rows_run, 2);
  EXPECT_EQ(first.rows_done_before, 0);
  ASSERT_EQ(first.rows.size(), 2u);
  EXPECT_EQ(first.rows[0].evaluations, 3 + 1);  // the scan, then one local evaluation
  EXPECT_EQ(first.rows[1].evaluations, 2);
  EXPECT_TRUE(fs::exists(dir / "heatmap_n1_fixed_theta.dat"));
  EXPECT_TRUE(fs::exists(dir / "heatmap_n1_pid_force.dat"));
  // Kill during a write: drop the last row and leave half of it.
  const std::string full = slurp(dir / "sweep.csv");
  const std::size_t last = full.rfind('\n', full.size() - 2) + 1;
  std::ofstream(dir / "sweep.csv", std::ios::binary | std::ios::trunc) << full.substr(0, last + 10);
  const SweepSummary second = run_sweep(sims, task, sweep, pid, o);
  EXPECT_EQ(second.rows_done_before, 1);
  EXPECT_EQ(second.rows_run, 1);
  // The run is deterministic, so the file is the same again except the rows' wall times.
  const std::vector<SweepRow> again = read_sweep_csv((dir / "sweep.csv").string());
  ASSERT_EQ(again.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    SweepRow x = again[i], y = first.rows[i];
    x.seconds = y.seconds = 0.0;
    EXPECT_EQ(sweep_csv_line(x), sweep_csv_line(y));
  }
  const SweepSummary third = run_sweep(sims, task, sweep, pid, o);
  EXPECT_EQ(third.rows_run, 0);
  EXPECT_EQ(third.rows_done_before, 2);
  // Report only: the same rows, nothing run, the CSV untouched.
  SweepOptions report = o;
  report.report_only = true;
  const std::string csv_before = slurp(dir / "sweep.csv");
  const SweepSummary fourth = run_sweep(sims, task, sweep, pid, report);
  EXPECT_EQ(fourth.rows_run, 0);
  EXPECT_EQ(fourth.rows.size(), 2u);
  EXPECT_EQ(slurp(dir / "sweep.csv"), csv_before);
  // Another config: refused, nothing changed.
  const std::string before = slurp(dir / "sweep.csv");
  o.config_text = "# another sweep\n";
  EXPECT_THROW(run_sweep(sims, task, sweep, pid, o), InputError);
  EXPECT_EQ(slurp(dir / "sweep.csv"), before);
}

}  // namespace
}  // namespace codesign::run
