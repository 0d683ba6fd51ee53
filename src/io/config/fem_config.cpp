#include "io/config/fem_config.hpp"

#include <numbers>

#include "fem/design.hpp"
#include "fem/config_tables.hpp"
#include "io/config/mesh_config.hpp"
#include "io/config/table_keys.hpp"

namespace codesign::io {

fem::SolverConfig read_solver(TableReader& root) {
  fem::SolverConfig c;
  read_keys(root, "solver", [&](auto& v) { fem::describe_solver_table(v, c); });
  return c;
}

FemTables read_fem_tables(TableReader& root) {
  FemTables f;
  read_keys(root, "material", [&](auto& v) { fem::describe_material_table(v, f.spec.model.material); });
  read_keys(root, "scene", [&](auto& v) { fem::describe_scene_table(v, f.scene, f.spec.model); });
  f.solver = read_solver(root);
  f.spec.geometry = read_geometry(root);
  f.spec.mesh = read_mesh_options(root);
  read_keys(root, "fibres", [&](auto& v) { fem::describe_fibres_table(v, f.spec.fibres, f.spec.model); });
  return f;
}

fem::SimScenario read_sim_scenario(TableReader& root) {
  fem::SimScenario s;
  read_keys(root, "sim", [&](auto& v) { fem::describe_sim_table(v, s); });
  return s;
}

}  // namespace codesign::io
