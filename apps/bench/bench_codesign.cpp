// `codesign bench codesign [--config configs/paper.toml] [--iterations N] [--threads N]`
//
// Times Algorithm 1 at the config's sizes (paper: ψ = 40 environments × 50 decisions of 5
// simulation steps, [512, 512, 512] networks, 10 epochs): one warm-up iteration (it meshes the
// sampled designs), then N timed iterations. Prints env steps/s (decisions and simulation
// steps), the wall time of an iteration split into rollout collection and PPO update, the CPU
// time of collection split into FEM stepping, settling and policy inference, and the wall time
// projected for the config's total_timesteps (iterations × mean iteration wall), against the
// 45-minute goal for the paper run.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "base/peak_memory.hpp"
#include "core/outer_loop.hpp"
#include "run/run_config.hpp"
#include "cli_options.hpp"
#include "commands.hpp"

namespace codesign::app {

namespace {

struct BenchCodesignOptions {
  std::string config = "configs/paper.toml";
  int iterations = 3;
  int threads = 0;
};

int run_bench_codesign(const BenchCodesignOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  core::LoopConfig lc{setup.task, setup.codesign, setup.ppo};
  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  auto envs = std::make_unique<core::ThreadEnvPool>(sims, lc.task, static_cast<std::size_t>(lc.codesign.designs_per_update),
                                                     static_cast<std::size_t>(o.threads), lc.ppo.privileged_critic);
  const std::size_t threads = envs->threads();
  core::EnvPool* pool = envs.get();
  core::OuterLoop loop(lc, std::move(envs));
  const int psi = lc.codesign.designs_per_update;
  const int n_steps = lc.ppo.n_steps;
  std::printf("bench codesign: %s: psi = %d environments x %d decisions x %d steps, actor %zu layers, %zu threads\n",
              o.config.c_str(), psi, n_steps, lc.task.action_hold_steps, lc.ppo.actor_hidden.size(), threads);
  const auto w0 = std::chrono::steady_clock::now();
  loop.iterate();  // warm-up: meshes the sampled designs, allocates
  std::printf("bench codesign: warm-up iteration %.2f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
  const double settle0 = pool->settle_seconds(), step0 = pool->step_seconds();
  double collect = 0.0, update = 0.0, dist = 0.0, policy = 0.0;
  std::int64_t decisions = 0;
  std::int64_t sim_steps = 0;
  std::int64_t episodes = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < o.iterations; ++k) {
    const core::IterationReport r = loop.iterate();
    collect += r.collect_s;
    update += r.update_s;
    dist += r.distribution_s;
    policy += r.policy_s;
    decisions += static_cast<std::int64_t>(psi) * n_steps;
    for (const core::EpisodeRecord& e : r.episodes) sim_steps += static_cast<std::int64_t>(e.decisions) * lc.task.action_hold_steps;
    episodes += static_cast<std::int64_t>(r.episodes.size());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double settle = pool->settle_seconds() - settle0, stepping = pool->step_seconds() - step0;
  const double per_iter = wall / o.iterations;
  const double iters_total = static_cast<double>(lc.codesign.total_timesteps) / (static_cast<double>(psi) * n_steps);
  const double projected = iters_total * per_iter;
  std::printf("bench codesign: %d iterations in %.2f s: %.2f s per iteration; peak resident memory %.0f MiB\n",
              o.iterations, wall, per_iter, peak_resident_mib());
  std::printf("  env decisions/s            %.0f   (simulation steps/s %.0f)\n", decisions / wall, sim_steps / wall);
  std::printf("  wall per iteration: collection %.3f s (%.0f %%), PPO update %.3f s (%.0f %%), distribution %.4f s\n",
              collect / o.iterations, 100.0 * collect / wall, update / o.iterations, 100.0 * update / wall,
              dist / o.iterations);
  std::printf("  collection CPU per iteration (summed over %zu threads): FEM stepping %.3f s, settling %.3f s; "
              "policy inference (main thread) %.3f s\n",
              threads, stepping / o.iterations, settle / o.iterations, policy / o.iterations);
  std::printf("  FEM step mean %.3f ms; %lld episodes (%.1f decisions each), settle or restore mean %.1f ms per episode\n",
              1e3 * stepping / std::max<std::int64_t>(1, sim_steps), static_cast<long long>(episodes),
              static_cast<double>(decisions) / std::max<std::int64_t>(1, episodes),
              1e3 * settle / static_cast<double>(std::max<std::int64_t>(1, episodes)));
  // The same iterations on idle cores: collection CPU shared by the threads, plus the serial
  // parts (policy inference and the PPO update, measured as wall time on the main thread).
  const double cpu_per_iter = (stepping + settle) / static_cast<double>(threads) / o.iterations +
                              (policy + update + dist) / o.iterations;
  std::printf("  projected wall time of %lld timesteps (%.0f iterations): %.1f min   (goal for the paper run: 45 min: %s)\n",
              static_cast<long long>(lc.codesign.total_timesteps), iters_total, projected / 60.0,
              projected <= 45.0 * 60.0 ? "met" : "NOT met");
  std::printf("  projected from CPU time (as on %zu idle cores): %.2f s per iteration, %.1f min   (goal 45 min: %s)\n",
              threads, cpu_per_iter, iters_total * cpu_per_iter / 60.0,
              iters_total * cpu_per_iter <= 45.0 * 60.0 ? "met" : "NOT met");
  std::printf("  (both projections repeat these iterations of a new policy, whose episodes last %.1f of %d decisions,\n"
              "   each beginning with a settle or restore; in a training run episodes grow to the full length, so\n"
              "   the run takes less than projected: time the run itself, docs/codesign.md \"Speed\")\n",
              static_cast<double>(decisions) / std::max<std::int64_t>(1, episodes),
              lc.task.episode_steps / std::max(1, lc.task.action_hold_steps));
  return 0;
}

}  // namespace

void add_bench_codesign_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchCodesignOptions>();
  CLI::App* cmd = bench.add_subcommand("codesign", "Algorithm 1 at paper sizes: env steps/s, time split, projected run time");
  cmd->add_option("--config", opt->config, "run config (default configs/paper.toml)");
  cmd->add_option("--iterations", opt->iterations, "timed iterations after one warm-up (default 3)")->check(CLI::Range(1, 1000));
  add_threads_option(*cmd, opt->threads, "rollout threads (0: all cores)");
  cmd->callback([opt, &run] { run = [opt] { return run_bench_codesign(*opt); }; });
}

}  // namespace codesign::app
