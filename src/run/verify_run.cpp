#include "run/verify_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "base/errors.hpp"
#include "base/seconds_since.hpp"
#include "base/thread_cpu_seconds.hpp"
#include "core/evaluation.hpp"
#include "core/pid_tuning.hpp"
#include "core/policy_controller.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "io/formats/csv_table.hpp"
#include "io/formats/gnuplot.hpp"
#include "io/formats/run_lock.hpp"
#include "rl/policy_file.hpp"
#include "run/resumable_table.hpp"
#include "run/run_config.hpp"
#include "run/run_evaluation.hpp"
#include "run/run_folder.hpp"
#include "run/run_settings.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

constexpr const char* kColumns =
    "subject,controller,design,p1_kPa,p2_kPa,condition,mean_return,std_return,ci95,band_fraction,episodes";

// The strain noise of the suite: 2 % of the tared strain's default reference range per decision
// (the range the observation scales to [−1, 1]), a gauge of a few microstrain; the default, not
// the run's, so that the suite is the same for every run.
double suite_strain_noise() {
  const core::TaskConfig task;
  return 0.02 * (task.zeroed_strain_max - task.zeroed_strain_min);
}

// Plate phase offsets: the test phases every reported result uses, and the validation phases
// experiments choose settings on (neither is a tuning phase, core::kTuningPhaseOffset).
constexpr double kTestOffset = 0.5, kValidationOffset = 0.25;

std::string num(double v) { return io::CsvLog::num(v); }

std::vector<VerifyRow> read_rows(const fs::path& csv) {
  std::vector<VerifyRow> rows;
  const io::CsvTable t = io::read_csv(csv.string());
  for (std::size_t i = 0; i < t.rows(); ++i) {
    VerifyRow r;
    r.subject = t.cell(i, t.column("subject"));
    r.controller = t.cell(i, t.column("controller"));
    r.at.design = static_cast<int>(t.integer(i, t.column("design")));
    r.at.p1_kPa = t.number(i, t.column("p1_kPa"));
    r.at.p2_kPa = t.number(i, t.column("p2_kPa"));
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

std::string row_line(const VerifyRow& r) {
  return r.subject + ',' + r.controller + ',' + std::to_string(r.at.design) + ',' + num(r.at.p1_kPa) + ',' +
         num(r.at.p2_kPa) + ',' + r.condition + ',' + num(r.mean_return) + ',' + num(r.std_return) + ',' +
         num(r.ci95) + ',' + num(r.band_fraction) + ',' + std::to_string(r.episodes);
}

DesignAtPressures at_of(const ResultDesign& d) { return {d.setup.design, d.setup.p1_kPa, d.setup.p2_kPa}; }

// The run's designs in its own order, best first: its `evaluate` ranking of the final state when
// it has one, else the final state's distribution by probability.
std::vector<DesignAtPressures> run_order(const RunSettings& settings, const fs::path& dir, std::string& from) {
  std::vector<DesignAtPressures> out;
  const fs::path ranking = dir / run_file::kEvaluateDir / "final" / "ranking.csv";
  std::error_code ec;
  if (fs::exists(ranking, ec)) {
    const io::CsvTable t = io::read_csv(ranking.string());
    for (std::size_t i = 0; i < t.rows(); ++i)
      out.push_back({static_cast<int>(t.integer(i, t.column("design"))), t.number(i, t.column("p1_kPa")),
                     t.number(i, t.column("p2_kPa"))});
    from = "run's evaluate ranking (evaluate/final/ranking.csv)";
    return out;
  }
  try {
    for (const StateDesign& d : state_designs(settings, dir.string(), "final"))
      out.push_back({d.design, d.p1_kPa, d.p2_kPa});
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + "; verify takes the next designs from the run's final state (or pass --next 0)");
  }
  from = "final design distribution by probability";
  return out;
}

// verify.dat (a block per subject: condition index, mean, 95 % half-width) and verify.png.
std::string draw_figure(const fs::path& folder, const std::string& plots_dir, const VerifySummary& s,
                        const std::vector<VerifyCondition>& suite, const std::string& run) {
  io::write_file_atomically((folder / "verify.dat").string(), [&](std::ostream& out) {
    for (const VerifySubject& sub : s.subjects) {
      out << "# " << sub.name << " " << fem::design_label(sub.at.design) << " " << sub.controller << "\n";
      for (std::size_t c = 0; c < suite.size(); ++c)
        for (const VerifyRow& r : s.rows)
          if (r.subject == sub.name && r.condition == suite[c].name)
            out << c << ' ' << num(r.mean_return) << ' ' << num(r.ci95) << '\n';
      out << "\n\n";
    }
  });
  if (plots_dir.empty()) return "no plots folder given";
  const fs::path script = fs::path(plots_dir) / "verify.gp";
  if (!fs::exists(script)) return script.string() + " not found";
  std::string subjects, conditions;
  for (const VerifySubject& sub : s.subjects) {
    if (!subjects.empty()) subjects += ' ';
    subjects += sub.name;
    if (sub.controller == kControllerPolicy) subjects += "(j" + std::to_string(sub.at.design) + ")";
  }
  for (const VerifyCondition& c : suite) {
    if (!conditions.empty()) conditions += ' ';
    for (const char ch : c.name) conditions += ch == '%' ? std::string("%%") : std::string(1, ch);  // tic labels are formats
  }
  io::GnuplotCall call;
  call.script = script.string();
  call.set("plotsdir", plots_dir);
  call.set("datafile", (folder / "verify.dat").string());
  call.set("outfile", (folder / "verify.png").string());
  call.set("subjects", subjects);
  call.set("conditions", conditions);
  call.set("title", "verify " + run + ": return per held-out condition, mean ± 95 % interval");
  const io::GnuplotOutcome r = io::run_gnuplot(call);
  return r.ok() ? "" : r.message();
}

// What the run's answers are: d*, the runner-up, its order of designs, other runs' d*.
SubjectSources subject_sources(const RunSettings& settings, const fs::path& dir, const VerifyOptions& options) {
  const double pmax = settings.loop.task.pressure_max_kPa;
  const std::optional<ResultDesign> best = read_result_design(dir, "best", pmax);
  if (!best) throw InputError((dir / run_file::kResult).string() + ": has no [best] table");
  SubjectSources sources;
  sources.best = at_of(*best);
  if (const auto r = read_result_design(dir, "runner_up", pmax)) sources.runner_up = at_of(*r);
  sources.next = options.next;
  sources.single_design = settings.loop.codesign.baseline == core::Baseline::SingleDesign;
  sources.baselines = options.baselines;
  if (!sources.single_design && options.next > 0) sources.ranked = run_order(settings, dir, sources.ranked_from);
  for (const std::string& w : options.with)
    if (const auto o = read_result_design(w, "best", pmax)) sources.others.emplace_back(run_folder_name(w), at_of(*o));
  return sources;
}

// verify.toml: what every cell of the folder shares; a folder holding cells of another is
// continued only if it matches. The subjects are not part of it: a cell is kept for the subject,
// design and pressures it was run for (cell_key), so a later call with more subjects (--next,
// --with, the specialists) runs only the cells it adds.
std::string verify_stamp(const VerifyOptions& options) {
  std::ostringstream stamp;
  stamp << "# codesign verify: the run's final policy (and two PIDs on d*) under held-out physics\n"
        << "phases = " << options.phases << "\n"
        << "phase_set = \"" << options.phase_set << "\"   # test: 2*pi*(k + 1/2)/phases, validation: 2*pi*(k + 1/4)/phases\n"
        << "policy_bytes = " << fs::file_size(fs::path(options.dir) / run_file::kPolicy) << "\n";
  return stamp.str();
}

std::string cell_key(const std::string& subject, const std::string& controller, const DesignAtPressures& at,
                     const std::string& condition) {
  return subject + ',' + controller + ',' + std::to_string(at.design) + ',' + num(at.p1_kPa) + ',' + num(at.p2_kPa) +
         ',' + condition;
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
        c.physics.strain_noise = suite_strain_noise();
        c.physics.noise_seed = 0x5645524946590001ULL;  // fixed: the suite is the same for every run
      });
  return s;
}

namespace {

// verify_plan for the run's settings, read once by the caller.
std::vector<VerifySubject> plan(const RunSettings& settings, const VerifyOptions& options) {
  std::vector<VerifySubject> subjects = verify_subjects(subject_sources(settings, options.dir, options));
  // The specialists after the run's policy subjects, before the PIDs.
  auto at = std::find_if(subjects.begin(), subjects.end(),
                         [](const VerifySubject& s) { return s.controller != kControllerPolicy; });
  for (const VerifyOptions::Specialist& sp : options.specialists) {
    VerifySubject s{sp.name, kControllerSpecialist, sp.at,
                    "a fresh policy trained on this design alone at these pressures, seed " + std::to_string(sp.seed),
                    sp.policy_file};
    at = subjects.insert(at, std::move(s)) + 1;
  }
  return subjects;
}

// The checks of the options and the run folder that come before anything is read.
void check_options(const VerifyOptions& options) {
  const fs::path dir(options.dir);
  std::error_code ec;
  for (const char* f : {run_file::kConfig, run_file::kResult, run_file::kPolicy})
    if (!fs::exists(dir / f, ec))
      throw InputError((dir / f).string() + ": not found; verify needs a finished co-design run folder");
  (void)chosen_conditions(options.conditions);  // a bad name before anything is read or written
  if (options.phase_set != "test" && options.phase_set != "validation")
    throw InputError("--phase-set: \"" + options.phase_set + "\" is not one of test, validation");
  for (const std::string& w : options.with)
    if (!fs::exists(fs::path(w) / run_file::kResult, ec))
      throw InputError("--with: " + (fs::path(w) / run_file::kResult).string() +
                       ": not found; each --with folder must be a finished co-design run");
}

}  // namespace

std::vector<VerifySubject> verify_plan(const VerifyOptions& options) {
  check_options(options);
  return plan(run_settings(read_run_config((fs::path(options.dir) / run_file::kConfig).string())), options);
}

std::vector<VerifyCondition> chosen_conditions(const std::vector<std::string>& names) {
  const std::vector<VerifyCondition> suite = verify_suite();
  if (names.empty()) return suite;
  std::string allowed;
  for (const VerifyCondition& c : suite) allowed += (allowed.empty() ? "" : ", ") + c.name;
  for (const std::string& n : names)
    if (std::none_of(suite.begin(), suite.end(), [&](const VerifyCondition& c) { return c.name == n; }))
      throw InputError("--conditions: \"" + n + "\" is not a condition of the suite; allowed: " + allowed);
  std::vector<VerifyCondition> out;
  for (const VerifyCondition& c : suite)
    if (std::find(names.begin(), names.end(), c.name) != names.end()) out.push_back(c);
  return out;
}

VerifySummary verify_run(const VerifyOptions& options) {
  const auto t_start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  check_options(options);
  const fs::path dir(options.dir);
  std::error_code ec;
  const RunConfig config = read_run_config((dir / run_file::kConfig).string());
  const RunSettings settings = run_settings(config);
  VerifySummary summary;
  summary.subjects = plan(settings, options);
  const core::TaskConfig& task = settings.loop.task;
  const auto policy = std::make_shared<const rl::Policy>(rl::load_policy(dir / run_file::kPolicy));

  const fs::path folder = dir / (options.phase_set == "test" ? "verify" : "verify_validation");
  summary.folder = folder.string();
  fs::create_directories(folder, ec);
  if (ec) throw InputError(folder.string() + ": cannot create: " + ec.message());
  const io::RunLock lock(folder.string());

  const fs::path csv = folder / "conditions.csv";
  std::map<std::string, VerifyRow> done;
  for (const VerifyRow& r : open_resumable_table<VerifyRow>(folder, folder / "verify.toml", csv,
                                                            verify_stamp(options), kColumns,
                                                            options.force, "a verify", read_rows))
    done[cell_key(r.subject, r.controller, r.at, r.condition)] = r;
  if (done.empty())
    for (const char* f : {"report.md", "verify.dat", "verify.png"}) fs::remove(folder / f, ec);

  core::EvaluationOptions eo;
  eo.episodes = options.phases;
  eo.phase_offset = options.phase_set == "test" ? kTestOffset : kValidationOffset;
  eo.threads = options.threads;
  eo.trace_first = false;
  auto nominal_sims = std::make_shared<core::SimulatorPool>(settings.spec, settings.scene, settings.solver);
  std::shared_ptr<core::SimulatorPool> refined_sims;
  const auto sims_for = [&](const VerifyCondition& c) {
    if (!c.refined_mesh) return nominal_sims;
    if (!refined_sims) {
      fem::WhiskerModelSpec spec = settings.spec;
      spec.mesh.radius_factor = 0.3;
      spec.mesh.wall_factor = 0.75;
      spec.mesh.max_size_mm = 3.0;
      refined_sims = std::make_shared<core::SimulatorPool>(spec, settings.scene, settings.solver);
    }
    return refined_sims;
  };
  // The PIDs are tuned once, on the nominal model's tuning phases, only if a cell still needs them.
  std::map<std::string, core::ControllerFactory> pids;
  const auto controller_for = [&](const VerifySubject& s) -> core::ControllerFactory {
    if (s.controller == kControllerPolicy) return core::policy_factory(policy);
    if (s.controller == kControllerSpecialist)
      return core::policy_factory(std::make_shared<const rl::Policy>(rl::load_policy(s.policy_file)));
    if (const auto it = pids.find(s.controller); it != pids.end()) return it->second;
    const core::PidSignal signal =
        s.controller == kControllerPidForce ? core::PidSignal::Force : core::PidSignal::Estimate;
    const core::EpisodeSetup setup{s.at.design, s.at.p1_kPa, s.at.p2_kPa, 0.0, 0.0};
    const core::PidTuningResult t = core::tune_whisker_pid(nominal_sims, task, setup, signal, config.pid, options.threads);
    if (options.progress) {
      std::printf("verify: %-13s tuned on %d nominal tuning phases: kp %.4g ki %.4g kd %.4g (tuning return %.2f)\n",
                  s.controller.c_str(), config.pid.tuning_phases, t.pid.gains.kp, t.pid.gains.ki, t.pid.gains.kd,
                  t.tuning_return);
      std::fflush(stdout);
    }
    return pids[s.controller] = core::pid_factory(t.pid, task);
  };

  const std::vector<VerifyCondition> suite = chosen_conditions(options.conditions);
  for (const VerifySubject& s : summary.subjects) {
    core::ControllerFactory controller;
    for (const VerifyCondition& c : suite) {
      if (const auto it = done.find(cell_key(s.name, s.controller, s.at, c.name)); it != done.end()) {
        summary.rows.push_back(it->second);
        ++summary.cells_before;
        continue;
      }
      if (!controller) controller = controller_for(s);
      core::EpisodeSetup setup{s.at.design, s.at.p1_kPa, s.at.p2_kPa, 0.0, 0.0};
      setup.physics = c.physics;
      const core::DesignEvaluation e = core::evaluate_feedback(controller, sims_for(c), task, setup, eo);
      VerifyRow r{s.name, s.controller, s.at, c.name, e.mean_return, e.std_return, core::ci95_of_mean(e),
                  e.mean_band_fraction, options.phases};
      std::ofstream out(csv, std::ios::binary | std::ios::app);
      out << row_line(r) << '\n';
      if (!out.flush()) throw InputError(csv.string() + ": cannot write (disk full?)");
      summary.rows.push_back(r);
      ++summary.cells_run;
      summary.episodes_run += options.phases;
      if (options.progress) {
        std::printf("verify: %-15s %-13s %6.2f +- %.2f (95 %% interval +- %.2f)\n", s.name.c_str(), c.name.c_str(),
                    r.mean_return, r.std_return, r.ci95);
        std::fflush(stdout);
      }
    }
  }

  VerifyReportInput in;
  in.run = options.dir;
  in.phase_set = options.phase_set;
  in.phases = options.phases;
  in.subjects = summary.subjects;
  for (const VerifyCondition& c : suite) in.conditions.emplace_back(c.name, c.what);
  in.rows = summary.rows;
  if (settings.loop.codesign.baseline == core::Baseline::SingleDesign)
    in.notes = "The run trained d* alone (codesign.baseline = \"single_design\"): its policy is tested on no other design.";
  io::write_file_atomically((folder / "report.md").string(), [&](std::ostream& out) { out << verify_report(in); });
  summary.figure_message = draw_figure(folder, options.plots_dir, summary, suite, run_folder_name(options.dir));
  summary.wall_s = seconds_since(t_start);
  summary.cpu_s = process_cpu_seconds() - cpu_start;
  return summary;
}

}  // namespace codesign::run
