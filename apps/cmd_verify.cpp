// `codesign verify --run DIR [--phases N] [--phase-set test|validation] [--next K] [--no-baselines]
//   [--with RUN2 RUN3] [--plots DIR] [--force] [--threads N]`
//
// The final policy of a finished co-design run on d* and its neighbours, and two PIDs on d*, under
// held-out physics, into DIR/verify/ (run/verify_run.hpp, docs/verify.md).
#include <cstdint>
#include <cstdio>
#include <memory>

#include "base/duration_text.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "run/verify_run.hpp"

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

namespace codesign::app {

namespace {

struct VerifyCliOptions {
  int threads = 0;
  run::VerifyOptions run;
};

}  // namespace

void add_verify_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<VerifyCliOptions>();
  opt->run.plots_dir = CODESIGN_PLOTS_DIR;
  CLI::App* cmd = root.add_subcommand(
      "verify", "Test a finished run's final policy on d* and its neighbours, beside two PIDs, under held-out physics");
  cmd->add_option("--run", opt->run.dir, "a finished run folder (config.toml, result.toml, policy.bin)")->required();
  cmd->add_option("--phases", opt->run.phases, "plate phases (episodes) per subject and condition (default 100)")
      ->check(CLI::Range(2, 100000));
  cmd->add_option("--phase-set", opt->run.phase_set,
                  "test (2 pi (k + 1/2)/n, what results report) or validation (2 pi (k + 1/4)/n, to choose settings on)")
      ->check(CLI::IsMember({"test", "validation"}));
  cmd->add_option("--next", opt->run.next, "designs of the run's order tested after d* and the runner-up (default 2)")
      ->check(CLI::Range(0, 109));
  cmd->add_flag("--no-baselines", [opt](std::int64_t) { opt->run.baselines = false; },
                "skip the two PIDs on d* (the force oracle and the estimator PI)");
  cmd->add_option("--with", opt->run.with, "other finished runs (other seeds) whose d* this run's policy is tested on")
      ->expected(1, 16);
  cmd->add_option("--plots", opt->run.plots_dir, "folder of verify.gp (default: " CODESIGN_PLOTS_DIR ")");
  cmd->add_flag("--force", opt->run.force, "replace a verify of the run made with other settings");
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] {
    run = [opt] {
      run::VerifyOptions o = opt->run;
      o.threads = static_cast<std::size_t>(opt->threads);
      const run::VerifySummary s = run::verify_run(o);
      std::printf("verify: %d cells run now, %d before -> %s/report.md\n", s.cells_run, s.cells_before,
                  s.folder.c_str());
      if (s.episodes_run > 0)
        std::printf("verify: %s wall for %d episodes (%.2f s each, the PIDs' tuning included)\n",
                    duration_text(s.wall_s).c_str(), s.episodes_run, s.wall_s / s.episodes_run);
      if (!s.figure_message.empty()) std::printf("verify: no verify.png: %s\n", s.figure_message.c_str());
      return 0;
    };
  });
}

}  // namespace codesign::app
