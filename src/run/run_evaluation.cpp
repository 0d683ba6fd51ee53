#include "run/run_evaluation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <set>
#include <sstream>

#include "base/duration_text.hpp"
#include "base/errors.hpp"
#include "base/seconds_since.hpp"
#include "core/evaluation.hpp"
#include "core/outer_loop.hpp"
#include "core/policy_controller.hpp"
#include "fem/design.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "io/formats/csv_table.hpp"
#include "io/formats/gnuplot.hpp"
#include "io/formats/run_lock.hpp"
#include "run/checkpoint.hpp"
#include "run/codesign_tables_writer.hpp"
#include "run/run_config.hpp"
#include "run/resumable_table.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

namespace {

namespace fs = std::filesystem;

constexpr const char* kColumns =
    "design,n,l_mm,w_mm,p1_kPa,p2_kPa,q,score,samples,mean_return,std_return,ci95,band_fraction,episodes,seconds";

std::string num(double v) { return io::CsvLog::num(v); }

std::string row_line(const RunEvaluationRow& r) {
  const fem::Design d = fem::design_from_index(r.design);
  std::ostringstream s;
  s << r.design << ',' << d.n << ',' << num(d.chamber_length_mm) << ',' << num(d.wall_mm) << ',' << num(r.p1_kPa)
    << ',' << num(r.p2_kPa) << ',' << num(r.q) << ',' << num(r.score) << ',' << r.samples << ','
    << num(r.mean_return) << ',' << num(r.std_return) << ',' << num(r.ci95) << ',' << num(r.band_fraction) << ','
    << r.episodes << ',' << num(r.seconds);
  return s.str();
}

std::vector<RunEvaluationRow> read_rows(const std::string& path) {
  const io::CsvTable t = io::read_csv(path);
  std::vector<RunEvaluationRow> rows;
  const auto col = [&](const char* name) { return t.column(name); };
  for (std::size_t i = 0; i < t.rows(); ++i) {
    RunEvaluationRow r;
    const std::int64_t j = t.integer(i, col("design"));
    if (j < 0 || j >= fem::kDesignCount)
      throw InputError(path + ": line " + std::to_string(i + 2) + ", column 'design': " + std::to_string(j) +
                       " is outside 0.." + std::to_string(fem::kDesignCount - 1));
    r.design = static_cast<int>(j);
    r.p1_kPa = t.number(i, col("p1_kPa"));
    r.p2_kPa = t.number(i, col("p2_kPa"));
    r.q = t.number(i, col("q"));
    r.score = t.number(i, col("score"));
    r.samples = t.integer(i, col("samples"));
    r.mean_return = t.number(i, col("mean_return"));
    r.std_return = t.number(i, col("std_return"));
    r.ci95 = t.number(i, col("ci95"));
    r.band_fraction = t.number(i, col("band_fraction"));
    r.episodes = static_cast<int>(t.integer(i, col("episodes")));
    r.seconds = t.number(i, col("seconds"));
    rows.push_back(r);
  }
  return rows;
}

// Draws ranking.png from ranking.dat with plots/evaluate_ranking.gp; "" if drawn, else why not.
std::string draw_ranking(const fs::path& folder, const std::string& plots_dir, const RunEvaluationSummary& s,
                         const std::string& at) {
  if (plots_dir.empty()) return "no plots folder given";
  const fs::path script = fs::path(plots_dir) / "evaluate_ranking.gp";
  if (!fs::exists(script)) return script.string() + " not found";
  io::GnuplotCall call;
  call.script = script.string();
  call.set("plotsdir", plots_dir);
  call.set("datafile", (folder / "ranking.dat").string());
  call.set("outfile", (folder / "ranking.png").string());
  call.set("title", "policy at " + at + " (t = " + std::to_string(s.t) + "): designs by test return" +
                        (s.pressures_t >= 0 ? ", at another run's pressures" : ""));
  const io::GnuplotOutcome r = io::run_gnuplot(call);
  return r.ok() ? "" : r.message();
}

}  // namespace

std::string checkpoint_file_of(const std::string& at) {
  if (at == "final") return run_file::kCheckpoint;
  for (const KeptCheckpoint& k : kept_checkpoints(CodesignConfig{}))
    if (k.name == at) return k.file;
  throw InputError("--at: '" + at + "' is not one of final, t1, t2");
}

std::string evaluation_folder_name(const RunEvaluationOptions& options) {
  if (options.pressures_of.empty()) return options.at;
  return options.at + "_pressures_of_" + run_folder_name(options.pressures_of);
}

namespace {

// One state of a run folder, restored from its checkpoint of `at`: the policy and the design
// distribution as the run held them (no rollout runs).
struct RestoredState {
  std::string file;                      // the checkpoint's file name
  std::uint64_t config_fingerprint = 0;
  std::shared_ptr<SimulatorPool> sims;
  std::unique_ptr<OuterLoop> loop;
};

RestoredState restore_state(const RunSettings& settings, const fs::path& dir, const std::string& at) {
  RestoredState s;
  s.file = checkpoint_file_of(at);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string() + ": no such run folder");
  const fs::path ckpt_path = dir / s.file;
  if (!fs::exists(ckpt_path, ec))
    throw InputError(ckpt_path.string() + ": no such checkpoint" +
                     (at == "final" ? std::string(" (the run has not reached its first checkpoint)")
                                    : " (the run has not reached " + at + " yet, or was started "
                                      "before runs kept their T1 and T2 checkpoints)"));
  const LoopConfig& lc = settings.loop;
  const std::string resolved = resolved_run_config(settings.spec, settings.scene, settings.solver, lc);
  const Checkpoint ckpt = load_checkpoint(ckpt_path.string(), fingerprint(resolved));
  s.config_fingerprint = ckpt.config_fingerprint;
  s.sims = std::make_shared<SimulatorPool>(settings.spec, settings.scene, settings.solver);
  s.loop = std::make_unique<OuterLoop>(
      lc, std::make_unique<ThreadEnvPool>(s.sims, lc.task, static_cast<std::size_t>(lc.codesign.designs_per_update), 1,
                                          lc.ppo.privileged_critic));
  try {
    s.loop->restore(ckpt.loop);
  } catch (const std::invalid_argument& e) {
    throw InputError("checkpoint " + ckpt_path.string() + ": " + e.what());
  }
  return s;
}

// The pressures a state tests design j at: map(μ_j), or the p* the run fixed for the design the
// distribution has collapsed to (as the run's own final evaluation does).
Eigen::Vector2d test_pressures(const DesignDistribution& dist, int j) {
  return dist.state().collapsed && j == dist.state().best_design ? dist.pressures_kPa(dist.state().best_latent, j)
                                                                 : dist.mean_pressures_kPa(j);
}

// The options' ranges: --at, --designs and the phases (returned: the run's eval_episodes unless
// given), each an InputError naming the flag.
int checked_phases(const RunEvaluationOptions& options, const LoopConfig& lc) {
  checkpoint_file_of(options.at);  // a bad --at first
  if (options.first_design < 0 || options.last_design >= fem::kDesignCount || options.first_design > options.last_design)
    throw InputError("--designs: " + std::to_string(options.first_design) + "-" + std::to_string(options.last_design) +
                     " is not a range A-B with 0 <= A <= B <= " + std::to_string(fem::kDesignCount - 1));
  const int phases = options.phases > 0 ? options.phases : lc.codesign.eval_episodes;
  if (phases < 2)
    throw InputError("--phases: " + std::to_string(phases) + " is not in [2, 100000] (the interval needs two episodes)");
  if (phases > 100000) throw InputError("--phases: " + std::to_string(phases) + " is not in [2, 100000]");
  return phases;
}

// The state of another run folder whose pressures the designs are tested at (--pressures-of).
struct PressureSource {
  RestoredState state;  // no loop: this run's own pressures
  std::string dir;      // its folder, canonical where possible
};

PressureSource pressure_source(const RunEvaluationOptions& options) {
  PressureSource source;
  if (options.pressures_of.empty()) return source;
  const fs::path odir(options.pressures_of);
  if (!fs::exists(odir / run_file::kConfig))
    throw InputError("--pressures-of: " + odir.string() + " has no config.toml; it must be a co-design run folder");
  source.state = restore_state(run_settings(read_run_config((odir / run_file::kConfig).string())), odir, options.at);
  std::error_code ec;
  source.dir = fs::weakly_canonical(odir, ec).string();
  if (ec) source.dir = odir.string();
  return source;
}

// evaluate.toml: what this evaluation is; a folder holding another one is continued only if it
// matches.
std::string evaluation_stamp(const RestoredState& state, const PressureSource& source, const RunEvaluationSummary& summary,
                             const RunEvaluationOptions& options, int phases) {
  std::ostringstream stamp;
  stamp << "# codesign evaluate: the deterministic policy of " << state.file << " tested on every design of the range\n"
        << "checkpoint = \"" << state.file << "\"\n"
        << "t = " << summary.t << "\n"
        << "config_fingerprint = \"" << std::hex << state.config_fingerprint << std::dec << "\"\n"
        << "phases = " << phases << "   # episodes per design, plate phases 2*pi*(k + 1/2)/phases\n"
        << "designs = [" << options.first_design << ", " << options.last_design << "]\n";
  if (source.state.loop)
    stamp << "# each design at the pressures of another run's state at " << options.at << "\n"
          << "pressures_of = \"" << source.dir << "\"\n"
          << "pressures_t = " << summary.pressures_t << "\n"
          << "pressures_config_fingerprint = \"" << std::hex << source.state.config_fingerprint << std::dec << "\"\n";
  return stamp.str();
}

// Design j tested with the policy over `phases` plate phases at the pressures `pressure_dist` gives.
RunEvaluationRow evaluate_design(int j, const ControllerFactory& controller, const RestoredState& state,
                                 const DesignDistribution& pressure_dist, const TaskConfig& task,
                                 const RunEvaluationOptions& options, int phases) {
  const auto t0 = std::chrono::steady_clock::now();
  const DesignDistribution& dist = state.loop->distribution();
  EvaluationOptions eo;
  eo.episodes = phases;
  eo.threads = options.threads;
  eo.trace_first = false;
  const Eigen::Vector2d p = test_pressures(pressure_dist, j);
  const DesignEvaluation e = evaluate_feedback(controller, state.sims, task, {j, p[0], p[1], 0.0, 0.0}, eo);
  RunEvaluationRow r;
  r.design = j;
  r.p1_kPa = p[0];
  r.p2_kPa = p[1];
  r.q = dist.probabilities(state.loop->timesteps())[j];
  r.score = dist.state().score[j];
  r.samples = dist.state().samples[static_cast<std::size_t>(j)];
  r.mean_return = e.mean_return;
  r.std_return = e.std_return;
  r.ci95 = ci95_of_mean(e);
  r.band_fraction = e.mean_band_fraction;
  r.episodes = phases;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// The ranking: by test return, best first (ties: lower design index), with each design's role.
std::vector<RunEvaluationRow> ranked(std::vector<RunEvaluationRow> rows, const RunEvaluationSummary& s) {
  std::stable_sort(rows.begin(), rows.end(), [](const RunEvaluationRow& a, const RunEvaluationRow& b) {
    return a.mean_return != b.mean_return ? a.mean_return > b.mean_return : a.design < b.design;
  });
  for (std::size_t i = 0; i < rows.size(); ++i) {
    RunEvaluationRow& r = rows[i];
    r.rank = static_cast<int>(i) + 1;
    r.role = r.design == s.leading_design             ? "d*"
             : r.design == s.runner_up                ? "runner_up"
             : r.design == s.pressures_leading_design ? "pressures_d*"
                                                      : "";
  }
  return rows;
}

// ranking.csv, and gnuplot's table ranking.dat: rank, mean, ci95, design, role index (0 other,
// 1 d*, 2 runner-up, 3 d* of the pressures' run).
void write_ranking(const fs::path& folder, const std::vector<RunEvaluationRow>& ranking) {
  io::write_file_atomically((folder / "ranking.csv").string(), [&](std::ostream& out) {
    out << "rank," << kColumns << ",role\n";
    for (const RunEvaluationRow& r : ranking) out << r.rank << ',' << row_line(r) << ',' << r.role << '\n';
  });
  io::write_file_atomically((folder / "ranking.dat").string(), [&](std::ostream& out) {
    out << "# rank mean_return ci95 design role(0 other, 1 d*, 2 runner-up, 3 d* of the pressures' run)\n";
    for (const RunEvaluationRow& r : ranking)
      out << r.rank << ' ' << num(r.mean_return) << ' ' << num(r.ci95) << ' ' << r.design << ' '
          << (r.role == "d*" ? 1 : r.role == "runner_up" ? 2 : r.role == "pressures_d*" ? 3 : 0) << '\n';
  });
}


}  // namespace

RunEvaluationSummary evaluate_run(const RunSettings& settings, const RunEvaluationOptions& options) {
  const auto t_start = std::chrono::steady_clock::now();
  const int phases = checked_phases(options, settings.loop);
  const RestoredState state = restore_state(settings, options.dir, options.at);
  const PressureSource source = pressure_source(options);
  const DesignDistribution& dist = state.loop->distribution();
  const DesignDistribution& pressure_dist = source.state.loop ? source.state.loop->distribution() : dist;

  RunEvaluationSummary summary;
  const fs::path folder = fs::path(options.dir) / run_file::kEvaluateDir / evaluation_folder_name(options);
  summary.folder = folder.string();
  summary.t = state.loop->timesteps();
  if (source.state.loop) {
    summary.pressures_leading_design = pressure_dist.leading_design();
    summary.pressures_t = source.state.loop->timesteps();
  }
  summary.leading_design = dist.leading_design();
  const std::vector<int> rank = dist.ranking();
  summary.runner_up = rank.size() < 2 ? -1 : (rank[0] == summary.leading_design ? rank[1] : rank[0]);
  const io::RunLock lock(folder.string());

  std::vector<RunEvaluationRow> done = open_resumable_table<RunEvaluationRow>(
      folder, folder / "evaluate.toml", folder / "designs.csv", evaluation_stamp(state, source, summary, options, phases),
      kColumns, options.force, "an evaluation", [](const fs::path& csv) { return read_rows(csv.string()); });
  std::error_code ec;
  if (done.empty())
    for (const char* f : {"ranking.csv", "ranking.dat", "ranking.png"}) fs::remove(folder / f, ec);
  std::set<int> have;
  for (const RunEvaluationRow& r : done) have.insert(r.design);
  summary.designs_before = static_cast<int>(have.size());

  const ControllerFactory controller = policy_factory(std::make_shared<const rl::Policy>(state.loop->policy_contents()));
  const int todo = options.last_design - options.first_design + 1 - static_cast<int>(have.size());
  const fs::path csv = folder / "designs.csv";
  std::FILE* f = std::fopen(csv.c_str(), "ab");
  if (!f) throw InputError(csv.string() + ": cannot open for appending");
  for (int j = options.first_design; j <= options.last_design; ++j) {
    if (have.count(j)) continue;
    const RunEvaluationRow r = evaluate_design(j, controller, state, pressure_dist, settings.loop.task, options, phases);
    const std::string line = row_line(r) + "\n";
    if (std::fwrite(line.data(), 1, line.size(), f) != line.size() || std::fflush(f) != 0) {
      std::fclose(f);
      throw InputError(csv.string() + ": cannot write (disk full?)");
    }
    done.push_back(r);
    ++summary.designs_run;
    if (options.progress) {
      const double eta = seconds_since(t_start) / summary.designs_run * (todo - summary.designs_run);
      std::printf("evaluate: %d/%d | ETA %s | %s p=[%.4g, %.4g] kPa: %.2f +- %.2f (q %.4f, R^ %.2f)\n",
                  summary.designs_run, todo, duration_text(eta).c_str(), fem::design_label(j).c_str(), r.p1_kPa,
                  r.p2_kPa, r.mean_return, r.ci95, r.q, r.score);
      std::fflush(stdout);
    }
  }
  std::fclose(f);

  summary.ranking = ranked(std::move(done), summary);
  write_ranking(folder, summary.ranking);
  summary.figure_message = draw_ranking(folder, options.plots_dir, summary, options.at);
  summary.figure = summary.figure_message.empty();
  summary.wall_s = seconds_since(t_start);
  return summary;
}

std::vector<StateDesign> state_designs(const RunSettings& settings, const std::string& dir, const std::string& at) {
  const RestoredState state = restore_state(settings, dir, at);
  const DesignDistribution& dist = state.loop->distribution();
  const Eigen::VectorXd q = dist.probabilities(state.loop->timesteps());
  std::vector<StateDesign> out;
  for (int j = 0; j < fem::kDesignCount; ++j) {
    const Eigen::Vector2d p = test_pressures(dist, j);
    out.push_back({j, q[j], p[0], p[1]});
  }
  std::stable_sort(out.begin(), out.end(), [](const StateDesign& a, const StateDesign& b) { return a.q > b.q; });
  return out;
}

void evaluate_run_folder(const RunEvaluationOptions& eo) {
  const fs::path dir(eo.dir);
  if (!fs::exists(dir / run_file::kConfig))
    throw InputError(dir.string() + ": has no config.toml; evaluate needs a co-design run folder");
  checkpoint_file_of(eo.at);  // a bad --at before the config is read
  const RunConfig setup = read_run_config((dir / run_file::kConfig).string());
  const RunSettings s = run_settings(setup);
  std::printf("evaluate: %s at %s: designs %d..%d, %d plate phases each%s%s\n", eo.dir.c_str(), eo.at.c_str(),
              eo.first_design, eo.last_design, eo.phases > 0 ? eo.phases : setup.codesign.eval_episodes,
              eo.pressures_of.empty() ? "" : ", at the pressures of ", eo.pressures_of.c_str());
  std::fflush(stdout);
  const RunEvaluationSummary r = evaluate_run(s, eo);
  const auto find = [&](int j) {
    return std::find_if(r.ranking.begin(), r.ranking.end(), [j](const RunEvaluationRow& x) { return x.design == j; });
  };
  std::printf("evaluate: t = %lld; %d designs run now, %d before; this call took %s\n", static_cast<long long>(r.t),
              r.designs_run, r.designs_before, duration_text(r.wall_s).c_str());
  std::printf("evaluate: top %zu by test return (mean +- 95 %% interval over the phases):\n",
              std::min<std::size_t>(10, r.ranking.size()));
  for (std::size_t i = 0; i < std::min<std::size_t>(10, r.ranking.size()); ++i) {
    const RunEvaluationRow& x = r.ranking[i];
    std::printf("  %3d  %-24s p=[%.4g, %.4g] kPa  %6.2f +- %.2f  q %.4f%s%s\n", x.rank,
                fem::design_label(x.design).c_str(), x.p1_kPa, x.p2_kPa, x.mean_return, x.ci95, x.q,
                x.role.empty() ? "" : "  ", x.role.c_str());
  }
  const std::string other_role = "d* of " + eo.pressures_of + " (its leading design at " + eo.at + ")";
  for (const auto& [j, role] : {std::pair{r.leading_design, std::string("d* (leading design)")},
                                std::pair{r.runner_up, std::string("runner-up")},
                                std::pair{r.pressures_leading_design, other_role}}) {
    const auto it = find(j);
    if (j < 0) continue;
    if (it == r.ranking.end())
      std::printf("evaluate: %s %s is outside the evaluated range\n", role.c_str(), fem::design_label(j).c_str());
    else
      std::printf("evaluate: %s %s ranks %d of %zu: %.2f +- %.2f\n", role.c_str(), fem::design_label(j).c_str(), it->rank,
                  r.ranking.size(), it->mean_return, it->ci95);
  }
  std::printf("evaluate: wrote %s/ranking.csv%s\n", r.folder.c_str(), r.figure ? " and ranking.png" : "");
  if (!r.figure) std::printf("evaluate: warning: no ranking.png: %s\n", r.figure_message.c_str());
}

}  // namespace codesign::run
