#include "rl/mlp.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "fd_check.hpp"

namespace codesign::rl {
namespace {

using MlpD = MlpT<double>;

Eigen::MatrixXd random_matrix(Eigen::Index r, Eigen::Index c, Rng& rng, double scale = 1.0) {
  Eigen::MatrixXd m(r, c);
  for (Eigen::Index j = 0; j < c; ++j)
    for (Eigen::Index i = 0; i < r; ++i) m(i, j) = scale * rng.normal();
  return m;
}

// Loss L = sum(C .* mlp(X)) with a fixed random C, so dL/d(out) = C.
void check_mlp_gradients(const std::vector<int>& sizes) {
  Rng rng(7);
  MlpD mlp(sizes);
  // Random (not orthogonal-with-0.01-head) weights so every layer has gradients of order 1.
  mlp.params() = random_matrix(mlp.num_params(), 1, rng, 0.5);
  Eigen::MatrixXd x = random_matrix(sizes.front(), 5, rng);
  const Eigen::MatrixXd c = random_matrix(sizes.back(), 5, rng);

  MlpD::Cache cache;
  mlp.forward(x, cache);
  Eigen::VectorXd grad(mlp.num_params());
  Eigen::MatrixXd d_input;
  mlp.backward(cache, c, grad, &d_input);

  auto loss = [&] { return (mlp.predict(x).array() * c.array()).sum(); };
  test::expect_gradient_matches(mlp.params(), loss, grad, "parameter gradient");
  Eigen::VectorXd x_flat = x.reshaped();
  auto loss_x = [&] {
    const Eigen::MatrixXd xr = x_flat.reshaped(x.rows(), x.cols());
    return (mlp.predict(xr).array() * c.array()).sum();
  };
  test::expect_gradient_matches(x_flat, loss_x, d_input.reshaped(), "input gradient");
}

TEST(Mlp, LinearLayerGradientMatchesFiniteDifferences) { check_mlp_gradients({3, 2}); }
TEST(Mlp, TanhLayerGradientMatchesFiniteDifferences) { check_mlp_gradients({3, 4, 2}); }
TEST(Mlp, DeepNetworkGradientMatchesFiniteDifferences) { check_mlp_gradients({4, 6, 5, 3, 2}); }

TEST(Mlp, ForwardIsTanhHiddenLinearOutput) {
  MlpD mlp({2, 3, 1});
  Rng rng(1);
  mlp.params() = random_matrix(mlp.num_params(), 1, rng);
  const Eigen::Vector2d x(0.3, -0.7);
  const Eigen::VectorXd h = (mlp.weight(1) * x + mlp.bias(1)).array().tanh();
  const double expected = (mlp.weight(2) * h + mlp.bias(2))(0);
  EXPECT_NEAR(mlp.predict(x)(0, 0), expected, 1e-14);
}

TEST(Mlp, OrthogonalInitHasGainTimesOrthonormalRowsOrColumnsAndZeroBias) {
  MlpD mlp({6, 8, 4, 1});
  Rng rng(3);
  mlp.init_orthogonal(0.01, rng);
  // W1 is 8x6 (tall): columns orthonormal * sqrt(2).
  const Eigen::MatrixXd w1 = mlp.weight(1);
  EXPECT_TRUE((w1.transpose() * w1).isApprox(2.0 * Eigen::MatrixXd::Identity(6, 6), 1e-12));
  // W2 is 4x8 (wide): rows orthonormal * sqrt(2).
  const Eigen::MatrixXd w2 = mlp.weight(2);
  EXPECT_TRUE((w2 * w2.transpose()).isApprox(2.0 * Eigen::MatrixXd::Identity(4, 4), 1e-12));
  // Head 1x4: a row of norm 0.01.
  EXPECT_NEAR(mlp.weight(3).norm(), 0.01, 1e-14);
  for (int l = 1; l <= 3; ++l) EXPECT_EQ(mlp.bias(l).norm(), 0.0);
}

TEST(Mlp, FloatAndDoubleAgreeWithinFloatRounding) {
  MlpD md({6, 32, 32, 1});
  Rng rng(5);
  md.init_orthogonal(1.0, rng);
  Mlp mf({6, 32, 32, 1});
  mf.params() = md.params().cast<float>();
  const Eigen::MatrixXd x = random_matrix(6, 10, rng);
  const Eigen::MatrixXd yd = md.predict(x);
  const Eigen::MatrixXd yf = mf.predict(x.cast<float>()).cast<double>();
  // Each output is a sum of ~32 terms of size <= ~1 per layer, three layers: float32 rounding
  // (2^-24 ~ 6e-8 per operation) accumulates to well below 1e-4. Eigen's fast float tanh has a
  // relative error of a few ulp.
  EXPECT_LT((yd - yf).cwiseAbs().maxCoeff(), 1e-4);
}

}  // namespace
}  // namespace codesign::rl
