#pragma once
// `codesign sweep` (docs/baselines.md): the design landscape of core::run_sweep (every design of
// [sweep] on its pressure grid, each with the controllers of [sweep] tuned on [pid]; DIR/sweep.csv,
// resumable), then a summary per controller and, with gnuplot installed, one heat map
// DIR/heatmap_<controller>.png per controller from the tables DIR/heatmap_n<N>_<c>.dat
// (plots/sweep_heatmap.gp through io::run_gnuplot).
#include <string>

#include "run/run_config.hpp"

namespace codesign::run {

struct SweepRunOptions {
  std::string out = "runs/sweep";  // DIR
  // The config file's text as read, kept as DIR/sweep.config.toml: a restart must match it (the
  // design range of `config`'s [sweep] is appended, since --designs may have changed it).
  std::string config_text;
  std::string plots_dir;   // folder of sweep_heatmap.gp
  int threads = 0;         // 0: one per core
  bool force = false;      // start afresh even if DIR holds a sweep of another config
  bool report_only = false;  // run nothing: heat maps and summary from the rows already there
};

// A missing script or a failing gnuplot is a printed warning: the tables are the result.
void run_design_sweep(const RunConfig& config, const SweepRunOptions& options);

}  // namespace codesign::run
