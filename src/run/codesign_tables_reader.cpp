#include "run/codesign_tables_reader.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/config_tables.hpp"
#include "fem/design.hpp"
#include "io/config/table_keys.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

TaskConfig read_task_config(io::TableReader& root) {
  TaskConfig c;
  io::read_keys(root, "task", [&](auto& v) { describe_task_table(v, c); });
  const int decisions = c.episode_steps / c.action_hold_steps;
  io::read_keys(root, "faults", [&](auto& v) { describe_faults_table(v, c.faults, decisions); });
  io::read_keys(root, "randomize", [&](auto& v) { describe_randomize_table(v, c.randomize); });
  return c;
}

CodesignConfig read_codesign_config(io::TableReader& root, const TaskConfig& task) {
  CodesignConfig c;
  io::read_keys(root, "codesign", [&](auto& v) { describe_codesign_table(v, c, task.pressure_max_kPa); });
  return c;
}

PidTuningConfig read_pid_config(io::TableReader& root) {
  PidTuningConfig c;
  io::read_keys(root, "pid", [&](auto& v) { describe_pid_table(v, c); });
  c.validate();  // every field was range-checked above; this cannot fail
  return c;
}

SweepConfig read_sweep_config(io::TableReader& root, const TaskConfig& task) {
  SweepConfig c;
  io::read_keys(root, "sweep", [&](auto& v) { describe_sweep_table(v, c, task.pressure_max_kPa); });
  c.validate();
  return c;
}

}  // namespace codesign::run
