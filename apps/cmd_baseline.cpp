// `codesign baseline pid --config run.toml --design J -o DIR [--p1 P] [--p2 P] [--threads N] [--force]`
//
// The classical baselines on one design (run/pid_baseline.hpp: the PIDs on force, strain and
// estimated force, and the best fixed base angle; DIR/baseline.toml and DIR/eval/).
#include <memory>
#include <string>

#include "cli_options.hpp"
#include "commands.hpp"
#include "run/pid_baseline.hpp"
#include "run/run_config.hpp"

namespace codesign::app {

namespace {

struct BaselineCliOptions {
  std::string config;
  run::PidBaselineOptions run;
};

}  // namespace

void add_baseline_command(CLI::App& root, Runner& run) {
  CLI::App* base = root.add_subcommand("baseline", "Classical baselines on one design");
  base->require_subcommand(1);
  auto opt = std::make_shared<BaselineCliOptions>();
  CLI::App* cmd = base->add_subcommand(
      "pid", "NLopt-tuned PID on the force (oracle), on the strain and on the force estimated from strain and "
      "base angle, and the best fixed theta, on one design");
  cmd->add_option("--config", opt->config, "run config (TOML; [pid], [sweep] fixed_theta_*)")->required();
  cmd->add_option("--design", opt->run.design, "design index 0..109 (default 21)");
  cmd->add_option("-o,--out", opt->run.out, "output directory")->required();
  cmd->add_option("--p1", opt->run.p1_kPa, "chamber 1 pressure, kPa (default 0)");
  cmd->add_option("--p2", opt->run.p2_kPa, "chamber 2 pressure, kPa (default 0; ignored for one chamber)");
  add_threads_option(*cmd, opt->run.threads);
  cmd->add_flag("--force", opt->run.force, "overwrite an earlier baseline.toml in the output directory");
  cmd->callback([opt, &run] {
    run = [opt] {
      run::run_pid_baseline(run::read_run_config(opt->config), opt->run);
      return 0;
    };
  });
}

}  // namespace codesign::app
