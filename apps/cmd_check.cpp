// `codesign check FILE [--config run.toml]`
//
// Validates a mesh, policy file or checkpoint a user brings and prints what it holds
// (run/file_check.hpp); with --config, whether it fits that run config. Writes nothing; any
// defect is one message naming the file and the field, exit status 2.
#include <memory>
#include <string>

#include "commands.hpp"
#include "run/file_check.hpp"

namespace codesign::app {

namespace {

struct CheckOptions {
  std::string file;
  std::string config;
};

}  // namespace

void add_check_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<CheckOptions>();
  CLI::App* cmd = root.add_subcommand(
      "check", "Validate a mesh (.msh 4.1), policy file or checkpoint and print what it holds; writes nothing");
  cmd->add_option("file", opt->file, "the file to check")->required();
  cmd->add_option("--config", opt->config,
                  "run config the file must fit (policy: network and observation sizes; checkpoint: required)");
  cmd->callback([opt, &run] {
    run = [opt] {
      run::check_file(opt->file, opt->config);
      return 0;
    };
  });
}

}  // namespace codesign::app
