// `codesign sweep --config run.toml -o DIR [--designs A-B] [--threads N] [--force] [--report] [--plots DIR]`
//
// The design landscape (docs/baselines.md): every design of [sweep] on its pressure grid, each
// with the best fixed θ, the force PID, the strain PID and the estimate PID tuned by NLopt ([pid]); DIR/sweep.csv
// one row per (design, pressures, controller), resumable: run the same command again and it
// continues after the last finished row. Then the heat-map tables DIR/heatmap_n<N>_<c>.dat and,
// with gnuplot installed, DIR/heatmap_<c>.png (plots/sweep_heatmap.gp through io::run_gnuplot),
// and a summary per controller.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "base/duration_text.hpp"
#include "codesign/design_sweep.hpp"
#include "run/run_config.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "io/gnuplot.hpp"
#include "io/toml_reader.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct SweepCliOptions {
  std::string config;
  std::string out = "runs/sweep";
  std::string designs;
  int threads = 0;
  bool force = false;
  bool report = false;
  std::string plots;  // folder of sweep_heatmap.gp; empty: CODESIGN_PLOTS_DIR
};

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

// The heat-map script: --plots DIR, else this source tree's plots/ (as `codesign figures`).
fs::path heatmap_script(const std::string& plots) {
  return fs::path(plots.empty() ? std::string(CODESIGN_PLOTS_DIR) : plots) / "sweep_heatmap.gp";
}

// One PNG per controller from the heat-map tables (a warning, not an error, if gnuplot is missing
// or fails: the tables are the result).
void plot_heatmaps(const fs::path& dir, const coopt::SweepConfig& sweep, const std::string& plots) {
  const fs::path script = heatmap_script(plots);
  for (coopt::SweepController c : sweep.controllers) {
    const std::string name = coopt::to_string(c);
    const fs::path f1 = dir / ("heatmap_n1_" + name + ".dat"), f2 = dir / ("heatmap_n2_" + name + ".dat");
    if (!fs::exists(f1) || !fs::exists(f2)) continue;
    io::GnuplotCall call;
    call.script = script.string();
    call.set("file_n1", f1.string());
    call.set("file_n2", f2.string());
    call.set("outfile", (dir / ("heatmap_" + name + ".png")).string());
    call.set("controller", name);
    if (!fs::exists(script)) {
      std::printf("sweep: warning: %s not found (pass --plots DIR): no heat-map PNGs\n", script.string().c_str());
      return;
    }
    const io::GnuplotOutcome r = io::run_gnuplot(call);
    if (r.ok())
      std::printf("sweep: wrote %s\n", (dir / ("heatmap_" + name + ".png")).string().c_str());
    else
      std::printf("sweep: warning: %s\n", r.message().c_str());
  }
}

int run_sweep_command(const SweepCliOptions& o) {
  run::RunConfig setup = run::read_run_config(o.config);
  if (!o.designs.empty()) std::tie(setup.sweep.first_design, setup.sweep.last_design) = parse_design_range(o.designs);
  auto sims = std::make_shared<coopt::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  coopt::SweepOptions so;
  so.dir = o.out;
  // The design range is part of what a restart must match.
  so.config_text = io::TableReader::input_text(o.config) + "\n# --designs " + std::to_string(setup.sweep.first_design) + "-" +
                   std::to_string(setup.sweep.last_design) + "\n";
  so.force = o.force;
  so.threads = static_cast<std::size_t>(o.threads);
  so.report_only = o.report;
  const coopt::PidTuningConfig& pc = setup.pid;
  std::printf("sweep: designs %d..%d, pressures_kPa [", setup.sweep.first_design, setup.sweep.last_design);
  for (std::size_t i = 0; i < setup.sweep.pressures_kPa.size(); ++i)
    std::printf("%s%g", i ? ", " : "", setup.sweep.pressures_kPa[i]);
  std::printf("] (two chambers: every pair); tuning on %d plate phases, testing on %d others; PID: NLopt %s, "
              "%d starts, %d evaluations; fixed theta: %d scan points + %d evaluations\n",
              pc.tuning_phases, pc.test_episodes, coopt::to_string(pc.search.method), pc.search.starts,
              pc.search.max_evals, setup.sweep.fixed_theta.scan_points, setup.sweep.fixed_theta.max_evals);
  std::fflush(stdout);
  const coopt::SweepSummary s = coopt::run_sweep(sims, setup.task, setup.sweep, pc, so);
  std::printf("sweep: %d rows run now, %d before, %d of %d in all; this call took %s\n", s.rows_run,
              s.rows_done_before, static_cast<int>(s.rows.size()), s.rows_total, duration_text(s.wall_s).c_str());
  // Summary per controller: best design, median, and the best few.
  for (coopt::SweepController c : setup.sweep.controllers) {
    std::vector<const coopt::SweepRow*> rows;
    for (const coopt::SweepRow& r : s.rows)
      if (r.controller == c) rows.push_back(&r);
    if (rows.empty()) continue;
    std::stable_sort(rows.begin(), rows.end(),
                     [](const coopt::SweepRow* a, const coopt::SweepRow* b) { return a->test_return > b->test_return; });
    const coopt::SweepRow& b = *rows.front();
    std::printf("sweep: %-11s best j%d p=[%g, %g]: %.2f +- %.2f over %d test episodes; median %.2f; worst %.2f "
                "(%zu rows)\n",
                coopt::to_string(c), b.point.design, b.point.p1_kPa, b.point.p2_kPa, b.test_return, b.test_std,
                b.test_episodes, rows[rows.size() / 2]->test_return, rows.back()->test_return, rows.size());
    std::printf("sweep: %-11s top 5:", coopt::to_string(c));
    for (std::size_t i = 0; i < std::min<std::size_t>(5, rows.size()); ++i)
      std::printf(" j%d %.2f", rows[i]->point.design, rows[i]->test_return);
    std::printf("\n");
  }
  plot_heatmaps(fs::path(o.out), setup.sweep, o.plots);
  std::printf("sweep: wrote %s\n", (fs::path(o.out) / "sweep.csv").string().c_str());
  return 0;
}

}  // namespace

void add_sweep_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<SweepCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "sweep", "Design landscape: every design on a pressure grid with tuned PIDs and the best fixed theta");
  cmd->add_option("--config", opt->config, "run config (TOML; [sweep], [pid])")->required();
  cmd->add_option("-o,--out", opt->out, "output directory (default runs/sweep)");
  add_designs_option(*cmd, opt->designs, "[sweep] first_design..last_design");
  add_threads_option(*cmd, opt->threads);
  cmd->add_flag("--force", opt->force, "start afresh even if the directory holds a sweep of another config");
  cmd->add_flag("--report", opt->report,
                "run nothing: heat maps and summary from the rows of an earlier (possibly unfinished) sweep");
  cmd->add_option("--plots", opt->plots, "folder of sweep_heatmap.gp (default: " CODESIGN_PLOTS_DIR ")");
  cmd->callback([opt, &run] { run = [opt] { return run_sweep_command(*opt); }; });
}

}  // namespace codesign::app
