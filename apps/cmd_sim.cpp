// `codesign sim --config run.toml [-o DIR] [--vtk-every N] [--force]`
//
// Runs the open-loop scenario of [sim] and records it (run/sim_run.hpp: DIR/trace.csv and VTK
// frames). A numerical failure ends the scenario early; the exit code is then 3. Existing results
// in DIR are kept unless --force.
#include <memory>
#include <string>

#include "commands.hpp"
#include "run/run_config.hpp"
#include "run/sim_run.hpp"

namespace codesign::app {

namespace {

struct SimCliOptions {
  std::string config;
  run::SimRunOptions run;
};

}  // namespace

void add_sim_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<SimCliOptions>();
  CLI::App* cmd = root.add_subcommand("sim", "Run an open-loop simulation scenario and write a CSV trace");
  cmd->add_option("--config", opt->config, "run config (TOML); tables [material] [scene] [solver] [fibres] [sim]")
      ->required();
  cmd->add_option("-o,--out", opt->run.out, "output directory (default runs/sim)");
  cmd->add_option("--vtk-every", opt->run.vtk_every,
                  "write a VTK frame every N steps (0: none; default [sim].vtk_every)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--force", opt->run.force, "overwrite the results of an earlier run in the output directory");
  cmd->callback([opt, &run] { run = [opt] { return run::run_sim(run::read_run_config(opt->config), opt->run); }; });
}

}  // namespace codesign::app
