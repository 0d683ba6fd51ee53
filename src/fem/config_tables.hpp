#pragma once
// The simulator's config tables, each key described once (base/config_keys.hpp says how the
// readers, the writer, the checks and the reference page use these lists). Units are in the
// key names; the structs hold SI-like simulator units (mm, g, s, Pa, µN).
//
//   [material]  fem::Material
//   [scene]     fem::SceneConfig, and the contact-candidate region of the model options
//   [solver]    fem::SolverConfig
//   [geometry]  fem::WhiskerGeometry (not its design: a run chooses the design per episode)
//   [mesh]      fem::MeshOptions
//   [fibres]    fem::FibreLayoutOptions and the fibre springs of the model options
//   [sim]       fem::SimScenario, the open-loop scenario of `codesign sim`
#include <vector>

#include "base/config_keys.hpp"
#include "fem/design.hpp"
#include "fem/material.hpp"
#include "fem/scene.hpp"
#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"

namespace codesign::fem {

template <class V>
void describe_material_table(V& v, Material& m) {
  v.scaled({"youngs_modulus_kPa", "kPa", "Young's modulus E of the silicone (paper: 500)"}, m.youngs_modulus_Pa, 1e3,
           {1.0, 1e5});
  v.number({"poisson_ratio", "", "Poisson's ratio ν (paper: 0.4)"}, m.poisson_ratio, {0.0, 0.49});
  v.number({"total_mass_g", "g", "mass of the whole body; density = mass / meshed volume"}, m.total_mass_g,
           {1e-3, 1e4});
  v.number({"gravity_mm_s2", "mm/s²", "gravity along −z of the world frame"}, m.gravity_mm_s2, {0.0, 1e5});
  v.number({"rayleigh_mass_per_s", "1/s", "Rayleigh damping C = a M + b K: a"}, m.rayleigh_mass_per_s, {0.0, 1e3});
  v.number({"rayleigh_stiffness_s", "s", "Rayleigh damping C = a M + b K: b"}, m.rayleigh_stiffness_s, {0.0, 1.0});
}

template <class V>
void describe_scene_table(V& v, SceneConfig& c, ModelOptions& model) {
  v.number({"inclination_deg", "deg", "inclination α of the base towards the plate"}, c.inclination_deg, {0.0, 80.0});
  v.number({"preload_mm", "mm", "plate mean height above the height where it touches the straight whisker"},
           c.preload_mm, {0.0, 30.0});
  v.number({"plate_amplitude_mm", "mm", "amplitude U of the plate's sine"}, c.plate_amplitude_mm, {0.0, 20.0});
  v.number({"plate_frequency_Hz", "Hz", "frequency f of the plate's sine"}, c.plate_frequency_Hz, {0.0, 20.0});
  v.degrees({"plate_phase_deg", "deg", "phase of the plate's sine at t = 0"}, c.plate_phase_rad, {-360.0, 360.0});
  v.number({"theta_limit_deg", "deg", "|θ| beyond this marks the base angle as extreme"}, c.theta_limit_deg,
           {0.1, 90.0});
  v.integer({"settle_steps", "", "quasi-static load steps that raise the plate to its mean height"}, c.settle_steps,
            {1, 1000});
  v.number({"tip_region_mm", "mm", "contact candidates: surface nodes within this of the tip"}, model.tip_region_mm,
           {0.1, 50.0});
}

template <class V>
void describe_solver_table(V& v, SolverConfig& c) {
  v.choice({"method", "", "time step: \"fast\" (CG preconditioned by a stored factor) or \"exact\""}, c.method,
           kStepMethodNames);
  v.number({"dt_s", "s", "time step"}, c.dt_s, {1e-5, 0.1});
  v.number({"static_dt_s", "s", "pseudo time step of the static steps that settle the body"}, c.static_dt_s,
           {1e-3, 100.0});
  v.number({"fast_tolerance", "", "fast step: CG tolerance of the stopping rule fast_stop"}, c.fast_tolerance,
           {1e-12, 0.1});
  v.choice({.name = "fast_stop", .unit = "", .meaning = "fast step: CG stopping rule, \"relative\" or \"force\" (docs/physics.md)", .written = config::Written::UnlessDefault, .at_default = c.fast_stop == SolverConfig{}.fast_stop},
           c.fast_stop, kFastStopNames);
  v.integer({"fast_max_iterations", "", "fast step: CG iterations at most"}, c.fast_max_iterations, {1, 1000});
  v.integer({"fast_refactor_iterations", "", "fast step: refactorise after a step needing more CG iterations"},
            c.fast_refactor_iterations, {1, 1000});
  v.number({"contact_tolerance_mm", "mm", "fast step: penetration that makes a candidate an active contact"},
           c.contact_tolerance_mm, {1e-9, 0.1});
  v.number({"contact_margin_mm", "mm", "candidates closer than this to the plate enter the contact problem"},
           c.contact_margin_mm, {0.0, 10.0});
}

template <class V>
void describe_geometry_table(V& v, WhiskerGeometry& g) {
  v.number({"length_mm", "mm", "length of the cone"}, g.length_mm, {10.0, 1000.0});
  v.number({"base_diameter_mm", "mm", "outer diameter at the base"}, g.base_diameter_mm, {1.0, 200.0});
  v.number({"tip_diameter_mm", "mm", "outer diameter at the tip"}, g.tip_diameter_mm, {0.5, 200.0});
  v.number({"proximal_cap_mm", "mm", "proximal end-wall thickness (raised to the wall w if thinner)"},
           g.proximal_cap_mm, {0.0, 50.0});
}

template <class V>
void describe_mesh_table(V& v, MeshOptions& o) {
  v.number({"max_size_mm", "mm", "largest element size"}, o.max_size_mm, {0.2, 50.0});
  v.number({"radius_factor", "", "element size at most this × the local outer radius"}, o.radius_factor, {0.05, 2.0});
  v.number({"wall_factor", "", "element size at most this × the chamber wall thickness"}, o.wall_factor, {0.2, 5.0});
  v.number({"grading", "1/mm", "growth of the element size per mm away from the chamber region"}, o.grading,
           {0.0, 5.0});
  v.number({"optimise_threshold", "", "gmsh optimises every tet of lower quality (gamma)"}, o.optimise_threshold,
           {0.0, 1.0});
  v.number({"min_dihedral_deg", "deg", "quality limit: smallest dihedral angle"}, o.quality.min_dihedral_deg,
           {0.0, 60.0});
  v.number({"max_dihedral_deg", "deg", "quality limit: largest dihedral angle"}, o.quality.max_dihedral_deg,
           {90.0, 180.0});
  v.number({"min_radius_ratio", "", "quality limit: smallest radius ratio"}, o.quality.min_radius_ratio, {0.0, 1.0});
}

template <class V>
void describe_fibres_table(V& v, FibreLayoutOptions& f, ModelOptions& model) {
  v.integer({"count", "", "helical fibres around the chamber region (0: none)"}, f.count, {0, 16});
  v.number({"pitch_mm", "mm", "axial advance of a helix per turn"}, f.pitch_mm, {0.5, 100.0});
  v.number({"points_per_turn", "", "spring nodes per turn"}, f.points_per_turn, {3.0, 200.0});
  // Upper limit: below the thinnest wall of the design space (2 mm).
  v.number({"radial_inset_mm", "mm", "depth of the fibres below the outer surface"}, f.radial_inset_mm,
           {0.05, 1.95});
  v.scaled({"axial_stiffness_N", "N", "EA of one fibre, force per unit strain (0: no springs)"},
           model.fibre_axial_stiffness_uN, 1e6, {0.0, 1e4});
  v.boolean({"tension_only", "", "springs resist stretching only (false: both ways, as SOFA's chains)"},
            model.fibres_tension_only);
}

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

}  // namespace codesign::fem
