// `codesign survey --config run.toml -o DIR [--designs A-B] [--phases N] [--no-fixed-theta] [--threads N]`
//
// Measures, over the designs (all 110 by default), what the task's defaults rest on: the reference
// range of the strain ε and of the zeroed strain ε − ε₀, and the best fixed base angle θ0 with its
// return (core/design_survey.hpp says over which episodes). Writes DIR/survey.csv (one row per
// design) and prints the suggested [task] strain_min / strain_max and a summary (run/survey.hpp).
#include <memory>
#include <string>
#include <tuple>

#include "run/run_config.hpp"
#include "run/survey.hpp"
#include "cli_options.hpp"
#include "commands.hpp"

namespace codesign::app {

namespace {

struct SurveyCliOptions {
  std::string config;
  std::string out = "runs/survey";
  std::string designs = "0-109";
  int phases = 2;
  bool fixed_theta = true;
  int threads = 0;
  bool force = false;
};

int run_survey_command(const SurveyCliOptions& o) {
  const run::RunConfig setup = run::read_run_config(o.config);
  run::SurveyRunOptions so;
  std::tie(so.survey.first_design, so.survey.last_design) = parse_design_range(o.designs);
  so.survey.phases = o.phases;
  so.survey.fixed_theta = o.fixed_theta;
  so.out = o.out;
  so.threads = o.threads;
  so.force = o.force;
  run::run_survey(setup, so);
  return 0;
}

}  // namespace

void add_survey_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<SurveyCliOptions>();
  CLI::App* cmd = root.add_subcommand(
      "survey", "Measure the strain reference range and the best fixed-theta return of every design");
  cmd->add_option("--config", opt->config, "run config (TOML)")->required();
  cmd->add_option("-o,--out", opt->out, "output directory (default runs/survey)");
  add_designs_option(*cmd, opt->designs, "0-109");
  cmd->add_option("--phases", opt->phases, "plate phases per fixed-theta evaluation (default 2)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("!--no-fixed-theta", opt->fixed_theta, "skip the fixed-theta search");
  add_threads_option(*cmd, opt->threads);
  cmd->add_flag("--force", opt->force, "overwrite an earlier survey.csv in the output directory");
  cmd->callback([opt, &run] { run = [opt] { return run_survey_command(*opt); }; });
}

}  // namespace codesign::app
