// `codesign bench waves`: a rank's share of a whole rollout run in waves against every
// environment at every decision (codesign/rollout_waves.hpp, run_ahead.hpp), on this machine.
//
// Algorithm 1 runs with the config's ψ environments cut into shares of --share environments, each
// on a pool of --threads threads, as MPI ranks of that many threads hold them (the busiest rank of
// ψ = 40 on 16 ranks holds 3). In each iteration every share runs its whole rollout twice from the
// same setups, once in waves and once decision by decision, the order alternating between shares
// and iterations (the machine's speed drifts); the two must agree bit for bit, and one of them
// goes on into the PPO update. The shares run one after another, so each has the cores to itself.
// Prints the wall of a share's rollout both ways, their ratio, and the forward passes per rollout.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "base/seconds_since.hpp"
#include "cli_options.hpp"
#include "codesign/env_pool.hpp"
#include "codesign/outer_loop.hpp"
#include "codesign/run_ahead.hpp"
#include "codesign/simulator_pool.hpp"
#include "commands.hpp"
#include "run/run.hpp"
#include "run/run_config.hpp"

namespace codesign::app {
namespace {

struct BenchWavesOptions {
  std::string config = "configs/paper.toml";
  int share = 3;
  int threads = 2;
  int warmup = 5;
  int iterations = 5;
};

bool same_share(const core::ShareRollout& a, const core::ShareRollout& b) {
  if (a.steps.size() != b.steps.size() || !(a.last_values == b.last_values)) return false;
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    const core::RolloutStepColumns &x = a.steps[k], &y = b.steps[k];
    if (!(x.obs == y.obs) || !(x.actions == y.actions) || !(x.values == y.values) || !(x.log_probs == y.log_probs) ||
        !(x.rewards == y.rewards) || !(x.raw_rewards == y.raw_rewards) || x.done != y.done ||
        x.in_band != y.in_band || x.reasons != y.reasons)
      return false;
  }
  return true;
}

// The ψ environments in shares, each run both ways; only whole rollouts (start() and step() are
// never called: the loop takes the RunAhead path for a feed-forward policy without observation
// statistics, which the command checks).
class TwoSchedulePool final : public core::EnvPool, public core::RunAhead {
 public:
  TwoSchedulePool(std::shared_ptr<core::SimulatorPool> sims, const core::TaskConfig& task, std::size_t envs,
                  std::size_t share, std::size_t threads)
      : n_(envs) {
    for (std::size_t first = 0; first < envs; first += share) {
      std::vector<std::size_t> places;
      for (std::size_t j = first; j < std::min(envs, first + share); ++j) places.push_back(j);
      pools_.push_back(std::make_unique<core::ThreadEnvPool>(sims, task, places.size(), threads));
      shares_.push_back(std::move(places));
    }
    caches_.resize(2 * shares_.size());
  }
  std::size_t size() const override { return n_; }
  const rl::EnvSpec& spec() const override { return pools_.front()->spec(); }
  Eigen::MatrixXd start(const std::vector<core::EpisodeSetup>&) override { throw std::logic_error("bench waves: start()"); }
  const rl::VecStepResult& step(const Eigen::MatrixXd&, bool) override { throw std::logic_error("bench waves: step()"); }
  int last_in_band(std::size_t) const override { throw std::logic_error("bench waves: last_in_band()"); }
  double settle_seconds() const override { return 0.0; }
  double step_seconds() const override { return 0.0; }
  double build_seconds() const override { return 0.0; }
  void set_step_observer(std::size_t, StepObserver, int) override {}
  std::vector<double> work_since_start() const override { return std::vector<double>(n_, 0.0); }
  rl::ThreadPool* thread_pool() override { return pools_.front()->thread_pool(); }
  core::RunAhead* run_ahead() override { return this; }

  core::ShareRollout rollout(const std::vector<core::EpisodeSetup>& setups, const rl::ActorCritic& model,
                             const std::vector<Eigen::MatrixXd>& normals, double gamma) override {
    core::ShareRollout all =
        core::empty_share(static_cast<int>(normals.size()), n_, spec().observation.dim(), spec().action.dim());
    for (std::size_t s = 0; s < shares_.size(); ++s) {
      std::vector<core::EpisodeSetup> mine;
      for (std::size_t p : shares_[s]) mine.push_back(setups[p]);
      const bool waves_first = (s + static_cast<std::size_t>(rollouts)) % 2 == 0;
      core::ShareRollout out[2];  // [0] waves, [1] every decision
      double wall[2] = {0.0, 0.0};
      for (int pass = 0; pass < 2; ++pass) {
        const int which = waves_first ? pass : 1 - pass;
        const auto t0 = std::chrono::steady_clock::now();
        out[which] = core::run_share(*pools_[s], mine, model, caches_[2 * s + static_cast<std::size_t>(which)],
                                     shares_[s], n_, normals, gamma,
                                     which == 0 ? core::ShareSchedule::Waves : core::ShareSchedule::EveryDecision);
        wall[which] = seconds_since(t0);
      }
      if (timing && shares_[s].size() == shares_.front().size()) {
        for (int which = 0; which < 2; ++which) {
          wall_s[which] += wall[which];
          passes[which] += out[which].passes;
        }
        ratios.push_back(wall[0] / wall[1]);
      }
      if (!same_share(out[0], out[1])) ++differing;
      core::place_share(out[0], shares_[s], all);
      all.policy_s += out[0].policy_s;
    }
    ++rollouts;
    return all;
  }
  std::size_t shares() const { return shares_.size(); }
  std::size_t full_shares() const {
    return static_cast<std::size_t>(std::count_if(shares_.begin(), shares_.end(),
                                                  [&](const auto& s) { return s.size() == shares_.front().size(); }));
  }

  bool timing = false;
  double wall_s[2] = {0.0, 0.0};   // timed rollouts of full shares: waves, every decision
  long passes[2] = {0, 0};         // their forward passes
  std::vector<double> ratios;      // per timed full share: the wall in waves over decision by decision
  int differing = 0;               // shares whose two rollouts differed (must stay 0)
  int rollouts = 0;

 private:
  std::size_t n_;
  std::vector<std::vector<std::size_t>> shares_;
  std::vector<std::unique_ptr<core::ThreadEnvPool>> pools_;
  std::vector<rl::ActorCritic::InferenceCache> caches_;
};

int run_bench_waves(const BenchWavesOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  const run::RunSettings s = run::run_settings(setup);
  const core::LoopConfig& lc = s.loop;
  if (!core::whole_rollouts_allowed(lc)) {
    std::fprintf(stderr, "codesign: error: %s: bench waves needs a feed-forward policy without observation statistics "
                         "(an MLP policy, ppo.normalize_observations = false): other rollouts go step by step\n",
                 o.config.c_str());
    return 2;
  }
  const auto psi = static_cast<std::size_t>(lc.codesign.designs_per_update);
  if (static_cast<std::size_t>(o.share) > psi) {
    std::fprintf(stderr, "codesign: error: --share %d: at most the config's %zu environments\n", o.share, psi);
    return 2;
  }
  auto sims = std::make_shared<core::SimulatorPool>(s.spec, s.scene, s.solver);
  auto owned = std::make_unique<TwoSchedulePool>(sims, lc.task, psi, static_cast<std::size_t>(o.share),
                                                 static_cast<std::size_t>(o.threads));
  TwoSchedulePool& pool = *owned;
  core::OuterLoop loop(lc, std::move(owned));
  std::printf("bench waves: %s: psi = %zu environments x %d decisions in %zu shares of <= %d on %d thread(s) each, "
              "each share's rollout run in waves and decision by decision\n",
              o.config.c_str(), psi, lc.ppo.n_steps, pool.shares(), o.share, o.threads);
  for (int k = 0; k < o.warmup; ++k) loop.iterate();
  pool.timing = true;
  for (int k = 0; k < o.iterations; ++k) loop.iterate();
  if (pool.rollouts != o.warmup + o.iterations) {
    std::fprintf(stderr, "codesign: error: bench waves: the loop did not run whole rollouts\n");
    return 1;
  }
  const double n = static_cast<double>(pool.ratios.size());
  double mean = 0.0, var = 0.0;
  for (double r : pool.ratios) mean += r / n;
  for (double r : pool.ratios) var += (r - mean) * (r - mean) / std::max(1.0, n - 1.0);
  std::printf("bench waves: %.0f timed rollouts of a share of %d each way (%d iterations x %zu full shares), after %d "
              "warm-up iteration(s)\n",
              n, o.share, o.iterations, pool.full_shares(), o.warmup);
  std::printf("  decision by decision: %.4f s per share's rollout, %.1f forward passes\n", pool.wall_s[1] / n,
              static_cast<double>(pool.passes[1]) / n);
  std::printf("  in waves:             %.4f s per share's rollout, %.1f forward passes\n", pool.wall_s[0] / n,
              static_cast<double>(pool.passes[0]) / n);
  std::printf("  waves / decision by decision: %.3f of the summed walls; per share %.3f +- %.3f (mean +- sd of %.0f "
              "pairs, each pair's rollouts back to back, standard error %.3f)\n",
              pool.wall_s[0] / pool.wall_s[1], mean, std::sqrt(var), n, std::sqrt(var / std::max(1.0, n)));
  std::printf("  rollouts that differed between the two schedules: %d of %d (must be 0)\n", pool.differing,
              pool.rollouts * static_cast<int>(pool.shares()));
  return pool.differing == 0 ? 0 : 1;
}

}  // namespace

void add_bench_waves_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchWavesOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "waves", "a rank's share of a whole rollout in waves against decision by decision, on this machine");
  cmd->add_option("--config", opt->config, "run config (default configs/paper.toml)");
  cmd->add_option("--share", opt->share, "environments per share, as on a rank (default 3)")->check(CLI::Range(1, 1024));
  add_threads_option(*cmd, opt->threads, "threads per share (default 2)");
  cmd->add_option("--warmup", opt->warmup, "untimed iterations first (default 5)")->check(CLI::Range(0, 1000));
  cmd->add_option("--iterations", opt->iterations, "timed iterations (default 5)")->check(CLI::Range(1, 1000));
  cmd->callback([opt, &run] { run = [opt] { return run_bench_waves(*opt); }; });
}

}  // namespace codesign::app
