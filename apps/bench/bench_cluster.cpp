// `codesign bench cluster [--config configs/paper.toml] [--iterations N] [--warmup K]
//                         [--threads T] [--model-threads T] [--exchanges N]`
// alone, or under `mpirun -np N` (issue 20 §3, docs/cluster.md).
//
// Rank 0 runs K warm-up iterations of Algorithm 1 (they mesh the designs first sampled and build
// their simulators, a cost a long run pays once) and N timed ones with the run's rollout backend
// (threads alone, or the MPI ranks of this launch), and prints the measured wall time per
// iteration split into collection, PPO update, policy inference and distribution update; the
// collection CPU of one environment per iteration (settles and FEM steps) and the collection wall
// of one environment per round of the busiest rank's threads (the model's c, which also holds
// resets, observations, thread hand-offs and imbalance); with ≥ 2 ranks, the cost of one exchange
// of a step's shape between rank 0 and one rank (mean of --exchanges rounds). Then the scaling
// model (cluster/scaling_model.hpp) with these costs: seconds per iteration and the projected run
// time for 1 … ψ ranks of --model-threads threads, with the update on rank 0 (as built) and
// spread over the ranks (a bound: not built, messages free), beside the measured figure of this
// launch, and the goal (the paper run in ≤ 5 min on 16 ranks). Without MPI the exchange
// cost is not measured and the model's message term is 0 (said so).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "cli_options.hpp"
#include "cluster/mpi_env_pool.hpp"
#include "cluster/mpi_world.hpp"
#include "cluster/scaling_model.hpp"
#include "codesign/outer_loop.hpp"
#include "commands.hpp"
#include "run/rollout_backend.hpp"
#include "run/run_config.hpp"

namespace codesign::app {

namespace {

struct BenchClusterOptions {
  std::string config = "configs/paper.toml";
  int iterations = 3;
  int warmup = 3;
  int threads = 0;
  int model_threads = 0;
  int exchanges = 200;
};

int run_bench_cluster(const BenchClusterOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  const run::RunSettings s = run::run_settings(setup);
  const core::LoopConfig& lc = s.loop;
  if (run::serve_unless_rank_zero(s, static_cast<std::size_t>(o.threads))) return 0;
  const int ranks = cluster::world_size();
  auto sims = std::make_shared<core::SimulatorPool>(s.spec, s.scene, s.solver);
  std::unique_ptr<core::EnvPool> envs = run::make_rollout_pool(sims, lc, static_cast<std::size_t>(o.threads), ranks);
  core::EnvPool* pool = envs.get();
  const std::size_t threads =
      o.threads > 0 ? static_cast<std::size_t>(o.threads) : std::max(1u, std::thread::hardware_concurrency());
  core::OuterLoop loop(lc, std::move(envs));
  const int psi = lc.codesign.designs_per_update, n_steps = lc.ppo.n_steps;
  std::printf("bench cluster: %s: psi = %d environments x %d decisions; %d rank(s) x %zu thread(s)\n", o.config.c_str(),
              psi, n_steps, ranks, threads);
  for (int k = 0; k < o.warmup; ++k) loop.iterate();  // meshes the sampled designs, builds simulators, allocates
  const int built0 = sims->constructed();

  // One exchange of a step's shape with one rank: the actions of the largest slice of a 2-rank
  // split out, its step results back (rewards, flags, observations, terminal observations).
  double exchange = 0.0;
  if (ranks > 1) {
    const std::size_t slice = cluster::env_slice(static_cast<std::size_t>(psi), 0, 2).count;
    const std::size_t obs = pool->spec().observation.dim(), act = pool->spec().action.dim();
    exchange = cluster::time_exchanges(ranks, slice * act, slice * (5 + 2 * obs), o.exchanges);
  }

  const double settle0 = pool->settle_seconds(), step0 = pool->step_seconds();
  double collect = 0.0, update = 0.0, dist = 0.0, policy = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < o.iterations; ++k) {
    const core::IterationReport r = loop.iterate();
    collect += r.collect_s;
    update += r.update_s;
    dist += r.distribution_s;
    policy += r.policy_s;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double env_cpu = (pool->settle_seconds() - settle0 + pool->step_seconds() - step0) / o.iterations / psi;
  const double n = o.iterations;
  // The collection wall of one environment in one round of the busiest rank's threads: this
  // launch's collection less its policy inference and its messages, over its rounds.
  const double messages = (ranks - 1) * (n_steps + 1) * exchange;
  const double env_wall =
      std::max(0.0, collect / n - policy / n - messages) /
      static_cast<double>(cluster::collection_rounds(static_cast<std::size_t>(psi), ranks, static_cast<int>(threads)));
  std::printf("bench cluster: measured on %d rank(s): %.3f s per iteration: collection %.3f s (policy inference "
              "%.3f s of it), PPO update %.3f s, distribution %.4f s\n",
              ranks, wall / n, collect / n, policy / n, update / n, dist / n);
  std::printf("  collection of one environment per iteration: %.4f s CPU in settles and FEM steps, %.4f s wall per "
              "round of a rank's threads (the model's c)\n",
              env_cpu, env_wall);
  std::printf("  simulators built during the timed iterations on rank 0: %d (after %d warm-up iteration(s))\n",
              sims->constructed() - built0, o.warmup);
  if (ranks > 1)
    std::printf("  one exchange rank 0 <-> one rank (a step's shape, mean of %d rounds over %d ranks): %.1f us\n",
                o.exchanges, ranks - 1, 1e6 * exchange);
  else
    std::printf("  exchange cost not measured (one process; run under mpirun -np 2 for it): the model's message "
                "term is 0\n");

  cluster::ScalingCosts c;
  c.environments = static_cast<std::size_t>(psi);
  c.threads_per_rank = o.model_threads > 0 ? o.model_threads : static_cast<int>(threads);
  c.env_collect_s = env_wall;
  c.exchanges = n_steps + 1;
  c.exchange_s = exchange;
  c.update_s = update / n;
  // Policy inference runs on rank 0 while the ranks wait; it is part of the collection's wall.
  c.policy_s = policy / n;
  c.distribution_s = dist / n;
  const double iterations_total =
      static_cast<double>(lc.codesign.total_timesteps) / (static_cast<double>(psi) * n_steps);
  std::printf("bench cluster: model (docs/cluster.md): %d thread(s) per rank, %.0f iterations for %lld timesteps\n",
              c.threads_per_rank, iterations_total, static_cast<long long>(lc.codesign.total_timesteps));
  std::printf("  ranks | update on rank 0 (built): s per iteration, run, speed-up | update spread (bound): s per "
              "iteration, run\n");
  cluster::ScalingCosts spread = c;
  spread.update_spread = true;
  const double base = cluster::iteration_seconds(c, 1);
  for (int r : {1, 2, 4, 8, 16, 32, 64}) {
    if (r > psi) break;
    const double it = cluster::iteration_seconds(c, r), its = cluster::iteration_seconds(spread, r);
    std::printf("  %5d | %7.3f s %8.1f min %6.2fx | %7.3f s %8.1f min%s\n", r, it, iterations_total * it / 60.0,
                base / it, its, iterations_total * its / 60.0,
                r == ranks && c.threads_per_rank == static_cast<int>(threads) ? "   (this launch: measured above)" : "");
  }
  if (psi >= 16) {
    const double m16 = iterations_total * cluster::iteration_seconds(c, 16) / 60.0;
    const double s16 = iterations_total * cluster::iteration_seconds(spread, 16) / 60.0;
    std::printf("  goal (issue 20 §3): the run in <= 5 min on 16 ranks by the model: %.1f min with the update on rank 0: "
                "%s; %.1f min with it spread (not built): %s\n",
                m16, m16 <= 5.0 ? "met" : "NOT met", s16, s16 <= 5.0 ? "would be met" : "NOT met either");
  }
  std::printf("  serial part per iteration (update + policy + distribution): %.3f s: with the update on rank 0 the "
              "model's floor is %.1f min\n",
              c.update_s + c.policy_s + c.distribution_s,
              iterations_total * (c.update_s + c.policy_s + c.distribution_s + c.env_collect_s) / 60.0);
  return 0;
}

}  // namespace

void add_bench_cluster_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchClusterOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "cluster", "Algorithm 1 on this launch's MPI ranks: measured costs and the scaling model to 64 ranks");
  cmd->add_option("--config", opt->config, "run config (default configs/paper.toml)");
  cmd->add_option("--iterations", opt->iterations, "timed iterations (default 3)")->check(CLI::Range(1, 1000));
  cmd->add_option("--warmup", opt->warmup, "untimed iterations first (default 3)")->check(CLI::Range(1, 1000));
  add_threads_option(*cmd, opt->threads, "rollout threads per rank (0: all cores)");
  cmd->add_option("--model-threads", opt->model_threads, "threads per rank in the model (default: this launch's)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--exchanges", opt->exchanges, "rounds of the exchange timing (default 200)")->check(CLI::Range(1, 1000000));
  cmd->callback([opt, &run] { run = [opt] { return run_bench_cluster(*opt); }; });
}

}  // namespace codesign::app
