// `codesign baseline pid`'s result file and its input checks (run/pid_baseline.hpp):
// baseline.toml written from a result and read back key by key, and bad options refused before
// any episode runs, leaving an earlier baseline.toml as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "base/errors.hpp"
#include "io/config/toml_reader.hpp"
#include "run/pid_baseline.hpp"
#include "test_files.hpp"

namespace codesign::run {
namespace {

namespace fs = std::filesystem;

core::DesignEvaluation test_of(double mean, double std, int episodes, double band) {
  core::DesignEvaluation e;
  e.returns.assign(static_cast<std::size_t>(episodes), mean);
  e.mean_return = mean;
  e.std_return = std;
  e.mean_band_fraction = band;
  return e;
}

core::PidTuningResult pid_result(core::PidSignal sig, double kp, double ki, double setpoint) {
  core::PidTuningResult r;
  r.pid.signal = sig;
  r.pid.gains.kp = kp;
  r.pid.gains.ki = ki;
  r.pid.gains.kd = 0.0;
  r.pid.setpoint = setpoint;
  r.tuning_return = 40.0 + kp;
  r.evaluations = 12;
  r.test = test_of(30.0 + ki, 0.25, 7, 0.5);
  return r;
}

TEST(PidBaselineFile, WritesEveryControllersTableReadableBack) {
  const fs::path dir = test_files::fresh_dir("pid_baseline_file");
  fs::create_directories(dir);
  PidBaselineResult r;
  r.design = 80;
  r.p1_kPa = 5.0;
  r.p2_kPa = 3.0;
  r.tuning_phases = 2;
  r.test_episodes = 7;
  r.pids.emplace_back(core::PidSignal::Force, pid_result(core::PidSignal::Force, 0.025, 0.05, 20.0));
  core::PidTuningResult strain = pid_result(core::PidSignal::Strain, 0.03, 0.06, 0.0065);
  strain.strain_calibrated = 0.0064;
  strain.offset = 0.125;
  r.pids.emplace_back(core::PidSignal::Strain, strain);
  core::PidTuningResult est = pid_result(core::PidSignal::Estimate, 0.02, 0.07, 20.0);
  est.estimator.fit.estimator = {0.001, 3.5e-4, -0.02};
  est.estimator.fit.r2 = 0.9987;
  est.estimator.fit.rms_mN = 0.41;
  est.estimator.fit.samples = 1234;
  est.estimator.episodes = 25;
  est.estimator.theta_centre_rad = 0.5;
  r.pids.emplace_back(core::PidSignal::Estimate, est);
  r.fixed_theta.theta0_rad = -0.25;
  r.fixed_theta.tuning_return = 6.5;
  r.fixed_theta.evaluations = 9;
  r.fixed_theta.test = test_of(6.25, 0.03, 7, 0.35);
  write_baseline_file(dir, r);

  io::TableReader root = io::TableReader::from_file((dir / kBaselineFile).string());
  EXPECT_EQ(root.table("design").integer("design", -1, 0, 109), 80);
  io::TableReader force = root.table("pid_force");
  EXPECT_EQ(force.number("kp", 0, -1e9, 1e9), 0.025);
  EXPECT_EQ(force.number("ki", 0, -1e9, 1e9), 0.05);
  EXPECT_EQ(force.number("setpoint", 0, -1e9, 1e9), 20.0);
  EXPECT_EQ(force.number("tuning_return", 0, -1e9, 1e9), 40.0 + 0.025);  // as computed, to the last bit
  EXPECT_EQ(force.integer("evaluations", 0, 0, 1000), 12);
  EXPECT_EQ(force.number("test_return", 0, -1e9, 1e9), 30.0 + 0.05);
  EXPECT_EQ(force.integer("test_episodes", 0, 0, 1000), 7);
  io::TableReader st = root.table("pid_strain");
  EXPECT_EQ(st.number("strain_calibrated", 0, -1, 1), 0.0064);
  EXPECT_EQ(st.number("setpoint_offset", 0, -1, 1), 0.125);
  EXPECT_FALSE(st.has("estimator_c0"));
  io::TableReader e = root.table("pid_estimate");
  EXPECT_EQ(e.number("estimator_c1", 0, -1, 1), 3.5e-4);
  EXPECT_EQ(e.number("estimator_c2", 0, -1, 1), -0.02);
  EXPECT_EQ(e.integer("fit_samples", 0, 0, 100000), 1234);
  // 0.5 rad in degrees, as rad · 180 / π is rounded (the file keeps 17 significant digits).
  EXPECT_EQ(e.number("fit_theta_centre_deg", 0, -360, 360), 0.5 * 180.0 / std::numbers::pi);
  EXPECT_FALSE(e.has("fit_failure"));
  io::TableReader ft = root.table("fixed_theta");
  EXPECT_EQ(ft.number("theta0_deg", 0, -360, 360), -0.25 * 180.0 / std::numbers::pi);
  EXPECT_EQ(ft.number("band_fraction", 0, 0, 1), 0.35);
  EXPECT_EQ(ft.number("test_return_std", 0, 0, 100), 0.03);
}

TEST(PidBaselineFile, AFailedFitSaysWhy) {
  const fs::path dir = test_files::fresh_dir("pid_baseline_fit_failure");
  fs::create_directories(dir);
  PidBaselineResult r;
  core::PidTuningResult est = pid_result(core::PidSignal::Estimate, 0.02, 0.07, 20.0);
  est.estimator.failure = "too few samples";
  r.pids.emplace_back(core::PidSignal::Estimate, est);
  write_baseline_file(dir, r);
  io::TableReader root = io::TableReader::from_file((dir / kBaselineFile).string());
  EXPECT_EQ(root.table("pid_estimate").string("fit_failure", ""),
            "too few samples");
}

// Each bad option is refused with a message naming it, before a simulator is built, and an
// earlier baseline.toml keeps its bytes.
TEST(PidBaseline, BadOptionsAreRefusedBeforeAnyEpisode) {
  const fs::path dir = test_files::fresh_dir("pid_baseline_refused");
  fs::create_directories(dir);
  const std::string earlier = "# an earlier baseline\n";
  std::ofstream(dir / kBaselineFile) << earlier;
  const RunConfig config{};  // [task] pressure_max_kPa 20
  auto message = [&](PidBaselineOptions o) -> std::string {
    try {
      run_pid_baseline(config, o);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  PidBaselineOptions o;
  o.out = dir.string();
  o.force = true;
  o.design = 110;
  EXPECT_NE(message(o).find("--design: 110 is out of range; allowed [0, 109]"), std::string::npos);
  o.design = -1;
  EXPECT_NE(message(o).find("--design: -1"), std::string::npos);
  o.design = 21;
  o.p1_kPa = 20.5;
  EXPECT_NE(message(o).find("--p1/--p2"), std::string::npos);
  o.p1_kPa = 5.0;
  o.p2_kPa = std::nan("");
  EXPECT_NE(message(o).find("--p1/--p2"), std::string::npos);
  o.p2_kPa = 0.0;
  o.force = false;
  EXPECT_NE(message(o).find("already holds baseline.toml"), std::string::npos);
  EXPECT_EQ(test_files::slurp(dir / kBaselineFile), earlier);
  EXPECT_FALSE(fs::exists(dir / "eval"));
}

}  // namespace
}  // namespace codesign::run
