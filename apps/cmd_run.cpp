// `codesign run --config run.toml [-o runs/NAME] [--resume] [--force] [--threads N] [--quiet] [--no-figures]`
// (also the main job: `codesign --config run.toml -o runs/NAME`).
//
// Runs the co-design (Algorithm 1 + 2) of the config's [codesign], [task], [ppo] and simulator
// tables, writing the run folder described in src/run/run.hpp, then its figures
// (`codesign figures`) into RUN/figures/ (apps/main_job.hpp).
#include <memory>

#include "cli_options.hpp"
#include "commands.hpp"
#include "main_job.hpp"

namespace codesign::app {

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

void add_run_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<run::MainJobOptions>();
  opt->plots_dir = CODESIGN_PLOTS_DIR;
  CLI::App* cmd = root.add_subcommand("run", "Co-design run: Algorithms 1 and 2, evaluation, result.toml (the main job)");
  cmd->add_option("--config", opt->config, "run config (TOML)")->required();
  cmd->add_option("-o,--out", opt->out, "run folder (default runs/<config name>)");
  CLI::Option* resume = cmd->add_flag("--resume", opt->resume, "continue the run in the folder from its checkpoint.bin");
  CLI::Option* force = cmd->add_flag("--force", opt->force, "start afresh even if the folder holds an earlier run");
  resume->excludes(force);
  add_threads_option(*cmd, opt->threads, "rollout threads, counting the main one (0: all cores)");
  cmd->add_option("--stop-after", opt->stop_after,
                  "stop (checkpointed, exit status 4) after the iteration reaching this many timesteps; for tests")
      ->check(CLI::Range(0LL, 1LL << 40));
  cmd->add_flag("--quiet", opt->quiet, "no progress line");
  cmd->add_flag("--no-figures", opt->no_figures, "do not draw RUN/figures/ at the end (see `codesign figures`)");
  cmd->add_option("--telemetry", opt->telemetry,
                  "LCM URL for live telemetry, overriding [telemetry] url (\"\" = off; see docs/telemetry.md)");
  cmd->callback([opt, &run] { run = [opt] { return run::run_main_job(*opt); }; });
}

}  // namespace codesign::app
