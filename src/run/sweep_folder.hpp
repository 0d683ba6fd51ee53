#pragma once
// `codesign sweep`'s folder (docs/baselines.md). run_sweep() writes DIR/sweep.csv, one row of
// core::sweep_one per (design, pressures, controller), appended and flushed as each row is
// finished; started again on the same DIR with the same config, it skips the rows already there
// (a half-written last line is cut off), so a killed sweep resumes. Work units (design,
// pressures) run in parallel, each single-threaded; a progress line is printed after each unit.
// At the end it writes the heat-map tables DIR/heatmap_n<N>_<controller>.dat (l × w, the best
// test return over the pressure grid).
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/design_sweep.hpp"
#include "core/pid_tuning.hpp"
#include "core/simulator_pool.hpp"
#include "core/task_config.hpp"

namespace codesign::run {

struct SweepOptions {
  std::string dir;
  std::string config_text;     // kept as DIR/sweep.config.toml; a restart must match it
  bool force = false;          // start afresh even if DIR holds a sweep of another config
  std::size_t threads = 0;     // 0: all cores
  bool progress = true;
  bool report_only = false;    // run nothing: heat maps and summary from the rows already there
};
struct SweepSummary {
  int rows_total = 0, rows_done_before = 0, rows_run = 0;
  double wall_s = 0.0;
  std::vector<core::SweepRow> rows;  // every row of sweep.csv at the end
};
// Runs the rows DIR/sweep.csv does not hold yet, the units (design, pressures) in a spread-out
// order, on options.threads threads; then writes the heat-map tables heatmap_n<N>_<controller>.dat.
// A folder holding a sweep of another config is an InputError unless options.force.
SweepSummary run_sweep(const std::shared_ptr<core::SimulatorPool>& sims, const core::TaskConfig& task,
                       const core::SweepConfig& sweep, const core::PidTuningConfig& pid, const SweepOptions& options);

// sweep.csv (header + rows) reading and writing, for resuming and for tests. The reader also
// takes a sweep.csv of the previous version (without the fit_r2, fit_rms_mN columns; those are
// then NaN), so `--report` works on it; run_sweep refuses to append to one.
std::string sweep_csv_header();
std::string sweep_csv_header_without_fit();  // the previous version's header
std::string sweep_csv_line(const core::SweepRow& r);
std::vector<core::SweepRow> read_sweep_csv(const std::string& path);  // complete lines only

}  // namespace codesign::run
