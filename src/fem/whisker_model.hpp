#pragma once
// One call from a design index to a simulation-ready Model: geometry → gmsh mesh → model
// (mass, stiffness, boundary sets, fibre springs).
#include <memory>

#include "fem/fibre_layout.hpp"
#include "fem/model.hpp"
#include "fem/whisker_geometry.hpp"
#include "fem/whisker_mesh.hpp"

namespace codesign::fem {

struct WhiskerModelSpec {
  WhiskerGeometry geometry{};  // its `design` is replaced by the design index given
  MeshOptions mesh{};
  ModelOptions model{};        // fibre_polylines / fibre_chains are replaced by the layout's
  FibreLayoutOptions fibres{}; // helical fibre springs around the chamber region (count 0: none)
};

// Throws std::out_of_range for a bad index and std::invalid_argument / std::runtime_error when
// the geometry cannot be meshed.
std::shared_ptr<const Model> build_whisker_model(int design_index, const WhiskerModelSpec& spec);

}  // namespace codesign::fem
