// `codesign evaluate --run DIR [--at final|t1|t2] [--designs A-B] [--phases N] [--force] [--plots DIR]
//                   [--threads N] [--pressures-of RUN]`
//
// The deterministic policy of one state of a co-design run tested on every design of a range,
// ranked, into DIR/evaluate/<at>/ (run/run_evaluation.hpp).
#include <memory>
#include <string>
#include <tuple>

#include "cli_options.hpp"
#include "commands.hpp"
#include "run/run_evaluation.hpp"

namespace codesign::app {

namespace {

#ifndef CODESIGN_PLOTS_DIR
#define CODESIGN_PLOTS_DIR "plots"
#endif

struct EvaluateCliOptions {
  std::string designs;
  int threads = 0;
  run::RunEvaluationOptions run;
};

}  // namespace

void add_evaluate_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<EvaluateCliOptions>();
  opt->run.plots_dir = CODESIGN_PLOTS_DIR;
  CLI::App* cmd = root.add_subcommand(
      "evaluate", "Test a run's policy (latest state, or at T1 / T2) on every design at its pressures, ranked");
  cmd->add_option("--run", opt->run.dir, "run folder (config.toml and its checkpoints)")->required();
  cmd->add_option("--at", opt->run.at, "which state: final (checkpoint.bin, default), t1 or t2 (the kept checkpoints)")
      ->check(CLI::IsMember({"final", "t1", "t2"}));
  add_designs_option(*cmd, opt->designs, "all 110");
  cmd->add_option("--phases", opt->run.phases, "plate phases (episodes) per design (default: the run's eval_episodes)")
      ->check(CLI::Range(2, 100000));
  cmd->add_flag("--force", opt->run.force, "replace an evaluation of this state made with other settings");
  cmd->add_option("--plots", opt->run.plots_dir, "folder of evaluate_ranking.gp (default: " CODESIGN_PLOTS_DIR ")");
  cmd->add_option("--pressures-of", opt->run.pressures_of,
                  "another run folder: test each design at the pressures that run's state at --at gives it "
                  "(one seed's policy on another seed's design answers)");
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] {
    run = [opt] {
      run::RunEvaluationOptions o = opt->run;
      if (!opt->designs.empty()) std::tie(o.first_design, o.last_design) = parse_design_range(opt->designs);
      o.threads = static_cast<std::size_t>(opt->threads);
      run::evaluate_run_folder(o);
      return 0;
    };
  });
}

}  // namespace codesign::app
