#pragma once
// Readers for the simulator's config tables [material], [scene], [solver], [fibres] (their keys
// are described in fem/config_tables.hpp) and for [sim], the scenario of `codesign sim`:
//
//   [sim]       design, pressures_kPa, theta_deg, theta_hold_steps, steps, vtk_every
//
// Every reader takes the root, reads its table and calls finish() on it (unknown keys are
// errors). Defaults are the value types' defaults.
#include <vector>

#include "fem/material.hpp"
#include "fem/scene.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"
#include "fem/config_tables.hpp"
#include "fem/design.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::io {

fem::SolverConfig read_solver(TableReader& root);

// Every simulator table of a run config, as the run uses them: [material], [scene] (with
// tip_region_mm into spec.model), [solver], [geometry], [mesh] (mesh_config.hpp) and [fibres]
// (layout and stiffness; finished here). The inverse is io::write_fem_tables (config_writer.hpp).
struct FemTables {
  fem::WhiskerModelSpec spec;
  fem::SceneConfig scene;
  fem::SolverConfig solver;
};
FemTables read_fem_tables(TableReader& root);

// [sim], the open-loop scenario of `codesign sim` (fem/config_tables.hpp describes its keys).
fem::SimScenario read_sim_scenario(TableReader& root);

}  // namespace codesign::io
