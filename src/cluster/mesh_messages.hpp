#pragma once
// The wire format of designs' meshes between MPI ranks (mpi_env_pool.hpp): a rank that meshed a
// design sends the mesh to rank 0, and rank 0 sends it to a rank that gets the design without
// having meshed it, which builds the model from it (core::SimulatorPool::adopt_mesh) instead of
// meshing: meshing is nearly all of a model's cost. One array of doubles: the number of meshes,
// then per mesh its design, its counts (nodes, tets, base faces, tip faces, chambers, each
// chamber's faces), the node coordinates and every index. Coordinates are copied bit for bit and
// the integers are exact as doubles. No MPI here (tests/cluster/mesh_messages_test.cpp).
#include <vector>

#include "fem/mesh.hpp"

namespace codesign::cluster {

struct DesignMesh {
  int design = -1;
  fem::TetMesh mesh;
};

// `meshes[k]` is the mesh of `designs[k]` (std::invalid_argument if the sizes differ or a mesh is null).
std::vector<double> pack_meshes(const std::vector<int>& designs, const std::vector<const fem::TetMesh*>& meshes);
// The inverse; std::invalid_argument for a message that ends early or goes on after its last
// mesh, a count or index that is not a non-negative integer, a design outside 0..109, or a tet or
// face naming a node the mesh does not have.
std::vector<DesignMesh> unpack_meshes(const std::vector<double>& v);

}  // namespace codesign::cluster
