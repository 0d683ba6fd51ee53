#pragma once
// Readers for the simulator's config tables (units in the key names):
//
//   [material]  youngs_modulus_kPa, poisson_ratio, total_mass_g, gravity_mm_s2,
//               rayleigh_mass_per_s, rayleigh_stiffness_s
//   [scene]     inclination_deg, preload_mm, plate_amplitude_mm, plate_frequency_Hz,
//               plate_phase_deg, theta_limit_deg, settle_steps, tip_region_mm
//   [solver]    method ("fast" | "exact"), dt_s, static_dt_s, fast_tolerance,
//               fast_stop ("relative" | "force"),
//               fast_max_iterations, fast_refactor_iterations, contact_tolerance_mm,
//               contact_margin_mm
//   [fibres]    axial_stiffness_N, tension_only (the layout keys belong to the mesh reader)
//   [sim]       design, pressures_kPa, theta_deg, theta_hold_steps, steps, vtk_every
//
// Every reader takes the root, reads its table and calls finish() on it (unknown keys are
// errors) — except read_fibre_stiffness, which reads its key from a table shared with the
// fibre layout and leaves finish() to the caller. Defaults are the value types' defaults.
#include <vector>

#include "fem/material.hpp"
#include "fem/scene.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"
#include "io/toml_reader.hpp"

namespace codesign::io {

fem::Material read_material(TableReader& root);
// The scene table also carries the contact-candidate region (a model option): tip_region_mm.
struct SceneSettings {
  fem::SceneConfig scene{};
  double tip_region_mm = 6.0;
};
SceneSettings read_scene(TableReader& root);
fem::SolverConfig read_solver(TableReader& root);
// The FEM part of [fibres]: axial_stiffness_N = EA of one fibre (default 50 N, range 0..1e4 N;
// 0 disables the springs), tension_only (default false: bilateral springs, as SOFA's chains).
struct FibreStiffness {
  double axial_stiffness_uN = 5.0e7;
  bool tension_only = false;
};
FibreStiffness read_fibre_stiffness(TableReader& fibres);

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
SimScenario read_sim_scenario(TableReader& root);

}  // namespace codesign::io
