#include "fem/pressure.hpp"

#include <Eigen/Dense>

namespace codesign::fem {

void add_pressure_forces(const TetMesh& mesh, const Eigen::VectorXd& x,
                         const std::vector<double>& pressures_Pa, Eigen::VectorXd& f) {
  const int nc = static_cast<int>(mesh.chamber_faces.size());
  for (int c = 0; c < nc && c < static_cast<int>(pressures_Pa.size()); ++c) {
    const double p = pressures_Pa[c];
    if (p == 0.0) continue;
    for (const Tri& t : mesh.chamber_faces[c]) {
      const Eigen::Vector3d x0 = x.segment<3>(3 * t[0]);
      const Eigen::Vector3d n2a = (x.segment<3>(3 * t[1]) - x0).cross(x.segment<3>(3 * t[2]) - x0);
      const Eigen::Vector3d fn = (-p / 6.0) * n2a;  // −p · (area·n) / 3 per node
      for (int a : t) f.segment<3>(3 * a) += fn;
    }
  }
}

}  // namespace codesign::fem
