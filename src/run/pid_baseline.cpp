#include "run/pid_baseline.hpp"

#include <cstdio>
#include <memory>
#include <numbers>
#include <ostream>
#include <sstream>

#include "base/errors.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "run/output_dir.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;
using io::CsvLog;

// Degrees as every file and message of this command has printed them (the product first).
double degrees(double rad) { return rad * 180.0 / std::numbers::pi; }

// The keys that close every controller's table: its tuning, then its test.
void write_test_keys(std::ostream& out, double tuning_return, int evaluations, const core::DesignEvaluation& e) {
  out << "tuning_return = " << CsvLog::num(tuning_return) << "\n"
      << "evaluations = " << evaluations << "\n"
      << "test_return = " << CsvLog::num(e.mean_return) << "\n"
      << "test_return_std = " << CsvLog::num(e.std_return) << "\n"
      << "test_episodes = " << e.returns.size() << "\n"
      << "band_fraction = " << CsvLog::num(e.mean_band_fraction) << "\n\n";
}

std::string table_name(core::PidSignal sig) { return std::string("pid_") + core::to_string(sig); }

void write_pid_table(std::ostream& t, core::PidSignal sig, const core::PidTuningResult& r) {
  const bool strain = sig == core::PidSignal::Strain;
  t << "[" << table_name(sig) << "]\nkp = " << CsvLog::num(r.pid.gains.kp) << "\nki = " << CsvLog::num(r.pid.gains.ki)
    << "\nkd = " << CsvLog::num(r.pid.gains.kd) << "\nsetpoint = " << CsvLog::num(r.pid.setpoint)
    << (strain ? "   # strain\n" : "   # F_t, mN\n");
  if (strain)
    t << "strain_calibrated = " << CsvLog::num(r.strain_calibrated) << "\nsetpoint_offset = " << CsvLog::num(r.offset)
      << "   # band units\n";
  if (sig == core::PidSignal::Estimate) {
    const core::ForceFit& fit = r.estimator.fit;
    t << "# F_hat = (eps - c0 - c2*theta)/c1, least squares of eps against (1, F, theta) over open-loop episodes\n"
      << "estimator_c0 = " << CsvLog::num(fit.estimator.c0) << "\nestimator_c1 = " << CsvLog::num(fit.estimator.c1)
      << "   # strain per mN\nestimator_c2 = " << CsvLog::num(fit.estimator.c2) << "   # strain per rad\n"
      << "fit_r2 = " << CsvLog::num(fit.r2) << "\nfit_rms_mN = " << CsvLog::num(fit.rms_mN)
      << "\nfit_samples = " << fit.samples << "\nfit_episodes = " << r.estimator.episodes
      << "\nfit_theta_centre_deg = " << CsvLog::num(degrees(r.estimator.theta_centre_rad)) << "\n"
      << (r.estimator.ok() ? std::string() : "fit_failure = \"" + r.estimator.failure + "\"\n");
  }
  write_test_keys(t, r.tuning_return, r.evaluations, r.test);
}

void print_fit(const std::string& name, const core::PidTuningResult& r) {
  const core::ForceFit& fit = r.estimator.fit;
  if (!r.estimator.ok())
    std::printf("baseline: %-11s fit failed on %d contact samples of %d open-loop episodes: %s; F_hat is NaN, so "
                "the PID holds the base\n",
                name.c_str(), fit.samples, r.estimator.episodes, r.estimator.failure.c_str());
  else
    std::printf("baseline: %-11s fit eps = c0 + c1 F + c2 theta: c0 %.6g, c1 %.4g /mN, c2 %.4g /rad over %d contact "
                "samples of %d open-loop episodes (theta centred on %.3f deg): R^2 %.4f, rms %.2f mN\n",
                name.c_str(), fit.estimator.c0, fit.estimator.c1, fit.estimator.c2, fit.samples, r.estimator.episodes,
                degrees(r.estimator.theta_centre_rad), fit.r2, fit.rms_mN);
}

}  // namespace

void write_baseline_file(const fs::path& dir, const PidBaselineResult& r) {
  std::ostringstream t;
  t << "# codesign baseline pid: tuned on plate phases 2*pi*(i + 0.618...)/" << r.tuning_phases
    << ", tested on 2*pi*(k + 1/2)/" << r.test_episodes << "\n\n";
  t << "[design]\ndesign = " << r.design << "\npressures_kPa = [" << CsvLog::num(r.p1_kPa) << ", "
    << CsvLog::num(r.p2_kPa) << "]\n\n";
  for (const auto& [sig, pid] : r.pids) write_pid_table(t, sig, pid);
  const core::FixedThetaTuning& ft = r.fixed_theta;
  t << "[fixed_theta]\ntheta0_deg = " << CsvLog::num(degrees(ft.theta0_rad)) << "\n";
  write_test_keys(t, ft.tuning_return, ft.evaluations, ft.test);
  const std::string text = t.str();
  io::write_file_atomically((dir / kBaselineFile).string(), [&](std::ostream& out) { out << text; });
}

void run_pid_baseline(const RunConfig& setup, const PidBaselineOptions& o) {
  if (o.design < 0 || o.design >= fem::kDesignCount)
    throw InputError("--design: " + std::to_string(o.design) + " is out of range; allowed [0, 109]");
  const double pmax = setup.task.pressure_max_kPa;
  if (!(o.p1_kPa >= 0 && o.p1_kPa <= pmax) || !(o.p2_kPa >= 0 && o.p2_kPa <= pmax))
    throw InputError("--p1/--p2: pressures must lie in [0, " + std::to_string(pmax) + "] kPa");
  const fem::Design d = fem::design_from_index(o.design);
  const double p2 = d.n == 2 ? o.p2_kPa : 0.0;
  const fs::path dir(o.out);
  prepare_output_dir(dir, kBaselineFile, "baseline", o.force);

  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const core::TaskConfig& task = setup.task;
  const core::PidTuningConfig& pc = setup.pid;
  const auto threads = static_cast<std::size_t>(o.threads);
  const core::EpisodeSetup es{o.design, o.p1_kPa, p2, 0.0, 0.0};
  std::printf("baseline: j%d {%d, %g mm, %g mm}, p = [%g, %g] kPa; tuning on %d plate phases, testing on %d others; "
              "NLopt %s, %d starts, %d evaluations\n",
              o.design, d.n, d.chamber_length_mm, d.wall_mm, o.p1_kPa, p2, pc.tuning_phases, pc.test_episodes,
              core::to_string(pc.search.method), pc.search.starts, pc.search.max_evals);
  std::fflush(stdout);

  PidBaselineResult result;
  result.design = o.design;
  result.p1_kPa = o.p1_kPa;
  result.p2_kPa = p2;
  result.tuning_phases = pc.tuning_phases;
  result.test_episodes = pc.test_episodes;
  const fs::path eval_dir = dir / run_file::kEvalDir;
  for (core::PidSignal sig : {core::PidSignal::Force, core::PidSignal::Strain, core::PidSignal::Estimate}) {
    const core::PidTuningResult r = core::tune_whisker_pid(sims, task, es, sig, pc, threads);
    const std::string name = table_name(sig);
    const bool estimate = sig == core::PidSignal::Estimate;
    if (estimate) print_fit(name, r);
    write_evaluation(eval_dir, name, r.test, estimate ? &r.estimator.fit.estimator : nullptr);
    std::printf("baseline: %-11s kp %.4g ki %.4g kd %.4g setpoint %.6g: tuning return %.2f (%d evaluations); "
                "test return %.2f +- %.2f over %zu episodes (band %.0f%%)\n",
                name.c_str(), r.pid.gains.kp, r.pid.gains.ki, r.pid.gains.kd, r.pid.setpoint, r.tuning_return,
                r.evaluations, r.test.mean_return, r.test.std_return, r.test.returns.size(),
                100.0 * r.test.mean_band_fraction);
    std::fflush(stdout);
    result.pids.emplace_back(sig, r);
  }
  result.fixed_theta =
      core::tune_fixed_theta(sims, task, es, setup.sweep.fixed_theta, pc.tuning_phases, pc.test_episodes, threads);
  const core::FixedThetaTuning& ft = result.fixed_theta;
  write_evaluation(eval_dir, "fixed_theta", ft.test);
  std::printf("baseline: %-11s theta0 %.3f deg: tuning return %.2f (%d evaluations); test return %.2f +- %.2f over "
              "%zu episodes (band %.0f%%)\n",
              "fixed_theta", degrees(ft.theta0_rad), ft.tuning_return, ft.evaluations, ft.test.mean_return,
              ft.test.std_return, ft.test.returns.size(), 100.0 * ft.test.mean_band_fraction);
  write_baseline_file(dir, result);
  std::printf("baseline: wrote %s\n", (dir / kBaselineFile).string().c_str());
}

}  // namespace codesign::run
