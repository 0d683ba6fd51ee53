#pragma once
// Readers for the mesh-related config tables (units in the key names):
//
//   [geometry]  length_mm, base_diameter_mm, tip_diameter_mm, proximal_cap_mm
//   [mesh]      max_size_mm, radius_factor, wall_factor, grading, optimise_threshold,
//               min_dihedral_deg, max_dihedral_deg, min_radius_ratio
//   [fibres]    count, pitch_mm, points_per_turn, radial_inset_mm   (layout part only)
//
// read_geometry / read_mesh_options read `root.table(...)` and call finish() on it.
// read_fibre_layout reads its keys from a [fibres] table it is given and does NOT call finish():
// the table is shared with the FEM's fibre stiffness key (see fem_config.hpp).
#include "fem/fibre_layout.hpp"
#include "fem/whisker_geometry.hpp"
#include "fem/whisker_mesh.hpp"
#include "io/toml_reader.hpp"

namespace codesign::io {

// The design of the returned geometry is the default (j21); every one of the 110 designs must
// fit the geometry read, otherwise InputError naming the table and the first design that fails.
fem::WhiskerGeometry read_geometry(TableReader& root);
fem::MeshOptions read_mesh_options(TableReader& root);
fem::FibreLayoutOptions read_fibre_layout(TableReader& fibres);

}  // namespace codesign::io
