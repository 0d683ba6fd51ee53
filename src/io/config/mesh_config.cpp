#include "io/config/mesh_config.hpp"

#include "fem/config_tables.hpp"
#include "io/config/table_keys.hpp"

#include <stdexcept>
#include <string>

namespace codesign::io {

fem::WhiskerGeometry read_geometry(TableReader& root) {
  fem::WhiskerGeometry g;
  read_keys(root, "geometry", [&](auto& v) { fem::describe_geometry_table(v, g); });
  for (int j = 0; j < fem::kDesignCount; ++j) {
    fem::WhiskerGeometry trial = g;
    trial.design = fem::design_from_index(j);
    try {
      fem::validate(trial);
    } catch (const std::invalid_argument& e) {
      // Not one key's fault: name the table and the keys involved.
      throw InputError(root.file() + ": [geometry] (length_mm, base_diameter_mm, tip_diameter_mm, proximal_cap_mm) " +
                       "cannot hold design " + std::to_string(j) + " of the design space: " + e.what());
    }
  }
  return g;
}

fem::MeshOptions read_mesh_options(TableReader& root) {
  fem::MeshOptions o;
  read_keys(root, "mesh", [&](auto& v) { fem::describe_mesh_table(v, o); });
  return o;
}
}  // namespace codesign::io
