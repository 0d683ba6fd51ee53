// The contact LCP solver on small problems with known answers.
#include <gtest/gtest.h>

#include <random>

#include "fem/contact.hpp"

namespace codesign::fem {
namespace {

TEST(ContactLcp, SinglePoint) {
  Eigen::MatrixXd D(1, 1);
  D << 2.0;
  Eigen::VectorXd g(1);
  g << -1.0;  // penetrates by 1: λ = 0.5 holds it on the plate
  auto r = solve_contact_lcp(D, g, {}, 1e-12);
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.lambda[0], 0.5, 1e-14);
  g << 0.3;  // separated: no force
  r = solve_contact_lcp(D, g, {1}, 1e-12);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.lambda[0], 0.0);
}

TEST(ContactLcp, CoupledPointsReleaseTheOneThatWouldPull) {
  // Pushing point 0 lifts point 1 (negative coupling): only point 0 carries load.
  Eigen::MatrixXd D(2, 2);
  D << 1.0, 0.9, 0.9, 1.0;
  Eigen::VectorXd g(2);
  g << -1.0, -0.5;
  const auto r = solve_contact_lcp(D, g, {1, 1}, 1e-12);
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.lambda[0], 1.0, 1e-12);
  EXPECT_EQ(r.lambda[1], 0.0);
  const Eigen::VectorXd w = g + D * r.lambda;
  EXPECT_GE(w[1], 0.0);
}

TEST(ContactLcp, RandomSpdProblemsSatisfyComplementarity) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int m = 1 + trial % 12;
    Eigen::MatrixXd B(m, m);
    for (int i = 0; i < m * m; ++i) B(i) = n(rng);
    const Eigen::MatrixXd D = B * B.transpose() + 0.1 * Eigen::MatrixXd::Identity(m, m);
    Eigen::VectorXd g(m);
    for (int i = 0; i < m; ++i) g[i] = n(rng);
    const auto r = solve_contact_lcp(D, g, {}, 1e-12);
    ASSERT_TRUE(r.converged);
    const Eigen::VectorXd w = g + D * r.lambda;
    // Residual tolerance: round-off of an m×m solve with entries O(|D|·|λ|), ~1e-12 relative.
    const double tol = 1e-9 * (1.0 + D.norm() * r.lambda.norm() + g.norm());
    for (int i = 0; i < m; ++i) {
      EXPECT_GE(r.lambda[i], 0.0);
      EXPECT_GE(w[i], -tol);
      EXPECT_LT(std::abs(w[i] * r.lambda[i]), tol * (1.0 + r.lambda.norm()));
    }
  }
}

}  // namespace
}  // namespace codesign::fem
