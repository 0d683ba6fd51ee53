#include "io/fem_config.hpp"

#include <numbers>

#include "fem/design.hpp"
#include "io/mesh_config.hpp"

namespace codesign::io {

fem::Material read_material(TableReader& root) {
  TableReader t = root.table("material");
  fem::Material m;
  m.youngs_modulus_Pa = 1e3 * t.number("youngs_modulus_kPa", 1e-3 * m.youngs_modulus_Pa, 1.0, 1e5);
  m.poisson_ratio = t.number("poisson_ratio", m.poisson_ratio, 0.0, 0.49);
  m.total_mass_g = t.number("total_mass_g", m.total_mass_g, 1e-3, 1e4);
  m.gravity_mm_s2 = t.number("gravity_mm_s2", m.gravity_mm_s2, 0.0, 1e5);
  m.rayleigh_mass_per_s = t.number("rayleigh_mass_per_s", m.rayleigh_mass_per_s, 0.0, 1e3);
  m.rayleigh_stiffness_s = t.number("rayleigh_stiffness_s", m.rayleigh_stiffness_s, 0.0, 1.0);
  t.finish();
  return m;
}

SceneSettings read_scene(TableReader& root) {
  TableReader t = root.table("scene");
  SceneSettings s;
  fem::SceneConfig& c = s.scene;
  namespace range = fem::scene_range;
  c.inclination_deg = t.number("inclination_deg", c.inclination_deg, range::inclination_deg);
  c.preload_mm = t.number("preload_mm", c.preload_mm, range::preload_mm);
  c.plate_amplitude_mm = t.number("plate_amplitude_mm", c.plate_amplitude_mm, range::plate_amplitude_mm);
  c.plate_frequency_Hz = t.number("plate_frequency_Hz", c.plate_frequency_Hz, range::plate_frequency_Hz);
  c.plate_phase_rad = t.number("plate_phase_deg", c.plate_phase_rad * 180.0 / std::numbers::pi,
                               range::plate_phase_deg) *
                      std::numbers::pi / 180.0;
  c.theta_limit_deg = t.number("theta_limit_deg", c.theta_limit_deg, range::theta_limit_deg);
  c.settle_steps = static_cast<int>(t.integer("settle_steps", c.settle_steps, range::settle_steps));
  s.tip_region_mm = t.number("tip_region_mm", s.tip_region_mm, 0.1, 50.0);
  t.finish();
  return s;
}

fem::SolverConfig read_solver(TableReader& root) {
  TableReader t = root.table("solver");
  fem::SolverConfig c;
  namespace range = fem::solver_range;
  c.method = t.choice("method", c.method, fem::kStepMethodNames);
  c.dt_s = t.number("dt_s", c.dt_s, range::dt_s);
  c.static_dt_s = t.number("static_dt_s", c.static_dt_s, range::static_dt_s);
  c.fast_tolerance = t.number("fast_tolerance", c.fast_tolerance, range::fast_tolerance);
  c.fast_stop = t.choice("fast_stop", c.fast_stop, fem::kFastStopNames);
  c.fast_max_iterations = static_cast<int>(
      t.integer("fast_max_iterations", c.fast_max_iterations, range::fast_max_iterations));
  c.fast_refactor_iterations =
      static_cast<int>(t.integer("fast_refactor_iterations", c.fast_refactor_iterations,
                                        range::fast_refactor_iterations));
  c.contact_tolerance_mm = t.number("contact_tolerance_mm", c.contact_tolerance_mm, range::contact_tolerance_mm);
  c.contact_margin_mm = t.number("contact_margin_mm", c.contact_margin_mm, range::contact_margin_mm);
  t.finish();
  return c;
}

FibreStiffness read_fibre_stiffness(TableReader& fibres) {
  FibreStiffness f;
  f.axial_stiffness_uN = 1e6 * fibres.number("axial_stiffness_N", 1e-6 * f.axial_stiffness_uN, 0.0, 1e4);
  f.tension_only = fibres.boolean("tension_only", f.tension_only);
  return f;
}

FemTables read_fem_tables(TableReader& root) {
  FemTables f;
  f.spec.model.material = read_material(root);
  const SceneSettings sc = read_scene(root);
  f.scene = sc.scene;
  f.spec.model.tip_region_mm = sc.tip_region_mm;
  f.solver = read_solver(root);
  f.spec.geometry = read_geometry(root);
  f.spec.mesh = read_mesh_options(root);
  TableReader fibres = root.table("fibres");
  const FibreStiffness fs = read_fibre_stiffness(fibres);
  f.spec.model.fibre_axial_stiffness_uN = fs.axial_stiffness_uN;
  f.spec.model.fibres_tension_only = fs.tension_only;
  f.spec.fibres = read_fibre_layout(fibres);
  fibres.finish();
  return f;
}

SimScenario read_sim_scenario(TableReader& root) {
  TableReader t = root.table("sim");
  SimScenario s;
  s.design = static_cast<int>(t.integer("design", s.design, 0, fem::kDesignCount - 1));
  s.pressures_kPa = t.numbers("pressures_kPa", s.pressures_kPa, 0.0, 20.0, 1, 2);
  if (s.pressures_kPa.size() == 1) s.pressures_kPa.push_back(0.0);
  s.theta_deg = t.numbers("theta_deg", s.theta_deg, -90.0, 90.0, 1, 100000);
  s.theta_hold_steps = static_cast<int>(t.integer("theta_hold_steps", s.theta_hold_steps, 1, 100000));
  s.steps = static_cast<int>(t.integer("steps", s.steps, 1, 10'000'000));
  s.vtk_every = static_cast<int>(t.integer("vtk_every", s.vtk_every, 0, 10'000'000));
  t.finish();
  return s;
}

}  // namespace codesign::io
