// `codesign survey --config run.toml -o DIR [--designs A-B] [--phases N] [--no-fixed-theta] [--threads N]`
//
// Measures, over the designs (all 110 by default), what the task's defaults rest on:
//  * the reference range of the strain observation ε: min and max of ε over episodes with the
//    base held at θ0 ∈ {−θ_max, 0, +θ_max} and the pressure corners of [0, p_max] (both
//    chambers for n = 2), plate phase 0;
//  * the best fixed base angle θ0 (coopt::best_fixed_theta at zero pressure over N plate
//    phases) and its return and band fraction — the no-controller baseline;
//  * the reference range of the zeroed strain ε − ε₀ ([task] strain_offset = "inflated") over the
//    same episodes as the first point.
// Writes DIR/survey.csv (one row per design) and prints the suggested [task] strain_min /
// strain_max (the measured range widened by 10 % on each side) and a summary.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "codesign/evaluation.hpp"
#include "run/run_config.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "fem/design.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_log.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct SurveyOptions {
  std::string config;
  std::string out = "runs/survey";
  std::string designs = "0-109";
  int phases = 2;
  bool fixed_theta = true;
  int threads = 0;
  bool force = false;
};

struct DesignRow {
  double strain_min = 1e300, strain_max = -1e300;
  double zeroed_min = 1e300, zeroed_max = -1e300;
  double force_mean = 0.0, force_min = 1e300, force_max = -1e300;
  coopt::FixedThetaResult fixed;
};

int run_survey(const SurveyOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  const auto [first, last] = parse_design_range(o.designs);
  const fs::path dir(o.out);
  std::error_code ec;
  if (fs::exists(dir / "survey.csv", ec) && !o.force)
    throw InputError(dir.string() + ": already holds survey.csv of an earlier survey; choose another -o or pass --force");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());

  auto sims = std::make_shared<coopt::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const coopt::TaskConfig& task = setup.task;
  coopt::TaskConfig zeroed_task = task;  // the same episodes, with ε₀ computed for each
  zeroed_task.strain_offset = coopt::StrainOffset::Inflated;
  const double pmax = task.pressure_max_kPa;
  const int count = last - first + 1;
  std::vector<DesignRow> rows(static_cast<std::size_t>(count));
  rl::ThreadPool pool(static_cast<std::size_t>(o.threads));
  std::printf("survey: designs %d..%d, %d plate phases for the fixed-theta search, %zu threads\n", first, last,
              o.phases, pool.size());
  pool.parallel_for(static_cast<std::size_t>(count), [&](std::size_t i) {
    const int j = first + static_cast<int>(i);
    DesignRow& row = rows[i];
    const int n = fem::design_from_index(j).n;
    std::vector<std::pair<double, double>> ps{{0.0, 0.0}, {pmax, 0.0}};
    if (n == 2) ps.insert(ps.end(), {{0.0, pmax}, {pmax, pmax}});
    coopt::EvaluationOptions eo;
    eo.episodes = 1;
    for (const auto& [p1, p2] : ps)
      for (double th : {-task.theta_max_rad, 0.0, task.theta_max_rad}) {
        const coopt::DesignEvaluation e =
            coopt::evaluate_design(nullptr, sims, zeroed_task, {j, p1, p2, 0.0, th}, eo);
        for (const coopt::TraceRow& r : e.trace) {
          row.strain_min = std::min(row.strain_min, r.strain);
          row.strain_max = std::max(row.strain_max, r.strain);
          row.zeroed_min = std::min(row.zeroed_min, r.strain - r.strain_zero);
          row.zeroed_max = std::max(row.zeroed_max, r.strain - r.strain_zero);
        }
        if (p1 == 0.0 && p2 == 0.0 && th == 0.0) {
          double sum = 0.0;
          for (const coopt::TraceRow& r : e.trace) {
            sum += r.force_mN;
            row.force_min = std::min(row.force_min, r.force_mN);
            row.force_max = std::max(row.force_max, r.force_mN);
          }
          row.force_mean = e.trace.empty() ? 0.0 : sum / static_cast<double>(e.trace.size());
        }
      }
    if (o.fixed_theta) row.fixed = coopt::best_fixed_theta(sims, task, {j, 0.0, 0.0, 0.0, 0.0}, o.phases, 1);
  });

  using io::CsvLog;
  io::write_file_atomically((dir / "survey.csv").string(), [&](std::ostream& out) {
    out << "j,n,l_mm,w_mm,strain_min,strain_max,force_mean_mN,force_min_mN,force_max_mN,best_theta0_deg,"
           "fixed_theta_return,fixed_theta_return_std,fixed_theta_band_fraction,fixed_theta_episodes,"
           "zeroed_strain_min,zeroed_strain_max\n";
    for (int i = 0; i < count; ++i) {
      const int j = first + i;
      const fem::Design d = fem::design_from_index(j);
      const DesignRow& r = rows[static_cast<std::size_t>(i)];
      out << j << ',' << d.n << ',' << d.chamber_length_mm << ',' << d.wall_mm << ',' << CsvLog::num(r.strain_min)
          << ',' << CsvLog::num(r.strain_max) << ',' << CsvLog::num(r.force_mean) << ',' << CsvLog::num(r.force_min)
          << ',' << CsvLog::num(r.force_max) << ',' << CsvLog::num(r.fixed.theta0_rad * 180.0 / std::numbers::pi)
          << ',' << CsvLog::num(r.fixed.evaluation.mean_return) << ',' << CsvLog::num(r.fixed.evaluation.std_return)
          << ',' << CsvLog::num(r.fixed.evaluation.mean_band_fraction) << ',' << r.fixed.evaluations << ','
          << CsvLog::num(r.zeroed_min) << ',' << CsvLog::num(r.zeroed_max) << '\n';
    }
  });
  double lo = 1e300, hi = -1e300;
  for (const DesignRow& r : rows) lo = std::min(lo, r.strain_min), hi = std::max(hi, r.strain_max);
  const double pad = 0.1 * (hi - lo);
  std::printf("survey: strain over all episodes in [%.6g, %.6g]\n", lo, hi);
  std::printf("survey: suggested [task] strain_min = %.4g, strain_max = %.4g (range widened by 10 %% each side)\n",
              lo - pad, hi + pad);
  double zlo = 1e300, zhi = -1e300;
  for (const DesignRow& r : rows) zlo = std::min(zlo, r.zeroed_min), zhi = std::max(zhi, r.zeroed_max);
  const double zpad = 0.1 * (zhi - zlo);
  std::printf("survey: zeroed strain (eps - eps0) over all episodes in [%.6g, %.6g]\n", zlo, zhi);
  std::printf("survey: suggested [task] zeroed_strain_min = %.4g, zeroed_strain_max = %.4g (widened by 10 %% each side)\n",
              zlo - zpad, zhi + zpad);
  if (o.fixed_theta) {
    std::vector<double> ret, band;
    int best_j = first;
    for (int i = 0; i < count; ++i) {
      ret.push_back(rows[static_cast<std::size_t>(i)].fixed.evaluation.mean_return);
      band.push_back(rows[static_cast<std::size_t>(i)].fixed.evaluation.mean_band_fraction);
      if (ret.back() > ret[static_cast<std::size_t>(best_j - first)]) best_j = first + i;
    }
    std::vector<double> sorted = ret;
    std::sort(sorted.begin(), sorted.end());
    const DesignRow& b = rows[static_cast<std::size_t>(best_j - first)];
    std::printf("survey: best fixed theta, return of %d decisions over %d phases: min %.2f, median %.2f, max %.2f "
                "(j%d at theta0 = %.2f deg, band %.0f%%)\n",
                task.episode_steps / task.action_hold_steps, o.phases, sorted.front(), sorted[sorted.size() / 2],
                sorted.back(), best_j, b.fixed.theta0_rad * 180.0 / std::numbers::pi,
                100.0 * b.fixed.evaluation.mean_band_fraction);
    const double max_band = *std::max_element(band.begin(), band.end());
    std::printf("survey: largest band fraction with a fixed theta: %.0f%% of decisions (%s)\n", 100.0 * max_band,
                max_band < 1.0 ? "every design leaves the band for part of every episode"
                               : "some design stays in the band with a fixed theta");
  }
  std::printf("survey: wrote %s\n", (dir / "survey.csv").string().c_str());
  return 0;
}

}  // namespace

void add_survey_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<SurveyOptions>();
  CLI::App* cmd = root.add_subcommand(
      "survey", "Measure the strain reference range and the best fixed-theta return of every design");
  cmd->add_option("--config", opt->config, "run config (TOML)")->required();
  cmd->add_option("-o,--out", opt->out, "output directory (default runs/survey)");
  add_designs_option(*cmd, opt->designs, "0-109");
  cmd->add_option("--phases", opt->phases, "plate phases per fixed-theta evaluation (default 2)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("!--no-fixed-theta", opt->fixed_theta, "skip the fixed-theta search");
  add_threads_option(*cmd, opt->threads);
  cmd->add_flag("--force", opt->force, "overwrite an earlier survey.csv in the output directory");
  cmd->callback([opt, &run] { run = [opt] { return run_survey(*opt); }; });
}

}  // namespace codesign::app
