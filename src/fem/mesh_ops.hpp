#pragma once
// Free functions on TetMesh: volumes, boundary extraction, orientation, renumbering, and fast
// point location with barycentric coordinates.
#include <vector>

#include <Eigen/Core>

#include "fem/mesh.hpp"

namespace codesign::fem {

// Signed volume det[b-a, c-a, d-a] / 6 (positive for the orientation of mesh.hpp).
double signed_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     const Eigen::Vector3d& d);
double tet_volume(const TetMesh& m, int t);  // signed
double total_volume(const TetMesh& m);

// Every face that belongs to exactly one tet, oriented with its normal out of the solid
// ((b-a)×(c-a) points away from the tet's fourth node). Deterministic order (by tet, then face).
std::vector<Tri> boundary_faces(const TetMesh& m);
// Faces shared by more than two tets (a non-manifold mesh); empty for a valid mesh.
int count_overshared_faces(const TetMesh& m);

// Sorted, unique node indices used by a face list.
std::vector<int> face_nodes(const std::vector<Tri>& faces);
// Sum of face areas, and the area-weighted outward normal sum (zero for a closed surface).
double surface_area(const TetMesh& m, const std::vector<Tri>& faces);
Eigen::Vector3d vector_area(const TetMesh& m, const std::vector<Tri>& faces);
// Edges used by exactly one face of the list (empty ⇔ the face set is closed/watertight),
// and edges used by more than two faces.
int count_open_edges(const std::vector<Tri>& faces);
int count_overshared_edges(const std::vector<Tri>& faces);
// Connected components of the tets (two tets connected when they share a face).
int count_tet_components(const TetMesh& m);

// Swaps two nodes of every tet with negative signed volume. Returns how many were flipped.
int orient_tets_positive(TetMesh& m);
// Re-orients every tagged face (base, tip, chambers) to agree with boundary_faces(); throws
// std::invalid_argument naming the tag if a tagged face is not a boundary face of the tets.
void orient_tagged_faces(TetMesh& m);
// Drops nodes no tet uses and renumbers the rest in their original order (tags follow).
// Throws std::invalid_argument if a tagged face refers to a node no tet uses.
void compact_nodes(TetMesh& m);

// Barycentric coordinates of p in tet t (sum to 1; all ≥ 0 inside).
Eigen::Vector4d barycentric(const TetMesh& m, int t, const Eigen::Vector3d& p);

// Point location: a uniform grid of cells over the mesh bounding box, each cell listing the tets
// whose bounding box overlaps it. About `tets_per_cell` tets per cell on average.
class TetLocator {
 public:
  explicit TetLocator(const TetMesh& m, double tets_per_cell = 2.0);
  // The tet containing p (all barycentric weights ≥ -tol), or -1 if none. When several tets
  // qualify (p on a shared face) the one with the largest minimum weight wins; ties → lowest id.
  int locate(const Eigen::Vector3d& p, double tol = 1e-9) const;

 private:
  const TetMesh* mesh_;
  Eigen::Vector3d lo_, cell_;
  Eigen::Vector3i dims_;
  std::vector<int> start_;  // CSR offsets per cell
  std::vector<int> items_;
  Eigen::Vector3i cell_of(const Eigen::Vector3d& p) const;
};

}  // namespace codesign::fem
