// `codesign config-keys`
//
// Prints the config-keys reference (every table and key with type, default, allowed values, unit
// and meaning) as Markdown, from the same descriptions the readers and writers use:
// docs/config_keys.md is this output.
#include <cstdio>

#include "commands.hpp"
#include "run/config_reference.hpp"

namespace codesign::app {

void add_config_keys_command(CLI::App& root, Runner& run) {
  CLI::App* cmd = root.add_subcommand("config-keys", "Print every config key with its default and range (Markdown)");
  cmd->callback([&run] {
    run = [] {
      std::fputs(run::config_reference_markdown().c_str(), stdout);
      return 0;
    };
  });
}

}  // namespace codesign::app
