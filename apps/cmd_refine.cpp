// `codesign refine --run DIR [--phases N] [--starts N] [--max-evals N] [--method M] [--threads N]`
//
// Polishes p* of a finished co-design run and appends a [refined] table to its result.toml
// (run/refine_run.hpp).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cli_options.hpp"
#include "core/nlopt_search.hpp"
#include "commands.hpp"
#include "run/refine_run.hpp"

namespace codesign::app {

namespace {

std::vector<std::string> method_names() {
  std::vector<std::string> out;
  for (const std::string_view n : names_in(core::kLocalMethodNames)) out.emplace_back(n);
  return out;
}

}  // namespace

void add_refine_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<run::RefineRunOptions>();
  CLI::App* cmd = root.add_subcommand("refine", "Polish p* of a finished co-design run with NLopt (policy, j* fixed)");
  cmd->add_option("--run", opt->run, "run folder (config.toml, policy.bin, result.toml)")->required();
  cmd->add_option("--phases", opt->phases, "tuning plate phases per evaluation (default 4)")->check(CLI::Range(1, 1000));
  cmd->add_option("--starts", opt->starts, "NLopt starts (default 2)")->check(CLI::Range(1, 100));
  cmd->add_option("--max-evals", opt->max_evals, "evaluations over all starts (default 20)")
      ->check(CLI::Range(1, 10000));
  cmd->add_option("--method", opt->method, "bobyqa (default), cobyla, neldermead or sbplx")
      ->check(CLI::IsMember(method_names()));
  add_threads_option(*cmd, opt->threads);
  cmd->callback([opt, &run] {
    run = [opt] {
      run::refine_run(*opt);
      return 0;
    };
  });
}

}  // namespace codesign::app
