#pragma once
// One call from a design index to a simulation-ready Model: geometry → gmsh mesh → model
// (mass, stiffness, boundary sets, fibre springs). Meshing is nearly all of it (`bench cluster`
// under mpirun prints both; measured: docs/journal/cluster.md, "Each design meshed once across
// the ranks"): whisker_model_from_mesh does the rest from a mesh made elsewhere (the MPI backend
// meshes each design once and sends the mesh to the other ranks).
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
// The same for a design given by its values, on the grid or off it (a cast wall thicker or thinner
// than drawn: core::PhysicsDraw::wall_offset_mm). Throws what meshing throws for a geometry that
// cannot be meshed.
std::shared_ptr<const Model> build_whisker_model(const Design& design, const WhiskerModelSpec& spec);

// The model of design `design_index` from its mesh: fibre layout and build_model, the steps
// build_whisker_model takes after meshing. Given the mesh that mesh_whisker makes for the design
// with `spec`, the model is build_whisker_model's, bit for bit. Throws std::out_of_range for a bad
// index and what layout_fibres and build_model throw.
std::shared_ptr<const Model> whisker_model_from_mesh(int design_index, TetMesh mesh, const WhiskerModelSpec& spec);

}  // namespace codesign::fem
