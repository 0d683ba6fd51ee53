// Rigid motions of the rest configuration produce no elastic force (co-rotational invariance),
// and the consistent tangent of the static solver matches finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "analytic.hpp"
#include "fem/corotational_tet.hpp"
#include "fem/static_solve.hpp"
#include "validation_setup.hpp"

namespace {

using namespace codesign::fem;
using namespace codesign::fem::validation;

// Force scale: the nodal forces of a 1 % strain, 0.01 E V ‖∇N‖ per element (summed in norm).
double unit_strain_force_scale(const Model& m) {
  double s2 = 0.0;
  for (const TetRest& r : m.rest) s2 += std::pow(0.01 * m.material.youngs_modulus_Pa * r.volume * r.grad.norm(), 2);
  return std::sqrt(s2);
}

// The element as the stepper uses it: polar rotation by F's quaternion iteration, cold-started
// from the identity (the worst case; the stepper warm-starts from the previous step).
Eigen::VectorXd element_forces_cold(const Model& m, const Eigen::VectorXd& x, double* energy) {
  const double mu = m.material.lame_mu(), lambda = m.material.lame_lambda();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  *energy = 0.0;
  for (std::size_t e = 0; e < m.mesh.tets.size(); ++e) {
    const Tet& t = m.mesh.tets[e];
    const std::array<Eigen::Vector3d, 4> xe{x.segment<3>(3 * t[0]), x.segment<3>(3 * t[1]), x.segment<3>(3 * t[2]),
                                            x.segment<3>(3 * t[3])};
    const Eigen::Matrix3d F = deformation_gradient(m.rest[e], xe);
    const Eigen::Matrix3d R = polar_rotation(F, Eigen::Matrix3d::Identity());
    const Vec12 fe = corotated_force(m.rest[e], F, R, mu, lambda);
    *energy += corotated_energy(m.rest[e], F, R, mu, lambda);
    for (int a = 0; a < 4; ++a) f.segment<3>(3 * t[a]) += fe.segment<3>(3 * a);
  }
  return f;
}

// Tolerance: the quaternion iteration stops when its update angle is < 1e-13 rad, so the
// left-over rotation error is ≲ 1e-13 and the spurious strain is of that size; with round-off
// (1e-16 × |x| / h ≈ 1e-14 at |x| ≈ 100 mm, h ≈ 2 mm) the spurious force is ≲ 1e-13 of the 100 %-
// strain scale, i.e. ≲ 1e-11 of the 1 %-strain scale. Bound: 1e-9 (100× margin). Energy: the
// spurious strain squared, ≲ 1e-24 of E V: bound 1e-18 of the 1 %-strain energy.
TEST(ValidationRigidMotion, LargeRotationAndTranslationGiveNoElasticForce) {
  const auto m = cylinder_model(2.0);
  const double scale = unit_strain_force_scale(*m);
  const double energy_scale = 0.5 * m->material.youngs_modulus_Pa * 1e-4 * m->volume_mm3;
  const Eigen::Vector3d shift(12.0, -40.0, 7.5);
  struct Case {
    double angle_deg;
    Eigen::Vector3d axis;
  };
  for (const Case& c : {Case{90.0, Eigen::Vector3d::UnitY()}, Case{90.0, Eigen::Vector3d::UnitZ()},
                        Case{179.0, Eigen::Vector3d(1.0, 2.0, -0.5)}, Case{37.0, Eigen::Vector3d(-0.3, 0.2, 1.0)}}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(c.angle_deg * kPi / 180.0, c.axis.normalized()).toRotationMatrix();
    Eigen::VectorXd x(m->rest_positions.size());
    for (int i = 0; i < m->node_count(); ++i) x.segment<3>(3 * i) = R * m->rest_positions.segment<3>(3 * i) + shift;
    double energy = 0.0;
    const Eigen::VectorXd f = element_forces_cold(*m, x, &energy);
    const Eigen::VectorXd f_svd = elastic_forces(*m, x);
    std::printf("[rigid] %.0f deg: |f|/scale = %.2e (quaternion polar), %.2e (SVD polar), W/W_scale = %.2e\n",
                c.angle_deg, f.norm() / scale, f_svd.norm() / scale, energy / energy_scale);
    EXPECT_LT(f.norm(), 1e-9 * scale);
    EXPECT_LT(f_svd.norm(), 1e-9 * scale);
    EXPECT_LT(std::abs(energy), 1e-18 * energy_scale);
    // Sanity of the scale: a 1 % stretch of the same configuration gives forces O(scale).
    const Eigen::VectorXd f_stretched = elastic_forces(*m, 1.01 * x);
    EXPECT_GT(f_stretched.norm(), 1e-3 * scale);
  }
}

// The consistent tangent is the exact Hessian of the co-rotated energy: central differences of
// the forces along a random direction at a strained, rotated state agree to O(ε²) truncation
// (ε = 1e-6 mm) + round-off/ε; bound 1e-6 relative. The SOFA-style R K0 Rᵀ differs by O(strain).
TEST(ValidationRigidMotion, ConsistentTangentMatchesFiniteDifferences) {
  const auto m = cylinder_model(3.0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  Eigen::VectorXd x(m->rest_positions.size());
  for (int i = 0; i < m->node_count(); ++i) {
    const Eigen::Vector3d X = m->rest_positions.segment<3>(3 * i);
    // Bend and stretch a little (strain ~ 1e-2), then rotate.
    const Eigen::Vector3d d(0.01 * X.x(), 0.0, 2e-4 * X.x() * X.x());
    x.segment<3>(3 * i) = R * (X + d);
  }
  Eigen::VectorXd v(x.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = std::sin(1.7 * static_cast<double>(i) + 0.3);
  const double eps = 1e-6;
  const Eigen::VectorXd df = (elastic_forces(*m, x + eps * v) - elastic_forces(*m, x - eps * v)) / (2 * eps);
  const Eigen::VectorXd kc = tangent_stiffness(*m, x, StaticTangent::Consistent) * v;
  const Eigen::VectorXd kr = tangent_stiffness(*m, x, StaticTangent::Corotational) * v;
  const double err_c = (kc + df).norm() / df.norm(), err_r = (kr + df).norm() / df.norm();
  std::printf("[tangent] consistent rel. error %.2e, co-rotational (R K0 R^T) %.2e\n", err_c, err_r);
  EXPECT_LT(err_c, 1e-6);
  EXPECT_GT(err_r, 1e-4);  // the SOFA tangent omits dR: visibly different at 1 % strain
}

}  // namespace
