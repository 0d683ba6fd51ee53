// `codesign run --config run.toml [-o runs/NAME] [--resume] [--force] [--threads N] [--quiet] [--no-figures]`
// (also the main job: `codesign --config run.toml -o runs/NAME`).
//
// Runs the co-design (Algorithm 1 + 2) of the config's [codesign], [task], [ppo] and simulator
// tables, writing the run folder described in src/run/run.hpp, then its figures
// (`codesign figures`, cmd_figures.cpp) into RUN/figures/.
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "base/errors.hpp"
#include "run/episode_render.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"
#include "run/stop_signals.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "io/run_lock.hpp"
#include "io/toml_reader.hpp"

namespace codesign::app {

namespace {

struct RunCliOptions {
  std::string config;
  std::string out;
  bool resume = false;
  bool force = false;
  int threads = 0;
  long long stop_after = -1;
  bool quiet = false;
  std::optional<std::string> telemetry;
  bool no_figures = false;
};

int run_main_job(const RunCliOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  // One rollout of ppo.n_steps decisions is one episode per environment (Algorithm 1).
  const int decisions = setup.task.episode_steps / setup.task.action_hold_steps;
  if (setup.ppo.n_steps != decisions)
    throw InputError(o.config + ": ppo.n_steps: value " + std::to_string(setup.ppo.n_steps) +
                     " must equal the decisions per episode, task.episode_steps / task.action_hold_steps = " +
                     std::to_string(decisions));
  // Default run folder: runs/<config file name without extension>.
  const std::string out = o.out.empty() ? "runs/" + std::filesystem::path(o.config).stem().string() : o.out;
  run::RunSettings s;
  s.spec = setup.spec;
  s.scene = setup.scene;
  s.solver = setup.solver;
  s.loop = {setup.task, setup.codesign, setup.ppo};
  s.config_text = io::TableReader::input_text(o.config);
  // SIGTERM / SIGINT stop the run at the next iteration's end with a checkpoint (stop_signals.hpp),
  // and the run folder stays locked from here through the frames and figures.
  const run::StopSignals signals;
  const std::unique_ptr<io::RunLock> lock = run::lock_run_folder(out, /*only_if_exists=*/o.resume);
  run::RunOptions ro;
  ro.lock = lock.get();
  ro.dir = out;
  ro.resume = o.resume;
  ro.force = o.force;
  ro.threads = static_cast<std::size_t>(o.threads);
  ro.progress = !o.quiet;
  ro.stop_after = o.stop_after;
  ro.telemetry_url = o.telemetry ? *o.telemetry : setup.telemetry_url;
  ro.telemetry_train_every = setup.telemetry_train_every;
  const run::RunResult r = run::run_codesign(s, ro);
  if (r.stop_signal != 0) return 128 + r.stop_signal;  // as a shell reports a process the signal ended
  if (!r.completed) return 4;
  // A signal after result.toml was written skips the frames and figures still to draw.
  const bool frames = setup.render.enabled, figures = !o.no_figures;
  if (const int st = run::stop_after_run(out, frames, figures); st != 0) return st;
  // The first evaluation episodes of d* and the runner-up as PNG frames ([render], docs/rendering.md).
  if (frames)
    run::render_run_frames(out, std::make_shared<coopt::SimulatorPool>(s.spec, s.scene, s.solver), s.loop.task,
                             s.loop.codesign.eval_episodes, setup.render, /*force=*/true);
  if (const int st = run::stop_after_run(out, false, figures); st != 0) return st;
  // The paper's figures from the finished run (RUN/figures/); a problem there is a warning only.
  if (figures) draw_run_figures(out);
  return 0;
}

}  // namespace

void add_run_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<RunCliOptions>();
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
  cmd->callback([opt, &run] { run = [opt] { return run_main_job(*opt); }; });
}

}  // namespace codesign::app
