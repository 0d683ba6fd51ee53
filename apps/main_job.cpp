#include "main_job.hpp"

#include <filesystem>
#include <memory>

#include "base/errors.hpp"
#include "cluster/mpi_world.hpp"
#include "io/formats/run_lock.hpp"
#include "io/config/toml_reader.hpp"
#include "run/episode_render.hpp"
#include "run/figures.hpp"
#include "run/rollout_backend.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"
#include "run/stop_signals.hpp"

namespace codesign::run {

int run_main_job(const MainJobOptions& o) {
  const RunConfig setup = read_run_config(o.config);
  // One rollout of ppo.n_steps decisions is one episode per environment (Algorithm 1).
  const int decisions = setup.task.episode_steps / setup.task.action_hold_steps;
  if (setup.ppo.n_steps != decisions)
    throw InputError(o.config + ": ppo.n_steps: value " + std::to_string(setup.ppo.n_steps) +
                     " must equal the decisions per episode, task.episode_steps / task.action_hold_steps = " +
                     std::to_string(decisions));
  // Default run folder: runs/<config file name without extension>.
  const std::string out = o.out.empty() ? "runs/" + std::filesystem::path(o.config).stem().string() : o.out;
  const RunSettings s = run_settings(setup, io::TableReader::input_text(o.config));
  // Under an MPI launcher (docs/cluster.md) rank 0 is the run; every other rank only steps its
  // slice of the rollouts and touches no file.
  const std::vector<int> here = cluster::ranks_on_this_machine();  // collective: every rank, before they part
  if (serve_unless_rank_zero(s, static_cast<std::size_t>(o.threads), here)) return 0;
  // SIGTERM / SIGINT stop the run at the next iteration's end with a checkpoint (stop_signals.hpp),
  // and the run folder stays locked from here through the frames and figures.
  const StopSignals signals;
  const std::unique_ptr<io::RunLock> lock = lock_run_folder(out, /*only_if_exists=*/o.resume);
  RunOptions ro;
  ro.lock = lock.get();
  ro.dir = out;
  ro.resume = o.resume;
  ro.force = o.force;
  ro.threads = static_cast<std::size_t>(o.threads);
  ro.ranks = cluster::world_size();
  ro.machine_ranks = here;
  // The other ranks on this machine sleep through the final evaluation: rank 0 takes their threads.
  if (o.threads > 0) ro.evaluation_threads = static_cast<std::size_t>(o.threads) * here.size();
  ro.progress = !o.quiet;
  ro.stop_after = o.stop_after;
  ro.telemetry_url = o.telemetry ? *o.telemetry : setup.telemetry_url;
  ro.telemetry_train_every = setup.telemetry_train_every;
  const RunResult r = run_codesign(s, ro);
  if (r.stop_signal != 0) return 128 + r.stop_signal;  // as a shell reports a process the signal ended
  if (!r.completed) return 4;
  // A signal after result.toml was written skips the frames and figures still to draw.
  const bool frames = setup.render.enabled, figures = !o.no_figures;
  if (const int st = stop_after_run(out, frames, figures); st != 0) return st;
  // The first evaluation episodes of d* and the runner-up as PNG frames ([render], docs/rendering.md).
  if (frames)
    render_run_frames(out, std::make_shared<core::SimulatorPool>(s.spec, s.scene, s.solver), s.loop.task,
                      s.loop.codesign.eval_episodes, setup.render, /*force=*/true);
  if (const int st = stop_after_run(out, false, figures); st != 0) return st;
  // The paper's figures from the finished run (RUN/figures/); a problem there is a warning only.
  if (figures) draw_run_figures(out, o.plots_dir);
  return 0;
}

}  // namespace codesign::run
