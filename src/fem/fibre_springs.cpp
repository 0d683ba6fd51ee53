#include "fem/fibre_springs.hpp"

#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

namespace codesign::fem {

EmbeddedPoint embed_point(const TetMesh& mesh, const Eigen::Vector3d& p, double tolerance_mm) {
  EmbeddedPoint best;
  double best_min = -std::numeric_limits<double>::infinity();
  double best_dist = std::numeric_limits<double>::infinity();
  for (int t = 0; t < static_cast<int>(mesh.tets.size()); ++t) {
    const Tet& tet = mesh.tets[t];
    const Eigen::Vector3d& x0 = mesh.nodes[tet[0]];
    Eigen::Matrix3d d;
    d << mesh.nodes[tet[1]] - x0, mesh.nodes[tet[2]] - x0, mesh.nodes[tet[3]] - x0;
    // Cheap reject: bounding sphere around x0.
    const double reach = std::max({d.col(0).norm(), d.col(1).norm(), d.col(2).norm()}) + tolerance_mm;
    if ((p - x0).norm() > reach) continue;
    const Eigen::Vector3d w123 = d.partialPivLu().solve(p - x0);
    Eigen::Vector4d w(1.0 - w123.sum(), w123[0], w123[1], w123[2]);
    const double wmin = w.minCoeff();
    if (wmin > best_min) {
      best_min = wmin;
      best.tet = t;
      best.weights = w;
      // Distance outside: clamp the weights and measure the gap.
      Eigen::Vector4d c = w.cwiseMax(0.0);
      c /= c.sum();
      Eigen::Vector3d q = Eigen::Vector3d::Zero();
      for (int a = 0; a < 4; ++a) q += c[a] * mesh.nodes[tet[a]];
      best_dist = wmin >= 0.0 ? 0.0 : (q - p).norm();
    }
  }
  if (best.tet < 0 || best_dist > tolerance_mm) return EmbeddedPoint{};
  return best;
}

std::vector<FibreSpring> make_fibre_springs(const TetMesh& mesh,
                                            const std::vector<std::vector<Eigen::Vector3d>>& polylines,
                                            double axial_stiffness_uN) {
  std::vector<FibreSpring> springs;
  for (std::size_t f = 0; f < polylines.size(); ++f) {
    const auto& line = polylines[f];
    std::vector<EmbeddedPoint> pts;
    for (std::size_t i = 0; i < line.size(); ++i) {
      EmbeddedPoint e = embed_point(mesh, line[i]);
      if (e.tet < 0)
        throw std::invalid_argument("fibre " + std::to_string(f) + " point " + std::to_string(i) +
                                    " lies outside the mesh");
      pts.push_back(e);
    }
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      const double len = (line[i + 1] - line[i]).norm();
      if (!(len > 1e-9)) continue;
      springs.push_back({pts[i], pts[i + 1], len, axial_stiffness_uN / len});
    }
  }
  return springs;
}

}  // namespace codesign::fem
