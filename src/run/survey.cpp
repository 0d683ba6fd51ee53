#include "run/survey.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <vector>

#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "rl/thread_pool.hpp"
#include "run/output_dir.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;
using io::CsvLog;
using core::SurveyRow;

void write_survey_csv(const fs::path& file, int first, const std::vector<SurveyRow>& rows) {
  io::write_file_atomically(file.string(), [&](std::ostream& out) {
    out << "j,n,l_mm,w_mm,strain_min,strain_max,force_mean_mN,force_min_mN,force_max_mN,best_theta0_deg,"
           "fixed_theta_return,fixed_theta_return_std,fixed_theta_band_fraction,fixed_theta_episodes,"
           "zeroed_strain_min,zeroed_strain_max\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const int j = first + static_cast<int>(i);
      const fem::Design d = fem::design_from_index(j);
      const SurveyRow& r = rows[i];
      out << j << ',' << d.n << ',' << d.chamber_length_mm << ',' << d.wall_mm << ',' << CsvLog::num(r.strain_min)
          << ',' << CsvLog::num(r.strain_max) << ',' << CsvLog::num(r.force_mean) << ',' << CsvLog::num(r.force_min)
          << ',' << CsvLog::num(r.force_max) << ',' << CsvLog::num(r.fixed.theta0_rad * 180.0 / std::numbers::pi)
          << ',' << CsvLog::num(r.fixed.evaluation.mean_return) << ',' << CsvLog::num(r.fixed.evaluation.std_return)
          << ',' << CsvLog::num(r.fixed.evaluation.mean_band_fraction) << ',' << r.fixed.evaluations << ','
          << CsvLog::num(r.zeroed_min) << ',' << CsvLog::num(r.zeroed_max) << '\n';
    }
  });
}

void print_summary(const core::TaskConfig& task, const core::SurveyOptions& o, const std::vector<SurveyRow>& rows) {
  const int first = o.first_design;
  const int count = static_cast<int>(rows.size());
  // The range of a strain column over every row, and the range widened by 10 % on each side.
  struct Range {
    double lo = 1e300, hi = -1e300;
    double pad() const { return 0.1 * (hi - lo); }
  };
  Range eps, zeroed;
  for (const SurveyRow& r : rows) {
    eps.lo = std::min(eps.lo, r.strain_min), eps.hi = std::max(eps.hi, r.strain_max);
    zeroed.lo = std::min(zeroed.lo, r.zeroed_min), zeroed.hi = std::max(zeroed.hi, r.zeroed_max);
  }
  std::printf("survey: strain over all episodes in [%.6g, %.6g]\n", eps.lo, eps.hi);
  std::printf("survey: suggested [task] strain_min = %.4g, strain_max = %.4g (range widened by 10 %% each side)\n",
              eps.lo - eps.pad(), eps.hi + eps.pad());
  std::printf("survey: zeroed strain (eps - eps0) over all episodes in [%.6g, %.6g]\n", zeroed.lo, zeroed.hi);
  std::printf("survey: suggested [task] zeroed_strain_min = %.4g, zeroed_strain_max = %.4g (widened by 10 %% each side)\n",
              zeroed.lo - zeroed.pad(), zeroed.hi + zeroed.pad());
  if (!o.fixed_theta) return;
  std::vector<double> ret, band;
  int best_j = first;
  for (int i = 0; i < count; ++i) {
    ret.push_back(rows[static_cast<std::size_t>(i)].fixed.evaluation.mean_return);
    band.push_back(rows[static_cast<std::size_t>(i)].fixed.evaluation.mean_band_fraction);
    if (ret.back() > ret[static_cast<std::size_t>(best_j - first)]) best_j = first + i;
  }
  std::vector<double> sorted = ret;
  std::sort(sorted.begin(), sorted.end());
  const SurveyRow& b = rows[static_cast<std::size_t>(best_j - first)];
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

}  // namespace

void run_survey(const RunConfig& setup, const SurveyRunOptions& o) {
  const fs::path dir(o.out);
  prepare_output_dir(dir, "survey.csv", "survey", o.force);

  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  rl::ThreadPool pool(static_cast<std::size_t>(o.threads));
  std::printf("survey: designs %d..%d, %d plate phases for the fixed-theta search, %zu threads\n",
              o.survey.first_design, o.survey.last_design, o.survey.phases, pool.size());
  const std::vector<SurveyRow> rows = core::survey_designs(sims, setup.task, o.survey, pool);
  write_survey_csv(dir / "survey.csv", o.survey.first_design, rows);
  print_summary(setup.task, o.survey, rows);
  std::printf("survey: wrote %s\n", (dir / "survey.csv").string().c_str());
}

}  // namespace codesign::run
