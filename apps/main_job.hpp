#pragma once
// `codesign run` and the main job `codesign --config run.toml -o runs/NAME`: the co-design run
// of a config file (run.hpp, run_codesign) under the run folder's lock and the stop signals
// (stop_signals.hpp), then its frames ([render], episode_render.hpp) and figures (figures.hpp).
#include <optional>
#include <string>

namespace codesign::run {

// The flags of `codesign run`.
struct MainJobOptions {
  std::string config;
  std::string out;
  bool resume = false;
  bool force = false;
  int threads = 0;
  long long stop_after = -1;
  bool quiet = false;
  std::optional<std::string> telemetry;
  bool no_figures = false;
  std::string plots_dir;   // the gnuplot scripts of the figures at the end
};

// Returns the exit status: 0 (done), 4 (stopped by --stop-after, checkpointed), 128 + signal
// (stopped by SIGTERM/SIGINT, checkpointed), or stop_after_run's status when a signal came after
// result.toml. Bad input (the config; ppo.n_steps other than the decisions per episode; a folder
// holding an earlier run or locked by a live one) is an InputError before the run starts.
int run_main_job(const MainJobOptions& options);

}  // namespace codesign::run
