// Element-level checks of the co-rotational tetrahedron against finite differences and
// invariance properties.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "fem/corotational_tet.hpp"

namespace codesign::fem {
namespace {

constexpr double kE = 5e5, kNu = 0.4;
const double kMu = kE / (2 * (1 + kNu));
const double kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu));

std::array<Eigen::Vector3d, 4> rest_tet() {
  return {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.2, 0.1, 0.0), Eigen::Vector3d(0.2, 0.9, 0.1),
          Eigen::Vector3d(0.1, 0.2, 1.1)};
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// A deformation gradient F = Q (I + H) with a random rotation Q and the entries of H uniform in
// [-0.2, 0.2] (large strains, so the polar iteration has work to do).
struct RandomDeformation {
  Eigen::Matrix3d Q, F;
};
RandomDeformation random_deformation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  const Eigen::Matrix3d Q = random_rotation(rng);
  Eigen::Matrix3d H;
  for (int i = 0; i < 9; ++i) H(i) = u(rng);
  return {Q, Q * (Eigen::Matrix3d::Identity() + H)};
}

// Current positions: x = Q (I + H) X + c with strain-like perturbation H (|H| ~ strain).
std::array<Eigen::Vector3d, 4> deform(const std::array<Eigen::Vector3d, 4>& X, const Eigen::Matrix3d& Q,
                                      const Eigen::Matrix3d& H, const Eigen::Vector3d& c) {
  std::array<Eigen::Vector3d, 4> x;
  for (int a = 0; a < 4; ++a) x[a] = Q * (X[a] + H * X[a]) + c;
  return x;
}

Vec12 force_at(const TetRest& r, const std::array<Eigen::Vector3d, 4>& x) {
  const Eigen::Matrix3d F = deformation_gradient(r, x);
  return corotated_force(r, F, polar_rotation_svd(F), kMu, kLambda);
}

double energy_at(const TetRest& r, const std::array<Eigen::Vector3d, 4>& x) {
  const Eigen::Matrix3d F = deformation_gradient(r, x);
  return corotated_energy(r, F, polar_rotation_svd(F), kMu, kLambda);
}

TEST(CorotationalTet, RestDataAndStiffnessNullSpace) {
  const TetRest r = make_tet_rest(rest_tet());
  EXPECT_GT(r.volume, 0.0);
  // Σ_a ∇N_a = 0 and Σ_a X_a ∇N_aᵀ = I (linear completeness).
  EXPECT_LT(r.grad.colwise().sum().norm(), 1e-12);
  Eigen::Matrix3d id = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 4; ++a) id += rest_tet()[a] * r.grad.row(a);
  EXPECT_LT((id - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // K0 annihilates translations and infinitesimal rotations; it is symmetric.
  const Mat12 k0 = rest_stiffness(r, kMu, kLambda);
  EXPECT_LT((k0 - k0.transpose()).norm(), 1e-9 * k0.norm());
  for (int d = 0; d < 3; ++d) {
    Vec12 tr = Vec12::Zero(), rot = Vec12::Zero();
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    w[d] = 1.0;
    for (int a = 0; a < 4; ++a) tr[3 * a + d] = 1.0, rot.segment<3>(3 * a) = w.cross(rest_tet()[a]);
    EXPECT_LT((k0 * tr).norm(), 1e-9 * k0.norm());
    EXPECT_LT((k0 * rot).norm(), 1e-9 * k0.norm());
  }
}

TEST(CorotationalTet, PolarRotationMatchesSvd) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const auto [Q, F] = random_deformation(rng);
    // Cold start (identity) and a warm start near the answer must both reach the polar factor.
    const Eigen::Matrix3d ref = polar_rotation_svd(F);
    EXPECT_LT((polar_rotation(F, Eigen::Matrix3d::Identity()) - ref).norm(), 1e-9);
    EXPECT_LT((polar_rotation(F, Q) - ref).norm(), 1e-9);
    // Rᵀ F symmetric (definition of the polar factor).
    const Eigen::Matrix3d S = ref.transpose() * F;
    EXPECT_LT((S - S.transpose()).norm(), 1e-10);
  }
}

// The matrix handed out with the quaternion is exactly that quaternion's rotation matrix (the
// simulator stores both; it must not matter which one a caller uses), on every exit path: the
// cold start, the warm start, the tight and the loose tolerance, and a guess that is already exact.
TEST(CorotationalTet, PolarRotationMatrixOutIsItsQuaternionsMatrix) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const auto [Q, F] = random_deformation(rng);
    const Eigen::Quaterniond exact(polar_rotation_svd(F));
    for (const Eigen::Quaterniond& guess : {Eigen::Quaterniond::Identity(), Eigen::Quaterniond(Q), exact})
      for (double tol : {1e-14, 1e-6}) {
        Eigen::Matrix3d R;
        const Eigen::Quaterniond q = polar_rotation(F, guess, tol, &R);
        EXPECT_EQ(R, q.toRotationMatrix());
      }
  }
}

TEST(CorotationalTet, RigidMotionGivesZeroForce) {
  std::mt19937 rng(7);
  const auto X = rest_tet();
  const TetRest r = make_tet_rest(X);
  // Scale of a typical force: E · V · |∇N| at unit strain. Round-off in R and F is ~1e-15
  // relative, so a force below 1e-10 of that scale is zero.
  const double scale = kE * r.volume * r.grad.norm();
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = deform(X, random_rotation(rng), Eigen::Matrix3d::Zero(), Eigen::Vector3d(3, -2, 5));
    EXPECT_LT(force_at(r, x).norm(), 1e-10 * scale);
    EXPECT_LT(std::abs(energy_at(r, x)), 1e-20 * scale);
  }
}

TEST(CorotationalTet, ForceIsMinusEnergyGradient) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  const auto X = rest_tet();
  const TetRest r = make_tet_rest(X);
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::Matrix3d H;
    for (int i = 0; i < 9; ++i) H(i) = u(rng);
    auto x = deform(X, random_rotation(rng), H, Eigen::Vector3d(1, 2, 3));
    const Vec12 f = force_at(r, x);
    // Central differences: truncation error ~ h² |W'''| ≈ h² · E V |∇N|³, i.e. relative to the
    // force scale E V |∇N| · |H| about h² |∇N|² / |H| ≈ 1e-10/0.05; round-off ~ ε W / h ≈ 1e-10.
    // A relative tolerance of 1e-6 is far above both and far below a real error (O(1)).
    const double h = 1e-6;
    Vec12 fd;
    for (int k = 0; k < 12; ++k) {
      auto xp = x, xm = x;
      xp[k / 3][k % 3] += h;
      xm[k / 3][k % 3] -= h;
      fd[k] = -(energy_at(r, xp) - energy_at(r, xm)) / (2 * h);
    }
    EXPECT_LT((f - fd).norm(), 1e-6 * f.norm()) << "trial " << trial;
  }
}

TEST(CorotationalTet, StiffnessMatchesForceDerivative) {
  std::mt19937 rng(5);
  const auto X = rest_tet();
  const TetRest r = make_tet_rest(X);
  const Mat12 k0 = rest_stiffness(r, kMu, kLambda);
  auto fd_stiffness = [&](const std::array<Eigen::Vector3d, 4>& x) {
    Mat12 k;
    const double h = 1e-6;
    for (int c = 0; c < 12; ++c) {
      auto xp = x, xm = x;
      xp[c / 3][c % 3] += h;
      xm[c / 3][c % 3] -= h;
      k.col(c) = -(force_at(r, xp) - force_at(r, xm)) / (2 * h);
    }
    return k;
  };
  for (double strain : {0.0, 1e-3, 1e-2}) {
    Eigen::Matrix3d H;
    std::uniform_real_distribution<double> u(-strain, strain);
    for (int i = 0; i < 9; ++i) H(i) = u(rng);
    const Eigen::Matrix3d Q = random_rotation(rng);
    const auto x = deform(X, Q, H, Eigen::Vector3d(-1, 0, 2));
    const Eigen::Matrix3d F = deformation_gradient(r, x);
    const Eigen::Matrix3d R = polar_rotation_svd(F);
    const Mat12 kc = corotated_stiffness(k0, R);
    const Mat12 kfd = fd_stiffness(x);
    // The co-rotational tangent R K0 Rᵀ omits ∂R/∂x · σ. That term scales with the stress, so
    // |K_fd − K_c| ≤ c · |ε| · |K0|, c = O(1 + λ/μ) = O(3) for ν = 0.4 on this well-shaped tet.
    // At zero strain it must vanish up to finite-difference error (~1e-7 relative here).
    // Bound: 10 · (max |H| entry) · |K0| + 1e-6 |K0|.
    const double err = (kc - kfd).norm() / k0.norm();
    EXPECT_LT(err, 10.0 * strain + 1e-6) << "strain " << strain;
    // The matrix-free product equals the matrix.
    Vec12 u12 = Vec12::Random();
    EXPECT_LT((corotated_stiffness_times(r, R, u12, kMu, kLambda) - kc * u12).norm(), 1e-10 * (kc * u12).norm());
  }
}

TEST(CorotationalTet, DegenerateTetRejected) {
  EXPECT_THROW(make_tet_rest({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                              Eigen::Vector3d(1, 1, 0)}),
               std::invalid_argument);
  // Negative orientation.
  EXPECT_THROW(make_tet_rest({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 0, 0),
                              Eigen::Vector3d(0, 0, 1)}),
               std::invalid_argument);
}

}  // namespace
}  // namespace codesign::fem
