#include "io/config/config_writer.hpp"

#include "fem/config_tables.hpp"
#include "io/config/table_keys.hpp"

namespace codesign::io {

void write_fem_tables(std::ostream& out, const fem::WhiskerModelSpec& spec, const fem::SceneConfig& scene,
                      const fem::SolverConfig& solver) {
  fem::WhiskerModelSpec sp = spec;  // the descriptions take the fields by reference
  fem::SceneConfig sc = scene;
  fem::SolverConfig so = solver;
  write_keys(out, "material", [&](auto& v) { fem::describe_material_table(v, sp.model.material); });
  write_keys(out, "scene", [&](auto& v) { fem::describe_scene_table(v, sc, sp.model); });
  write_keys(out, "solver", [&](auto& v) { fem::describe_solver_table(v, so); });
  write_keys(out, "geometry", [&](auto& v) { fem::describe_geometry_table(v, sp.geometry); });
  write_keys(out, "mesh", [&](auto& v) { fem::describe_mesh_table(v, sp.mesh); });
  write_keys(out, "fibres", [&](auto& v) { fem::describe_fibres_table(v, sp.fibres, sp.model); });
}

void write_ppo_table(std::ostream& out, const rl::PpoConfig& ppo) {
  rl::PpoConfig c = ppo;  // the description takes the fields by reference
  write_keys(out, "ppo", [&](auto& v) { rl::describe_ppo_table(v, c); });
}

}  // namespace codesign::io
