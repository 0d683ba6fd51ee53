#pragma once
// Fibres as chains of stiff springs between points embedded barycentrically in tetrahedra.
//
// A point p = Σ_a w_a x_{tet[a]} (w: barycentric weights, Σ w = 1) moves with its host tet.
// A spring between embedded points p and q has rest length ℓ0 = |p − q| at rest and stiffness k:
//   f = −k (ℓ − ℓ0) n on p (n = (p − q)/ℓ); bilateral by default (SOFA-like spring chain), or
// tension-only (nothing when slack) when the model says so (see system_matrix.hpp). The force
// on p is spread to the host nodes with weights w (and the opposite force on q's nodes).
#include <array>
#include <vector>

#include <Eigen/Core>

#include "fem/mesh.hpp"

namespace codesign::fem {

struct EmbeddedPoint {
  int tet = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();  // barycentric weights of the tet's nodes
};

struct FibreSpring {
  EmbeddedPoint a, b;
  double rest_length_mm = 0.0;
  double stiffness_uN_per_mm = 0.0;
};

// Where a point sits in the mesh: the tet whose smallest barycentric weight is largest (so a
// point on a shared face, or just outside the surface by round-off, still embeds). Returns
// tet = -1 if the point lies farther outside every tet than `tolerance_mm`.
EmbeddedPoint embed_point(const TetMesh& mesh, const Eigen::Vector3d& p, double tolerance_mm = 0.05);

// Springs along the polylines (each polyline is one fibre, consecutive points joined).
// Every spring gets k = axial_stiffness_uN / ℓ0, i.e. `axial_stiffness_uN` is the fibre's
// EA (force per unit strain). Throws std::invalid_argument when a point cannot be embedded.
std::vector<FibreSpring> make_fibre_springs(const TetMesh& mesh,
                                            const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                                            double axial_stiffness_uN);

// Position of an embedded point given all node positions (3N vector, node-major). Inline: the
// fibre loops of every force pass and stiffness product call it twice per spring.
inline Eigen::Vector3d embedded_position(const TetMesh& mesh, const EmbeddedPoint& p, const Eigen::VectorXd& x) {
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (int a = 0; a < 4; ++a) q += p.weights[a] * x.segment<3>(3 * mesh.tets[p.tet][a]);
  return q;
}

}  // namespace codesign::fem
