// The element pass vectorised across elements (CorotatedBatch) against the one-element
// functions it replaces in the simulator (polar_rotation, corotated_force,
// corotated_stiffness_times), summed element by element over a shared-node mesh.
//
// Tolerances: both sides compute the same quantities in double precision in another order, and
// both polar iterations stop within 1e-14 rad of the rotation (tolerance 1e-14), so rotations
// agree to a few 1e-14; nodal sums of forces of size |f| then agree to about 1e-13 |f| (a
// handful of rounding steps of 1e-16 on each of up to ~24 element terms, plus the rotation
// difference times the stress). We assert 1e-11 relative: tight enough that one wrong index,
// sign or transposition (an O(1) error) fails.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <stdexcept>

#include "fem/box_mesh.hpp"
#include "fem/corotated_batch.hpp"
#include "fem/corotational_tet.hpp"

namespace codesign::fem {
namespace {

constexpr double kMu = 1.8e5, kLambda = 7.1e5;

struct Fixture {
  TetMesh mesh;
  std::vector<TetRest> rest;
  Eigen::VectorXd X;  // rest positions, 3 per node
};

// A box of nx·ny·nz cells, 6 tets each.
Fixture make_fixture(int nx, int ny, int nz) {
  Fixture f;
  f.mesh = make_box_mesh(3.0, 1.0, 1.0, nx, ny, nz);
  for (const Tet& t : f.mesh.tets)
    f.rest.push_back(make_tet_rest({f.mesh.nodes[t[0]], f.mesh.nodes[t[1]], f.mesh.nodes[t[2]], f.mesh.nodes[t[3]]}));
  f.X.resize(3 * f.mesh.nodes.size());
  for (std::size_t i = 0; i < f.mesh.nodes.size(); ++i) f.X.segment<3>(3 * i) = f.mesh.nodes[i];
  return f;
}

// Positions: a rigid rotation by `angle` about a random axis of the rest shape, plus nodal
// noise of size `noise` (large strains at 0.1).
Eigen::VectorXd deformed(const Fixture& f, double angle, double noise, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(angle, Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()).toRotationMatrix();
  std::uniform_real_distribution<double> u(-noise, noise);
  Eigen::VectorXd x(f.X.size());
  for (Eigen::Index i = 0; i < x.size() / 3; ++i)
    x.segment<3>(3 * i) = Q * f.X.segment<3>(3 * i) + Eigen::Vector3d(u(rng), u(rng), u(rng));
  return x;
}

Eigen::Matrix3d element_F(const Fixture& f, const Eigen::VectorXd& x, std::size_t e) {
  const Tet& t = f.mesh.tets[e];
  return deformation_gradient(f.rest[e], {x.segment<3>(3 * t[0]), x.segment<3>(3 * t[1]), x.segment<3>(3 * t[2]),
                                          x.segment<3>(3 * t[3])});
}

void check_pass(int nx, int ny, int nz, double angle, std::uint32_t seed) {
  SCOPED_TRACE("mesh " + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) +
               ", angle " + std::to_string(angle));
  std::mt19937 rng(seed);
  const Fixture fx = make_fixture(nx, ny, nz);
  const std::size_t ne = fx.mesh.tets.size();
  const Eigen::VectorXd x = deformed(fx, angle, 0.1, rng);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd u(x.size());
  for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = n(rng);

  // Reference: one element at a time, from the identity as warm start.
  Eigen::VectorXd f_ref = Eigen::VectorXd::Zero(x.size()), ku_ref = f_ref;
  std::vector<Eigen::Matrix3d> R_ref(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const Eigen::Matrix3d F = element_F(fx, x, e);
    polar_rotation(F, Eigen::Quaterniond::Identity(), 1e-14, &R_ref[e]);
    const Tet& t = fx.mesh.tets[e];
    Vec12 ue;
    for (int a = 0; a < 4; ++a) ue.segment<3>(3 * a) = u.segment<3>(3 * t[a]);
    const Vec12 fe = corotated_force(fx.rest[e], F, R_ref[e], kMu, kLambda);
    const Vec12 ye = corotated_stiffness_times(fx.rest[e], R_ref[e], ue, kMu, kLambda);
    for (int a = 0; a < 4; ++a) {
      f_ref.segment<3>(3 * t[a]) += fe.segment<3>(3 * a);
      ku_ref.segment<3>(3 * t[a]) += ye.segment<3>(3 * a);
    }
  }

  CorotatedBatch batch(fx.mesh.tets, fx.rest, kMu, kLambda);  // rotations start at the identity
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size()), ku = f;
  double det = 0.0;
  ASSERT_EQ(batch.elastic_pass(x, 1e-14, f, &u, &ku, &det), -1);
  const std::vector<Eigen::Matrix3d> R = batch.rotation_matrices();
  ASSERT_EQ(R.size(), ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const int ei = static_cast<int>(e);
    EXPECT_LT((R[e] - R_ref[e]).norm(), 1e-12) << "element " << e;
    EXPECT_EQ(batch.rotation(ei), R[e]);
    EXPECT_LT((batch.quaternion(ei).toRotationMatrix() - R[e]).norm(), 1e-14) << "element " << e;
    // The polar rotation makes Rᵀ F symmetric (its defining property, independent of the reference).
    const Eigen::Matrix3d S = R[e].transpose() * element_F(fx, x, e);
    EXPECT_LT((S - S.transpose()).norm(), 1e-11 * S.norm()) << "element " << e;
  }
  EXPECT_LT((f - f_ref).norm(), 1e-11 * f_ref.norm());
  EXPECT_LT((ku - ku_ref).norm(), 1e-11 * ku_ref.norm());

  // The product alone, with the rotations the pass stored, and with rotations set one by one.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  batch.add_stiffness_times(u, y);
  EXPECT_LT((y - ku_ref).norm(), 1e-11 * ku_ref.norm());
  // Rotations put back whole into a fresh batch give the same product, bit for bit; and a pass
  // from them starts where this one ended (the same rotations again, to the tolerance).
  CorotatedBatch fresh(fx.mesh.tets, fx.rest, kMu, kLambda);
  fresh.set_rotations(batch.rotations());
  EXPECT_EQ(fresh.rotations(), batch.rotations());
  Eigen::VectorXd y2 = Eigen::VectorXd::Zero(x.size());
  fresh.add_stiffness_times(u, y2);
  EXPECT_EQ(y2, y);
  // All set to one rotation G: matrix G, quaternion G's, padding untouched by the product.
  const Eigen::Matrix3d G = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()).toRotationMatrix();
  fresh.set_all_rotations(G);
  for (std::size_t e = 0; e < ne; ++e) {
    EXPECT_EQ(fresh.rotation(static_cast<int>(e)), G);
    EXPECT_EQ(fresh.quaternion(static_cast<int>(e)).coeffs(), Eigen::Quaterniond(G).coeffs());
  }
  // Matrices only: the quaternions (warm starts) stay those put back before.
  fresh.set_rotations(batch.rotations());
  fresh.set_all_rotation_matrices(G);
  for (std::size_t e = 0; e < ne; ++e) {
    EXPECT_EQ(fresh.rotation(static_cast<int>(e)), G);
    EXPECT_EQ(fresh.quaternion(static_cast<int>(e)).coeffs(), batch.quaternion(static_cast<int>(e)).coeffs());
  }
  CorotatedBatch other(make_fixture(2, 1, 1).mesh.tets, make_fixture(2, 1, 1).rest, kMu, kLambda);
  EXPECT_THROW(other.set_rotations(batch.rotations()), std::invalid_argument);
}

TEST(CorotatedBatch, ElasticPassMatchesTheElementFunctionsOnSharedNodes) {
  check_pass(3, 2, 2, 0.3, 1);   // 72 tets: nine full groups
  check_pass(3, 2, 1, 0.3, 2);   // 36 tets: a last group of four lanes (padding)
}

TEST(CorotatedBatch, LargeTurnsFromAnOldWarmStartConverge) {
  // 2.5 rad from the identity: the first increments exceed half a radian (the scalar step with
  // std::cos and std::sin).
  check_pass(3, 2, 1, 2.5, 3);
}

TEST(CorotatedBatch, ReportsTheFirstInvertedElementAndItsDeterminant) {
  const Fixture fx = make_fixture(3, 2, 1);
  const std::size_t ne = fx.mesh.tets.size();
  Eigen::VectorXd x = fx.X;
  // Mirror every node through the plane x = 1.5: every element inverts; the first is 0.
  for (Eigen::Index i = 0; i < x.size() / 3; ++i) x[3 * i] = 3.0 - x[3 * i];
  CorotatedBatch batch(fx.mesh.tets, fx.rest, kMu, kLambda);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  double det = 0.0;
  EXPECT_EQ(batch.elastic_pass(x, 1e-6, f, nullptr, nullptr, &det), 0);
  EXPECT_NEAR(det, element_F(fx, x, 0).determinant(), 1e-12);
  EXPECT_LT(det, 0.0);
  // Node 0 of element 29 pushed through its opposite face: the first element that inverts
  // (by the one-element determinant) is reported.
  x = fx.X;
  const Tet& t = fx.mesh.tets[29];
  const Eigen::Vector3d centroid = (fx.mesh.nodes[t[1]] + fx.mesh.nodes[t[2]] + fx.mesh.nodes[t[3]]) / 3.0;
  x.segment<3>(3 * t[0]) = fx.mesh.nodes[t[0]] + 2.0 * (centroid - fx.mesh.nodes[t[0]]);
  int first_bad = -1;
  for (std::size_t e = 0; e < ne && first_bad < 0; ++e)
    if (!(element_F(fx, x, e).determinant() > 0.0)) first_bad = static_cast<int>(e);
  ASSERT_GE(first_bad, 0);
  EXPECT_EQ(batch.elastic_pass(x, 1e-6, f, nullptr, nullptr, &det), first_bad);
  // A NaN position: reported as a non-finite determinant at the first element touching it.
  x = fx.X;
  x[3 * fx.mesh.tets[5][2] + 1] = std::nan("");
  int first_nan = -1;
  for (std::size_t e = 0; e < ne && first_nan < 0; ++e)
    for (int a = 0; a < 4; ++a)
      if (fx.mesh.tets[e][a] == fx.mesh.tets[5][2]) first_nan = static_cast<int>(e);
  EXPECT_EQ(batch.elastic_pass(x, 1e-6, f, nullptr, nullptr, &det), first_nan);
  EXPECT_FALSE(std::isfinite(det));
}

}  // namespace
}  // namespace codesign::fem
