#include "rl/gru.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "fd_check.hpp"

namespace codesign::rl {
namespace {

using GruD = GruT<double>;

Eigen::MatrixXd random_matrix(Eigen::Index r, Eigen::Index c, Rng& rng, double scale = 1.0) {
  Eigen::MatrixXd m(r, c);
  for (Eigen::Index i = 0; i < m.size(); ++i) m(i) = scale * rng.normal();
  return m;
}

// A 1-unit GRU, one step, worked by hand from PyTorch's equations:
//   r = σ(0.5·1 + 0.1 + 0.2·0.5 + 0.05) = σ(0.75) = 0.679178699175393
//   z = σ(−0.3·1 + 0 + 0.4·0.5 + 0.1) = σ(0) = 0.5
//   W_hn h + b_hn = −0.6·0.5 + 0.4 = 0.1
//   n = tanh(0.8·1 − 0.2 + r·0.1) = tanh(0.6679178699175393) = 0.5836085925036042
//   h' = (1 − z) n + z h = 0.5·0.5836085925036042 + 0.25 = 0.5418042962518022
TEST(Gru, OneUnitForwardMatchesHandComputedValue) {
  GruD gru(1, 1);
  // Layout: W_ih (r, z, n), W_hh (r, z, n), b_ih (r, z, n), b_hh (r, z, n).
  gru.params() << 0.5, -0.3, 0.8, 0.2, 0.4, -0.6, 0.1, 0.0, -0.2, 0.05, 0.1, 0.4;
  GruD::Cache cache;
  const Eigen::MatrixXd x = Eigen::MatrixXd::Constant(1, 1, 1.0);
  const Eigen::MatrixXd h0 = Eigen::MatrixXd::Constant(1, 1, 0.5);
  const Eigen::RowVectorXd starts = Eigen::RowVectorXd::Zero(1);
  const auto& h = gru.forward(x, starts, h0, 1, cache);
  EXPECT_NEAR(h(0, 0), 0.5418042962518022, 1e-15);
  Eigen::MatrixXd hs = h0;
  gru.step(x, starts, hs);
  EXPECT_EQ(hs(0, 0), h(0, 0));
  // A reset at the step: the state is zero before it, so h0 no longer matters.
  Eigen::MatrixXd other = Eigen::MatrixXd::Constant(1, 1, -0.9);
  const Eigen::RowVectorXd reset = Eigen::RowVectorXd::Ones(1);
  const double a = gru.forward(x, reset, h0, 1, cache)(0, 0);
  EXPECT_EQ(gru.forward(x, reset, other, 1, cache)(0, 0), a);
}

// Loss L = sum(C ⊙ H) over every output of a 4-step, 3-sequence batch with a fixed random C, so
// dL/dH = C. Tolerance: fd_check.hpp's bound h²D/6 + εF/h with h = 1e-5. Here |L| ≤ sum|C| ≈ 36·0.8
// < 100 (every |h_t| ≤ 1: a convex combination of a tanh and a previous state with |h0| < 1), and the
// third derivatives of L stay below ~100: the third derivatives of σ and tanh are bounded (≤ 1/8
// and 2), and chaining them through 4 steps of weights of scale 0.5 multiplies by at most a few
// units per step. So the error is below 5e-9 and the check's 1e-6·(1 + |g|) holds with a margin.
TEST(Gru, ParameterInputAndInitialStateGradientsMatchFiniteDifferences) {
  Rng rng(31);
  const int in = 2, hid = 3, steps = 4, batch = 3;
  GruD gru(in, hid);
  gru.params() = random_matrix(gru.num_params(), 1, rng, 0.5);
  Eigen::MatrixXd x = random_matrix(in, steps * batch, rng);
  Eigen::MatrixXd h0 = random_matrix(hid, batch, rng, 0.5).array().tanh();
  Eigen::RowVectorXd starts = Eigen::RowVectorXd::Zero(steps * batch);
  starts(2 * batch + 1) = 1;  // sequence 1 starts an episode at step 2
  const Eigen::MatrixXd c = random_matrix(hid, steps * batch, rng);

  GruD::Cache cache;
  gru.forward(x, starts, h0, steps, cache);
  Eigen::VectorXd grad(gru.num_params());
  Eigen::MatrixXd d_x, d_h0;
  gru.backward(cache, c, grad, &d_x, &d_h0);

  auto loss_of = [&](const Eigen::MatrixXd& xx, const Eigen::MatrixXd& hh) {
    GruD::Cache k;
    return (gru.forward(xx, starts, hh, steps, k).array() * c.array()).sum();
  };
  auto loss = [&] { return loss_of(x, h0); };
  test::expect_gradient_matches(gru.params(), loss, grad, "parameter gradient");
  Eigen::VectorXd x_flat = x.reshaped();
  auto loss_x = [&] { return loss_of(x_flat.reshaped(in, steps * batch), h0); };
  test::expect_gradient_matches(x_flat, loss_x, d_x.reshaped(), "input gradient");
  Eigen::VectorXd h_flat = h0.reshaped();
  auto loss_h = [&] { return loss_of(x, h_flat.reshaped(hid, batch)); };
  test::expect_gradient_matches(h_flat, loss_h, d_h0.reshaped(), "initial state gradient");
}

// With a reset before step 2 of sequence 1, a loss on that sequence's outputs from step 2 on does
// not depend on its earlier inputs or on h0: those gradients are exactly zero, while without the
// reset they are not.
TEST(Gru, GradientDoesNotFlowAcrossAReset) {
  Rng rng(32);
  const int in = 2, hid = 4, steps = 5, batch = 2;
  GruD gru(in, hid);
  gru.params() = random_matrix(gru.num_params(), 1, rng, 0.7);
  const Eigen::MatrixXd x = random_matrix(in, steps * batch, rng);
  const Eigen::MatrixXd h0 = random_matrix(hid, batch, rng, 0.5);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(hid, steps * batch);
  for (int t = 2; t < steps; ++t) c.col(t * batch + 1) = random_matrix(hid, 1, rng);
  auto grads = [&](const Eigen::RowVectorXd& starts, Eigen::MatrixXd& d_x, Eigen::MatrixXd& d_h0) {
    GruD::Cache cache;
    gru.forward(x, starts, h0, steps, cache);
    Eigen::VectorXd grad(gru.num_params());
    gru.backward(cache, c, grad, &d_x, &d_h0);
  };
  Eigen::RowVectorXd starts = Eigen::RowVectorXd::Zero(steps * batch);
  Eigen::MatrixXd d_x, d_h0;
  grads(starts, d_x, d_h0);
  EXPECT_GT(d_h0.col(1).norm(), 1e-3);
  for (int t = 0; t < 2; ++t) EXPECT_GT(d_x.col(t * batch + 1).norm(), 1e-3);

  starts(2 * batch + 1) = 1;
  grads(starts, d_x, d_h0);
  EXPECT_EQ(d_h0.col(1).norm(), 0.0);
  for (int t = 0; t < 2; ++t) EXPECT_EQ(d_x.col(t * batch + 1).norm(), 0.0) << "step " << t;
  EXPECT_GT(d_x.col(2 * batch + 1).norm(), 1e-3);
  // Sequence 0 gets no loss at all.
  EXPECT_EQ(d_h0.col(0).norm(), 0.0);
  // And forward: the outputs after the reset are those of a sequence started from zero there.
  GruD::Cache cache;
  const Eigen::MatrixXd h = gru.forward(x, starts, h0, steps, cache);
  Eigen::MatrixXd state = Eigen::MatrixXd::Zero(hid, 1);
  for (int t = 2; t < steps; ++t) {
    gru.step(x.col(t * batch + 1), Eigen::RowVectorXd::Zero(1), state);
    EXPECT_NEAR((state - h.col(t * batch + 1)).norm(), 0.0, 1e-14) << "step " << t;
  }
}

TEST(Gru, DefaultInitIsUniformWithinOneOverSqrtHidden) {
  Gru gru(5, 16);
  Rng rng(3);
  gru.init_uniform(rng);
  EXPECT_EQ(gru.num_params(), 3 * 16 * (5 + 16 + 2));
  EXPECT_LE(gru.params().cwiseAbs().maxCoeff(), 0.25f);
  EXPECT_GT(gru.params().cwiseAbs().maxCoeff(), 0.24f);
  EXPECT_NEAR(gru.params().mean(), 0.0f, 0.02f);
}

}  // namespace
}  // namespace codesign::rl
