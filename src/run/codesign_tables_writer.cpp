#include "run/codesign_tables_writer.hpp"

#include <sstream>

#include "core/outer_loop.hpp"
#include "core/config_tables.hpp"
#include "io/config/config_writer.hpp"
#include "io/config/table_keys.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

void write_task_table(std::ostream& out, const TaskConfig& task) {
  TaskConfig c = task;  // the descriptions take the fields by reference
  io::write_keys(out, "task", [&](auto& v) { describe_task_table(v, c); });
}

void write_faults_table(std::ostream& out, const TaskConfig& task) {
  TaskConfig c = task;
  io::write_keys(out, "faults",
                 [&](auto& v) { describe_faults_table(v, c.faults, c.episode_steps / c.action_hold_steps); });
}

void write_randomize_table(std::ostream& out, const TaskConfig& task) {
  TaskConfig c = task;
  io::write_keys(out, "randomize", [&](auto& v) { describe_randomize_table(v, c.randomize); });
}

void write_codesign_table(std::ostream& out, const CodesignConfig& codesign, const TaskConfig& task) {
  CodesignConfig c = codesign;
  io::write_keys(out, "codesign", [&](auto& v) { describe_codesign_table(v, c, task.pressure_max_kPa); });
}

std::string resolved_run_config(const fem::WhiskerModelSpec& spec, const fem::SceneConfig& scene,
                                const fem::SolverConfig& solver, const LoopConfig& loop) {
  std::ostringstream out;
  out << "# resolved by codesign: every key the run reads, with the value used\n\n";
  io::write_fem_tables(out, spec, scene, solver);
  write_task_table(out, loop.task);
  // Only a run that injects faults has the table: other runs keep their config text (and the
  // fingerprint of their checkpoints).
  if (loop.task.faults.enabled()) write_faults_table(out, loop.task);
  // The same for physical uncertainty: a run without it resolves to the text it always had.
  if (loop.task.randomize.enabled()) write_randomize_table(out, loop.task);
  write_codesign_table(out, loop.codesign, loop.task);
  io::write_ppo_table(out, loop.ppo);
  return out.str();
}

}  // namespace codesign::run
