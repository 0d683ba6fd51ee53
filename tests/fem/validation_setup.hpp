#pragma once
// Shared set-up of the FEM validation tests: the slender solid cylinder, tip tractions and the
// work-conjugate tip displacement.
#include <cmath>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "fem/mesh_ops.hpp"
#include "fem/model.hpp"
#include "fem/whisker_mesh.hpp"

namespace codesign::fem::validation {

// The validation beam: r = 2.5 mm, L = 75 mm (L/r = 30), the project material (E = 500 kPa,
// ν = 0.4), gravity off. The total mass only sets the density (used by the frequency tests).
inline constexpr double kBeamRadius = 2.5;
inline constexpr double kBeamLength = 75.0;

inline std::shared_ptr<const Model> cylinder_model(double size_mm, double radius = kBeamRadius,
                                                   double length = kBeamLength) {
  ModelOptions opt;
  opt.material.gravity_mm_s2 = 0.0;
  return build_model(mesh_cylinder(radius, length, size_mm), opt);
}

// Effective element size (V / N_tets)^(1/3) [mm]: what convergence orders are measured against.
inline double effective_size(const Model& m) {
  return std::cbrt(m.volume_mm3 / static_cast<double>(m.mesh.tets.size()));
}

inline double face_area(const Model& m, const Tri& f) {
  const auto& n = m.mesh.nodes;
  return 0.5 * (n[f[1]] - n[f[0]]).cross(n[f[2]] - n[f[0]]).norm();
}

// Uniform traction on the tip faces with resultant `force`, lumped consistently (a third of each
// face's share on each of its nodes). Dead load (fixed direction).
inline Eigen::VectorXd tip_traction(const Model& m, const Eigen::Vector3d& force) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * m.node_count());
  const double area = surface_area(m.mesh, m.mesh.tip_faces);
  for (const Tri& t : m.mesh.tip_faces)
    for (int k : t) f.segment<3>(3 * k) += force * (face_area(m, t) / area / 3.0);
  return f;
}

// Area-weighted mean displacement of the tip face: the displacement work-conjugate to a uniform
// tip traction (P · this = the work of the load), so P·δ is exactly twice the strain energy.
inline Eigen::Vector3d tip_displacement(const Model& m, const Eigen::VectorXd& x) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  double w = 0.0;
  for (const Tri& t : m.mesh.tip_faces) {
    const double a = face_area(m, t) / 3.0;
    for (int k : t) {
      u += a * (x.segment<3>(3 * k) - m.rest_positions.segment<3>(3 * k));
      w += a;
    }
  }
  return u / w;
}

}  // namespace codesign::fem::validation
