#include "run/verify_run.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "base/errors.hpp"
#include "core/evaluation.hpp"
#include "core/policy_controller.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "io/formats/csv_table.hpp"
#include "io/formats/run_lock.hpp"
#include "rl/policy_file.hpp"
#include "run/run_config.hpp"
#include "run/resumable_table.hpp"
#include "run/run_folder.hpp"
#include "run/run_settings.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

constexpr const char* kColumns = "condition,mean_return,std_return,ci95,band_fraction,episodes";

// The strain noise of the suite: 2 % of the tared strain's reference range per decision (the
// range the observation scales to [−1, 1]), a gauge of a few microstrain.
constexpr double kStrainNoise = 0.02 * (8.997e-05 + 9.826e-04);

std::string num(double v) { return io::CsvLog::num(v); }

std::vector<VerifyRow> read_rows(const fs::path& csv) {
  std::vector<VerifyRow> rows;
  const io::CsvTable t = io::read_csv(csv.string());
  for (std::size_t i = 0; i < t.rows(); ++i) {
    VerifyRow r;
    r.condition = t.cell(i, t.column("condition"));
    r.mean_return = t.number(i, t.column("mean_return"));
    r.std_return = t.number(i, t.column("std_return"));
    r.ci95 = t.number(i, t.column("ci95"));
    r.band_fraction = t.number(i, t.column("band_fraction"));
    r.episodes = static_cast<int>(t.integer(i, t.column("episodes")));
    rows.push_back(r);
  }
  return rows;
}

std::string report(const VerifySummary& s, const std::vector<VerifyCondition>& suite, const std::string& run_dir) {
  std::ostringstream o;
  const VerifyRow* nominal = s.rows.empty() ? nullptr : &s.rows.front();
  o << "# verify: " << run_dir << "\n\n";
  if (nominal) {
    double worst = nominal->mean_return;
    std::string worst_name = nominal->condition;
    for (const VerifyRow& r : s.rows)
      if (r.mean_return < worst) worst = r.mean_return, worst_name = r.condition;
    char line[256];
    std::snprintf(line, sizeof line,
                  "The final policy on d* = %s tracks to %.1f of 50 on the nominal model and to %.1f at worst "
                  "(%s) over the held-out physics below.\n\n",
                  fem::design_label(s.design).c_str(), nominal->mean_return, worst, worst_name.c_str());
    o << line;
  }
  o << "d* = " << fem::design_label(s.design) << " at p = [" << num(s.p1_kPa) << ", " << num(s.p2_kPa)
    << "] kPa, the run's final policy; each condition over " << (nominal ? nominal->episodes : 0)
    << " test plate phases 2π(k + ½)/n; return = Σ of the 50 decisions' rewards (max 50 for the force term); "
       "mean ± std and the 95 % interval of the mean (1.96 s/√n).\n\n"
    << "| condition | what it is | return (mean ± std) | 95 % interval | decisions in band |\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < s.rows.size(); ++i) {
    const VerifyRow& r = s.rows[i];
    char cells[200];
    std::snprintf(cells, sizeof cells, "%.2f ± %.2f | [%.2f, %.2f] | %.0f %%", r.mean_return, r.std_return,
                  r.mean_return - r.ci95, r.mean_return + r.ci95, 100.0 * r.band_fraction);
    o << "| " << r.condition << " | " << suite[i].what << " | " << cells << " |\n";
  }
  return o.str();
}

}  // namespace

std::vector<VerifyCondition> verify_suite() {
  std::vector<VerifyCondition> s;
  const auto add = [&](std::string name, std::string what, auto set) {
    VerifyCondition c{std::move(name), std::move(what), {}, false};
    set(c);
    s.push_back(c);
  };
  add("nominal", "the model the run trained on", [](VerifyCondition&) {});
  add("modulus_-20%", "Young's modulus × 0.8", [](VerifyCondition& c) { c.physics.youngs_scale = 0.8; });
  add("modulus_+20%", "Young's modulus × 1.2", [](VerifyCondition& c) { c.physics.youngs_scale = 1.2; });
  add("refined_mesh", "[mesh] radius_factor 0.3, wall_factor 0.75, max_size_mm 3 (closer to the converged body)",
      [](VerifyCondition& c) { c.refined_mesh = true; });
  add("plate_x0.5", "plate amplitude × 0.5", [](VerifyCondition& c) { c.physics.plate_amplitude_scale = 0.5; });
  add("plate_x1.5", "plate amplitude × 1.5", [](VerifyCondition& c) { c.physics.plate_amplitude_scale = 1.5; });
  add("gain_-10%", "strain gauge gain × 0.9", [](VerifyCondition& c) { c.physics.strain_gain = 0.9; });
  add("gain_+10%", "strain gauge gain × 1.1", [](VerifyCondition& c) { c.physics.strain_gain = 1.1; });
  add("strain_noise", "strain noise, standard deviation 2 % of the tared strain's range per decision",
      [](VerifyCondition& c) {
        c.physics.strain_noise = kStrainNoise;
        c.physics.noise_seed = 0x5645524946590001ULL;  // fixed: the suite is the same for every run
      });
  return s;
}

VerifySummary verify_run(const VerifyOptions& options) {
  const fs::path dir(options.dir);
  std::error_code ec;
  for (const char* f : {run_file::kConfig, run_file::kResult, run_file::kPolicy})
    if (!fs::exists(dir / f, ec))
      throw InputError((dir / f).string() + ": not found; verify needs a finished co-design run folder");
  const RunSettings settings = run_settings(read_run_config((dir / run_file::kConfig).string()));
  const std::optional<ResultDesign> best =
      read_result_design(dir, "best", settings.loop.task.pressure_max_kPa);
  if (!best) throw InputError((dir / run_file::kResult).string() + ": has no [best] table");
  const auto policy = std::make_shared<const rl::Policy>(rl::load_policy(dir / run_file::kPolicy));

  VerifySummary summary;
  const fs::path folder = dir / "verify";
  summary.folder = folder.string();
  summary.design = best->setup.design;
  summary.p1_kPa = best->setup.p1_kPa;
  summary.p2_kPa = best->setup.p2_kPa;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(folder.string() + ": cannot create: " + ec.message());
  const io::RunLock lock(folder.string());

  std::ostringstream stamp;
  stamp << "# codesign verify: the final policy of this run on d* under held-out physics\n"
        << "design = " << summary.design << "\n"
        << "pressures_kPa = [" << num(summary.p1_kPa) << ", " << num(summary.p2_kPa) << "]\n"
        << "phases = " << options.phases << "   # test plate phases 2*pi*(k + 1/2)/phases\n"
        << "policy_bytes = " << fs::file_size(dir / run_file::kPolicy) << "\n";
  const fs::path csv = folder / "conditions.csv";
  std::map<std::string, VerifyRow> done;
  for (const VerifyRow& r : open_resumable_table<VerifyRow>(folder, folder / "verify.toml", csv, stamp.str(), kColumns,
                                                            options.force, "a verify", read_rows))
    done[r.condition] = r;
  summary.conditions_before = static_cast<int>(done.size());

  const core::ControllerFactory controller = core::policy_factory(policy);
  core::EvaluationOptions eo;
  eo.episodes = options.phases;
  eo.threads = options.threads;
  eo.trace_first = false;
  auto nominal_sims = std::make_shared<core::SimulatorPool>(settings.spec, settings.scene, settings.solver);
  std::shared_ptr<core::SimulatorPool> refined_sims;
  const std::vector<VerifyCondition> suite = verify_suite();
  for (const VerifyCondition& c : suite) {
    if (const auto it = done.find(c.name); it != done.end()) {
      summary.rows.push_back(it->second);
      continue;
    }
    std::shared_ptr<core::SimulatorPool> sims = nominal_sims;
    if (c.refined_mesh) {
      if (!refined_sims) {
        fem::WhiskerModelSpec spec = settings.spec;
        spec.mesh.radius_factor = 0.3;
        spec.mesh.wall_factor = 0.75;
        spec.mesh.max_size_mm = 3.0;
        refined_sims = std::make_shared<core::SimulatorPool>(spec, settings.scene, settings.solver);
      }
      sims = refined_sims;
    }
    core::EpisodeSetup setup = best->setup;
    setup.physics = c.physics;
    const core::DesignEvaluation e = core::evaluate_feedback(controller, sims, settings.loop.task, setup, eo);
    VerifyRow r;
    r.condition = c.name;
    r.mean_return = e.mean_return;
    r.std_return = e.std_return;
    r.ci95 = core::ci95_of_mean(e);
    r.band_fraction = e.mean_band_fraction;
    r.episodes = options.phases;
    std::ofstream out(csv, std::ios::binary | std::ios::app);
    out << r.condition << ',' << num(r.mean_return) << ',' << num(r.std_return) << ',' << num(r.ci95) << ','
        << num(r.band_fraction) << ',' << r.episodes << '\n';
    if (!out.flush()) throw InputError(csv.string() + ": cannot write (disk full?)");
    summary.rows.push_back(r);
    ++summary.conditions_run;
    if (options.progress) {
      std::printf("verify: %-13s %6.2f +- %.2f (95 %% interval +- %.2f)\n", r.condition.c_str(), r.mean_return,
                  r.std_return, r.ci95);
      std::fflush(stdout);
    }
  }
  io::write_file_atomically((folder / "report.md").string(),
                            [&](std::ostream& out) { out << report(summary, suite, options.dir); });
  return summary;
}

}  // namespace codesign::run
