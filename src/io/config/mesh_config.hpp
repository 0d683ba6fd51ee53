#pragma once
// Readers for the mesh-related config tables (units in the key names):
//
//   [geometry]  length_mm, base_diameter_mm, tip_diameter_mm, proximal_cap_mm
//   [mesh]      max_size_mm, radius_factor, wall_factor, grading, optimise_threshold,
//               min_dihedral_deg, max_dihedral_deg, min_radius_ratio
//
// Both read `root.table(...)` and call finish() on it; the keys are described in
// fem/config_tables.hpp. [fibres] is read with the other simulator tables (fem_config.hpp).
#include "fem/whisker_geometry.hpp"
#include "fem/whisker_mesh.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::io {

// The design of the returned geometry is the default (j21); every one of the 110 designs must
// fit the geometry read, otherwise InputError naming the table and the first design that fails.
fem::WhiskerGeometry read_geometry(TableReader& root);
fem::MeshOptions read_mesh_options(TableReader& root);

}  // namespace codesign::io
