// `codesign sweep --config run.toml -o DIR [--designs A-B] [--threads N] [--force] [--report] [--plots DIR]`
//
// The design landscape (run/sweep_run.hpp, docs/baselines.md): every design of [sweep] on its
// pressure grid with the best fixed θ and the PIDs tuned by NLopt ([pid]); DIR/sweep.csv,
// resumable (run the same command again and it continues after the last finished row), the
// heat-map tables and PNGs and a summary per controller.
#include <memory>
#include <string>
#include <tuple>

#include "cli_options.hpp"
#include "commands.hpp"
#include "io/config/toml_reader.hpp"
#include "run/run_config.hpp"
#include "run/sweep_run.hpp"

namespace codesign::app {

namespace {

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

struct SweepCliOptions {
  std::string config;
  std::string designs;
  run::SweepRunOptions run;
};

int run_sweep_command(const SweepCliOptions& o) {
  run::RunConfig setup = run::read_run_config(o.config);
  if (!o.designs.empty()) std::tie(setup.sweep.first_design, setup.sweep.last_design) = parse_design_range(o.designs);
  run::SweepRunOptions so = o.run;
  so.config_text = io::TableReader::input_text(o.config);
  if (so.plots_dir.empty()) so.plots_dir = CODESIGN_PLOTS_DIR;
  run::run_design_sweep(setup, so);
  return 0;
}

}  // namespace

void add_sweep_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<SweepCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "sweep", "Design landscape: every design on a pressure grid with tuned PIDs and the best fixed theta");
  cmd->add_option("--config", opt->config, "run config (TOML; [sweep], [pid])")->required();
  cmd->add_option("-o,--out", opt->run.out, "output directory (default runs/sweep)");
  add_designs_option(*cmd, opt->designs, "[sweep] first_design..last_design");
  add_threads_option(*cmd, opt->run.threads);
  cmd->add_flag("--force", opt->run.force, "start afresh even if the directory holds a sweep of another config");
  cmd->add_flag("--report", opt->run.report_only,
                "run nothing: heat maps and summary from the rows of an earlier (possibly unfinished) sweep");
  cmd->add_option("--plots", opt->run.plots_dir, "folder of sweep_heatmap.gp (default: " CODESIGN_PLOTS_DIR ")");
  cmd->callback([opt, &run] { run = [opt] { return run_sweep_command(*opt); }; });
}

}  // namespace codesign::app
