#pragma once
// Reads the [task] and [codesign] tables of a run config into the co-design value types.
#include "core/codesign_config.hpp"
#include "core/design_sweep.hpp"
#include "core/pid_tuning.hpp"
#include "core/task_config.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::run {

// [task], and [faults] into TaskConfig::faults.
core::TaskConfig read_task_config(io::TableReader& root);
// The [codesign] table; pressure ranges come from the task (read it first).
core::CodesignConfig read_codesign_config(io::TableReader& root, const core::TaskConfig& task);
// The [pid] table (PID gain bounds, start, search budget, tuning and test phases).
core::PidTuningConfig read_pid_config(io::TableReader& root);
// The [sweep] table (pressure grid, controllers, fixed-θ budget, design range).
core::SweepConfig read_sweep_config(io::TableReader& root, const core::TaskConfig& task);

}  // namespace codesign::run
