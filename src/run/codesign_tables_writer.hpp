#pragma once
// Writing the co-design tables back as TOML (the inverse of codesign_tables_reader.hpp), and the whole
// resolved config of a run: every table and key the run reads, with the value it uses.
#include <ostream>
#include <string>

#include "core/codesign_config.hpp"
#include "core/task_config.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"

namespace codesign::core {
struct LoopConfig;  // outer_loop.hpp
}

namespace codesign::run {

// [task] (observation as its name).
void write_task_table(std::ostream& out, const core::TaskConfig& task);
// [faults] of task (resolved_run_config writes it only when a fault is enabled).
void write_faults_table(std::ostream& out, const core::TaskConfig& task);
// [randomize] of task (written only when physical uncertainty is on).
void write_randomize_table(std::ostream& out, const core::TaskConfig& task);
// [codesign] (baseline as "none" / "single_design", plate_phase_deg in degrees); task for the
// ranges that depend on it.
void write_codesign_table(std::ostream& out, const core::CodesignConfig& codesign, const core::TaskConfig& task);

// The resolved config of a co-design run: a header comment, then [material], [scene],
// [solver], [geometry], [mesh], [fibres] (io::write_fem_tables), [task], [faults] (if enabled), [codesign] and [ppo]
// (io::write_ppo_table). No [sim]: the run does not read it. Reading the text back (the readers
// of io/config/fem_config.hpp, io/config/mesh_config.hpp, codesign_tables_reader.hpp and read_ppo_config over
// rl::paper_ppo_config()) gives the same values, so resolving that again gives the same text.
std::string resolved_run_config(const fem::WhiskerModelSpec& spec, const fem::SceneConfig& scene,
                                const fem::SolverConfig& solver, const core::LoopConfig& loop);

}  // namespace codesign::run
