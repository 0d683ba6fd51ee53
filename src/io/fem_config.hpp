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
#include "fem/design.hpp"
#include "io/toml_reader.hpp"

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

// The open-loop scenario of `codesign sim`.
struct SimScenario {
  int design = 21;                          // design index j, 0..109
  std::vector<double> pressures_kPa{0.0, 0.0};  // p1, p2 in [0, 20]; p2 ignored for n = 1
  // θ schedule: theta_deg[i] is the target of hold-interval i, reached by spreading the change
  // over its theta_hold_steps steps (like an action); the last value is then kept.
  std::vector<double> theta_deg{0.0};
  int theta_hold_steps = 5;
  int steps = 250;
  int vtk_every = 0;                        // 0: no VTK frames
};
template <class V>
void describe_sim_table(V& v, SimScenario& s) {
  v.integer({"design", "", "design index j"}, s.design, {0, fem::kDesignCount - 1});
  v.numbers({"pressures_kPa", "kPa", "chamber pressures [p1] or [p1, p2] (p2 ignored for one chamber)"},
            s.pressures_kPa, {0.0, 20.0}, {1, 2});
  if (s.pressures_kPa.size() == 1) s.pressures_kPa.push_back(0.0);
  v.numbers({"theta_deg", "deg", "base angle targets, one per hold interval; the last is kept"}, s.theta_deg,
            {-90.0, 90.0}, {1, 100000});
  v.integer({"theta_hold_steps", "", "steps over which each change of θ is spread"}, s.theta_hold_steps, {1, 100000});
  v.integer({"steps", "", "simulation steps"}, s.steps, {1, 10'000'000});
  v.integer({"vtk_every", "", "a VTK frame every this many steps (0: none)"}, s.vtk_every, {0, 10'000'000});
}
SimScenario read_sim_scenario(TableReader& root);

}  // namespace codesign::io
