#include "rl/mlp.hpp"

#include <algorithm>
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

// backward() returns the squared L2 norm of the gradient it wrote (for global gradient-norm
// clipping without another pass over the gradient).
//
// float64, sizes {3, 70, 40, 2}: N = 3202 parameters. backward() sums, per layer, the squares of
// the weight gradient and of the bias gradient (Eigen squaredNorm: n_i rounded squares, n_i - 1
// additions, any order) and adds the parts (at most 4 more additions on any term); the reference
// sums all N rounded squares at once. Nonnegative terms, so each result carries at most N
// rounding factors on every term (n_i + 5 <= N): relative error <= gamma_N(u64) against the
// exact sum S (Higham, Lemma 3.4), whatever the order or blocking. Hence
// |returned - reference| <= 2 gamma_N S <= 2 gamma_{N+1} reference (the step from S to the
// reference, a factor 1 / (1 - gamma_N), is absorbed by N + 1): ~7e-13 relative.
TEST(Mlp, BackwardReturnsSquaredGradientNorm) {
  Rng rng(12);
  MlpD mlp({3, 70, 40, 2});
  mlp.params() = random_matrix(mlp.num_params(), 1, rng, 0.3);
  const Eigen::MatrixXd x = random_matrix(3, 33, rng);
  const Eigen::MatrixXd d_out = random_matrix(2, 33, rng);
  MlpD::Cache cache;
  mlp.forward(x, cache);
  Eigen::VectorXd grad(mlp.num_params());
  const double returned = mlp.backward(cache, d_out, grad);
  const double reference = grad.squaredNorm();
  const auto n = static_cast<double>(mlp.num_params());
  ASSERT_EQ(mlp.num_params(), 3202);
  const double u64 = 0x1p-53, gamma = (n + 1) * u64 / (1 - (n + 1) * u64);
  EXPECT_LE(std::abs(returned - reference), 2 * gamma * reference)
      << "returned " << returned << " reference " << reference;
  // Every layer contributes (a norm that skipped a layer would be off by far more than that).
  for (int l = 1; l <= mlp.num_layers(); ++l) {
    const double part =
        grad.segment(mlp.weight_offset(l), mlp.bias_offset(l) + mlp.sizes()[l] -
                                              mlp.weight_offset(l)).squaredNorm();
    EXPECT_GT(part, 4 * gamma * reference) << "layer " << l;
  }
}

// float32 network on the bf16 path, sizes {6, 96, 80, 1}, batch 40 (the 80 x 96 layer's weight
// gradient and input gradient run on gemm_bf16). backward() returns the sum, in double, of
// float32 squaredNorm()s of the parts (largest: the 80 x 96 weight gradient, n = 7680 terms). A
// float32 sum of n rounded nonnegative squares has relative error <= gamma_n(u32) (the square
// rounds once, then n - 1 additions); converting to double is exact and the double additions of
// the six parts add <= gamma_6(u64). The reference squares and sums the same float values in
// double: <= gamma_N(u64), N = 7841. So, to first order, |returned - reference| <=
// (gamma_7680(u32) + gamma_6(u64) + gamma_N(u64)) reference, ~4.6e-4 relative; the indices are
// raised by one (gamma_{n+1}) to cover the second-order terms (< 1e-7 of the bound). What the
// arithmetic of the gradient itself is (bf16 or not) does not matter: both sides see the same
// gradient values.
TEST(Mlp, BackwardReturnsSquaredGradientNormOnBf16Path) {
  if (!bf16_gemm_available()) GTEST_SKIP() << "built without AVX-512 BF16";
  Rng rng(13);
  MlpD md({6, 96, 80, 1});
  md.init_orthogonal(1.0, rng);
  Mlp mlp({6, 96, 80, 1});
  mlp.params() = md.params().cast<float>();
  mlp.set_matmul_precision(MatmulPrecision::BFloat16);
  const Eigen::MatrixXf x = random_matrix(6, 40, rng).cast<float>();
  const Eigen::MatrixXf d_out = random_matrix(1, 40, rng).cast<float>();
  Mlp::Cache cache;
  mlp.forward(x, cache);
  Eigen::VectorXf grad(mlp.num_params());
  const double returned = mlp.backward(cache, d_out, grad);
  const double reference = grad.cast<double>().squaredNorm();
  Eigen::Index largest = 0;
  for (int l = 1; l <= mlp.num_layers(); ++l)
    largest = std::max<Eigen::Index>(largest, Eigen::Index{mlp.sizes()[l]} * mlp.sizes()[l - 1]);
  ASSERT_EQ(largest, 7680);
  const auto gamma = [](double n, double u) { return n * u / (1 - n * u); };
  const double bound = gamma(double(largest + 1), 0x1p-24) + gamma(7, 0x1p-53) +
                       gamma(double(mlp.num_params() + 1), 0x1p-53);
  EXPECT_LE(std::abs(returned - reference), bound * reference)
      << "returned " << returned << " reference " << reference;
  // The smallest layer part (the 1 x 80 head plus its bias, 81 entries) must be visible in the
  // sum above the tolerance, or dropping it would go unnoticed.
  const Eigen::Index head = mlp.weight_offset(3);
  EXPECT_GT(grad.segment(head, mlp.num_params() - head).cast<double>().squaredNorm(),
            2 * bound * reference);
}

}  // namespace
}  // namespace codesign::rl
