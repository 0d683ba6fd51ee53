#pragma once
// Reads the [task] and [codesign] tables of a run config.
#include "codesign/codesign_config.hpp"
#include "codesign/task_config.hpp"
#include "io/toml_reader.hpp"

namespace codesign::io {

codesign::TaskConfig read_task_config(TableReader& root);
codesign::CodesignConfig read_codesign_config(TableReader& root);

}  // namespace codesign::io
