// `codesign verify --run DIR [--phases N] [--phase-set test|validation] [--next K] [--no-baselines]
//   [--with RUN2 RUN3] [--conditions NAME...] [--specialists [--specialist-timesteps N] [--specialist-seeds S...]] [--plots DIR]
//   [--force] [--threads N]`
//
// The final policy of a finished co-design run on d* and its neighbours, and two PIDs on d*, under
// held-out physics, into DIR/verify/ (run/verify_run.hpp, docs/verify.md).
#include <cstdint>
#include <cstdio>
#include <memory>

#include "cli_options.hpp"
#include "commands.hpp"
#include "verify_job.hpp"

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

namespace codesign::app {

namespace {

struct VerifyCliOptions {
  int threads = 0;
  run::VerifyJobOptions job;
};

}  // namespace

void add_verify_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<VerifyCliOptions>();
  opt->job.verify.plots_dir = CODESIGN_PLOTS_DIR;
  CLI::App* cmd = root.add_subcommand(
      "verify", "Test a finished run's final policy on d* and its neighbours, beside two PIDs, under held-out physics");
  cmd->add_option("--run", opt->job.verify.dir, "a finished run folder (config.toml, result.toml, policy.bin)")->required();
  cmd->add_option("--phases", opt->job.verify.phases, "plate phases (episodes) per subject and condition (default 100)")
      ->check(CLI::Range(2, 100000));
  cmd->add_option("--phase-set", opt->job.verify.phase_set,
                  "test (2 pi (k + 1/2)/n, what results report) or validation (2 pi (k + 1/4)/n, to choose settings on)")
      ->check(CLI::IsMember({"test", "validation"}));
  cmd->add_option("--next", opt->job.verify.next, "designs of the run's order tested after d* and the runner-up (default 2)")
      ->check(CLI::Range(0, 109));
  cmd->add_flag("--no-baselines", [opt](std::int64_t) { opt->job.verify.baselines = false; },
                "skip the two PIDs on d* (the force oracle and the estimator PI)");
  cmd->add_option("--with", opt->job.verify.with, "other finished runs (other seeds) whose d* this run's policy is tested on")
      ->expected(1, 16);
  cmd->add_option("--conditions", opt->job.verify.conditions,
                  "run only these conditions of the suite (default: all), e.g. nominal modulus_-20% modulus_+20%")
      ->expected(1, 32);
  cmd->add_option("--plots", opt->job.verify.plots_dir, "folder of verify.gp (default: " CODESIGN_PLOTS_DIR ")");
  cmd->add_flag("--specialists", opt->job.specialists,
                "first train a fresh policy on each tested design of the run alone (RUN/verify/specialists/)");
  cmd->add_option("--specialist-timesteps", opt->job.specialist_timesteps,
                  "decisions of each specialist's training (default 100000)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100000000}));
  cmd->add_option("--specialist-seeds", opt->job.specialist_seeds, "seeds of the specialists (default 1)")
      ->expected(1, 16);
  cmd->add_flag("--force", opt->job.verify.force, "replace a verify of the run made with other settings");
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] {
    run = [opt] {
      run::VerifyJobOptions o = opt->job;
      o.verify.threads = static_cast<std::size_t>(opt->threads);
      return run::run_verify_job(o);
    };
  });
}

}  // namespace codesign::app
