#include "io/mesh_config.hpp"

#include <stdexcept>
#include <string>

namespace codesign::io {

fem::WhiskerGeometry read_geometry(TableReader& root) {
  TableReader t = root.table("geometry");
  fem::WhiskerGeometry g;
  g.length_mm = t.number("length_mm", g.length_mm, 10.0, 1000.0);
  g.base_diameter_mm = t.number("base_diameter_mm", g.base_diameter_mm, 1.0, 200.0);
  g.tip_diameter_mm = t.number("tip_diameter_mm", g.tip_diameter_mm, 0.5, 200.0);
  g.proximal_cap_mm = t.number("proximal_cap_mm", g.proximal_cap_mm, 0.0, 50.0);
  t.finish();
  for (int j = 0; j < fem::kDesignCount; ++j) {
    fem::WhiskerGeometry trial = g;
    trial.design = fem::design_from_index(j);
    try {
      fem::validate(trial);
    } catch (const std::invalid_argument& e) {
      // Not one key's fault: name the table and the keys involved.
      throw InputError(t.file() + ": [geometry] (length_mm, base_diameter_mm, tip_diameter_mm, proximal_cap_mm) " +
                       "cannot hold design " + std::to_string(j) + " of the design space: " + e.what());
    }
  }
  return g;
}

fem::MeshOptions read_mesh_options(TableReader& root) {
  TableReader t = root.table("mesh");
  fem::MeshOptions o;
  o.max_size_mm = t.number("max_size_mm", o.max_size_mm, 0.2, 50.0);
  o.radius_factor = t.number("radius_factor", o.radius_factor, 0.05, 2.0);
  o.wall_factor = t.number("wall_factor", o.wall_factor, 0.2, 5.0);
  o.grading = t.number("grading", o.grading, 0.0, 5.0);
  o.optimise_threshold = t.number("optimise_threshold", o.optimise_threshold, 0.0, 1.0);
  o.quality.min_dihedral_deg = t.number("min_dihedral_deg", o.quality.min_dihedral_deg, 0.0, 60.0);
  o.quality.max_dihedral_deg = t.number("max_dihedral_deg", o.quality.max_dihedral_deg, 90.0, 180.0);
  o.quality.min_radius_ratio = t.number("min_radius_ratio", o.quality.min_radius_ratio, 0.0, 1.0);
  t.finish();
  return o;
}

fem::FibreLayoutOptions read_fibre_layout(TableReader& fibres) {
  fem::FibreLayoutOptions o;
  o.count = static_cast<int>(fibres.integer("count", o.count, 0, 16));
  o.pitch_mm = fibres.number("pitch_mm", o.pitch_mm, 0.5, 100.0);
  o.points_per_turn = fibres.number("points_per_turn", o.points_per_turn, 3.0, 200.0);
  // Upper limit: below the thinnest wall of the design space (2 mm).
  o.radial_inset_mm = fibres.number("radial_inset_mm", o.radial_inset_mm, 0.05, 1.95);
  return o;
}

}  // namespace codesign::io
