#pragma once
// Every config table, with its keys as their descriptions state them (base/config_keys.hpp), and
// the config-keys reference page printed from them (docs/config_keys.md, `codesign config-keys`).
#include <string>
#include <vector>

#include "io/config/key_reference.hpp"

namespace codesign::run {

struct TableReference {
  std::string name;       // "material"
  std::string about;      // what the table sets
  std::string read_by;    // the sub-commands that read it
  bool resolved = false;  // part of a co-design run's resolved config.toml
  std::vector<io::KeyRow> rows;
  // Where a sub-command reads the table over other defaults ([ppo] of train-gym: SB3's), the
  // rows with those defaults, and what to call each set.
  std::vector<io::KeyRow> other_rows;
  std::string label, other_label;
};

// The tables in the order the page lists them.
std::vector<TableReference> config_tables();
// The Markdown page.
std::string config_reference_markdown();

}  // namespace codesign::run
