// `codesign baseline pid --config run.toml --design J -o DIR [--p1 P] [--p2 P] [--threads N] [--force]`
//
// What a control engineer would try first, on one design: a PID on the measured force (an oracle
// sensor the policy lacks), a PID on the strain ε (the policy's signal) and a PID on the force
// estimated from ε and the base angle θ (fitted on open-loop episodes), gains tuned by NLopt
// ([pid] of the config), and the best fixed base angle for comparison ([sweep] fixed_theta_*),
// all tuned on the tuning phases and tested on disjoint evaluation phases (docs/baselines.md).
// Writes DIR/baseline.toml and DIR/eval/<controller>.csv (+ _trace.csv of the first test episode).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>

#include "base/errors.hpp"
#include "codesign/design_sweep.hpp"
#include "codesign/pid_tuning.hpp"
#include "run/run_config.hpp"
#include "run/run_folder.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "fem/design.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_log.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;
using io::CsvLog;

struct BaselineOptions {
  std::string config;
  std::string out;
  int design = 21;
  double p1 = 0.0, p2 = 0.0;
  int threads = 0;
  bool force = false;
};

void toml_test(std::ostream& out, double tuning_return, int evaluations, const coopt::DesignEvaluation& e) {
  out << "tuning_return = " << CsvLog::num(tuning_return) << "\n"
      << "evaluations = " << evaluations << "\n"
      << "test_return = " << CsvLog::num(e.mean_return) << "\n"
      << "test_return_std = " << CsvLog::num(e.std_return) << "\n"
      << "test_episodes = " << e.returns.size() << "\n"
      << "band_fraction = " << CsvLog::num(e.mean_band_fraction) << "\n\n";
}

int run_baseline(const BaselineOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  if (o.design < 0 || o.design >= fem::kDesignCount)
    throw InputError("--design: " + std::to_string(o.design) + " is out of range; allowed [0, 109]");
  const double pmax = setup.task.pressure_max_kPa;
  if (!(o.p1 >= 0 && o.p1 <= pmax) || !(o.p2 >= 0 && o.p2 <= pmax))
    throw InputError("--p1/--p2: pressures must lie in [0, " + std::to_string(pmax) + "] kPa");
  const fem::Design d = fem::design_from_index(o.design);
  const double p2 = d.n == 2 ? o.p2 : 0.0;
  const fs::path dir(o.out);
  std::error_code ec;
  if (fs::exists(dir / "baseline.toml", ec) && !o.force)
    throw InputError(dir.string() + ": already holds baseline.toml of an earlier baseline; choose another -o or "
                     "pass --force");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());

  auto sims = std::make_shared<coopt::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const coopt::TaskConfig& task = setup.task;
  const coopt::PidTuningConfig& pc = setup.pid;
  const auto threads = static_cast<std::size_t>(o.threads);
  const coopt::EpisodeSetup es{o.design, o.p1, p2, 0.0, 0.0};
  std::printf("baseline: j%d {%d, %g mm, %g mm}, p = [%g, %g] kPa; tuning on %d plate phases, testing on %d others; "
              "NLopt %s, %d starts, %d evaluations\n",
              o.design, d.n, d.chamber_length_mm, d.wall_mm, o.p1, p2, pc.tuning_phases, pc.test_episodes,
              coopt::to_string(pc.search.method), pc.search.starts, pc.search.max_evals);
  std::fflush(stdout);

  std::string toml = "# codesign baseline pid: tuned on plate phases 2*pi*(i + 0.618...)/" +
                     std::to_string(pc.tuning_phases) + ", tested on 2*pi*(k + 1/2)/" +
                     std::to_string(pc.test_episodes) + "\n\n";
  toml += "[design]\ndesign = " + std::to_string(o.design) + "\npressures_kPa = [" + CsvLog::num(o.p1) + ", " +
          CsvLog::num(p2) + "]\n\n";
  for (coopt::PidSignal sig : {coopt::PidSignal::Force, coopt::PidSignal::Strain, coopt::PidSignal::Estimate}) {
    const coopt::PidTuningResult r = coopt::tune_whisker_pid(sims, task, es, sig, pc, threads);
    const std::string name = std::string("pid_") + coopt::to_string(sig);
    const bool estimate = sig == coopt::PidSignal::Estimate;
    const coopt::ForceFit& fit = r.estimator.fit;
    if (estimate && !r.estimator.ok())
      std::printf("baseline: %-11s fit failed on %d contact samples of %d open-loop episodes: %s; F_hat is NaN, so "
                  "the PID holds the base\n",
                  name.c_str(), fit.samples, r.estimator.episodes, r.estimator.failure.c_str());
    else if (estimate)
      std::printf("baseline: %-11s fit eps = c0 + c1 F + c2 theta: c0 %.6g, c1 %.4g /mN, c2 %.4g /rad over %d contact "
                  "samples of %d open-loop episodes (theta centred on %.3f deg): R^2 %.4f, rms %.2f mN\n",
                  name.c_str(), fit.estimator.c0, fit.estimator.c1, fit.estimator.c2, fit.samples, r.estimator.episodes,
                  r.estimator.theta_centre_rad * 180.0 / std::numbers::pi, fit.r2, fit.rms_mN);
    run::write_evaluation(dir / run::run_file::kEvalDir, name, r.test, estimate ? &fit.estimator : nullptr);
    std::printf("baseline: %-11s kp %.4g ki %.4g kd %.4g setpoint %.6g: tuning return %.2f (%d evaluations); "
                "test return %.2f +- %.2f over %zu episodes (band %.0f%%)\n",
                name.c_str(), r.pid.gains.kp, r.pid.gains.ki, r.pid.gains.kd, r.pid.setpoint, r.tuning_return,
                r.evaluations, r.test.mean_return, r.test.std_return, r.test.returns.size(),
                100.0 * r.test.mean_band_fraction);
    std::fflush(stdout);
    std::ostringstream t;
    t << "[" << name << "]\nkp = " << CsvLog::num(r.pid.gains.kp) << "\nki = " << CsvLog::num(r.pid.gains.ki)
      << "\nkd = " << CsvLog::num(r.pid.gains.kd) << "\nsetpoint = " << CsvLog::num(r.pid.setpoint)
      << (sig == coopt::PidSignal::Strain ? "   # strain\n" : "   # F_t, mN\n");
    if (sig == coopt::PidSignal::Strain)
      t << "strain_calibrated = " << CsvLog::num(r.strain_calibrated) << "\nsetpoint_offset = " << CsvLog::num(r.offset)
        << "   # band units\n";
    if (estimate)
      t << "# F_hat = (eps - c0 - c2*theta)/c1, least squares of eps against (1, F, theta) over open-loop episodes\n"
        << "estimator_c0 = " << CsvLog::num(fit.estimator.c0) << "\nestimator_c1 = " << CsvLog::num(fit.estimator.c1)
        << "   # strain per mN\nestimator_c2 = " << CsvLog::num(fit.estimator.c2) << "   # strain per rad\n"
        << "fit_r2 = " << CsvLog::num(fit.r2) << "\nfit_rms_mN = " << CsvLog::num(fit.rms_mN)
        << "\nfit_samples = " << fit.samples << "\nfit_episodes = " << r.estimator.episodes
        << "\nfit_theta_centre_deg = " << CsvLog::num(r.estimator.theta_centre_rad * 180.0 / std::numbers::pi) << "\n"
        << (r.estimator.ok() ? std::string() : "fit_failure = \"" + r.estimator.failure + "\"\n");
    toml += t.str();
    std::ostringstream rest;
    toml_test(rest, r.tuning_return, r.evaluations, r.test);
    toml += rest.str();
  }
  const coopt::FixedThetaTuning ft =
      coopt::tune_fixed_theta(sims, task, es, setup.sweep.fixed_theta, pc.tuning_phases, pc.test_episodes, threads);
  run::write_evaluation(dir / run::run_file::kEvalDir, "fixed_theta", ft.test);
  std::printf("baseline: %-11s theta0 %.3f deg: tuning return %.2f (%d evaluations); test return %.2f +- %.2f over "
              "%zu episodes (band %.0f%%)\n",
              "fixed_theta", ft.theta0_rad * 180.0 / std::numbers::pi, ft.tuning_return, ft.evaluations,
              ft.test.mean_return, ft.test.std_return, ft.test.returns.size(), 100.0 * ft.test.mean_band_fraction);
  {
    std::ostringstream t;
    t << "[fixed_theta]\ntheta0_deg = " << CsvLog::num(ft.theta0_rad * 180.0 / std::numbers::pi) << "\n";
    toml_test(t, ft.tuning_return, ft.evaluations, ft.test);
    toml += t.str();
  }
  io::write_file_atomically((dir / "baseline.toml").string(), [&](std::ostream& out) { out << toml; });
  std::printf("baseline: wrote %s\n", (dir / "baseline.toml").string().c_str());
  return 0;
}

}  // namespace

void add_baseline_command(CLI::App& root, Runner& run) {
  CLI::App* base = root.add_subcommand("baseline", "Classical baselines on one design");
  base->require_subcommand(1);
  auto opt = std::make_shared<BaselineOptions>();
  CLI::App* cmd = base->add_subcommand(
      "pid", "NLopt-tuned PID on the force (oracle), on the strain and on the force estimated from strain and "
      "base angle, and the best fixed theta, on one design");
  cmd->add_option("--config", opt->config, "run config (TOML; [pid], [sweep] fixed_theta_*)")->required();
  cmd->add_option("--design", opt->design, "design index 0..109 (default 21)");
  cmd->add_option("-o,--out", opt->out, "output directory")->required();
  cmd->add_option("--p1", opt->p1, "chamber 1 pressure, kPa (default 0)");
  cmd->add_option("--p2", opt->p2, "chamber 2 pressure, kPa (default 0; ignored for one chamber)");
  add_threads_option(*cmd, opt->threads);
  cmd->add_flag("--force", opt->force, "overwrite an earlier baseline.toml in the output directory");
  cmd->callback([opt, &run] { run = [opt] { return run_baseline(*opt); }; });
}

}  // namespace codesign::app
