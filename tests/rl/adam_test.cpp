#include "rl/adam.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "rl/rng.hpp"

namespace codesign::rl {
namespace {

// Two parameters, three steps, lr 0.1, betas (0.9, 0.999), eps 1e-5, worked by hand:
//
// step 1, g = (0.5, -2):
//   m = 0.1 g = (0.05, -0.2)           v = 0.001 g^2 = (0.00025, 0.004)
//   m / (1 - 0.9) = g, sqrt(v / (1 - 0.999)) = |g|
//   p -= 0.1 * g / (|g| + 1e-5):  dp = (-0.1 * 0.5 / 0.50001, +0.1 * 2 / 2.00001)
//                                     = (-0.0999980000399992, +0.0999995000025)
// step 2, g = (0.5, 1):
//   m = 0.9 (0.05, -0.2) + 0.1 (0.5, 1) = (0.095, -0.08)
//   v = 0.999 (0.00025, 0.004) + 0.001 (0.25, 1) = (0.00049975, 0.004996)
//   bc1 = 1 - 0.81 = 0.19, bc2 = 1 - 0.998001 = 0.001999
//   denom = sqrt(v) / sqrt(bc2) + eps = (0.5 + 1e-5, sqrt(0.004996 / 0.001999) + 1e-5)
//         = (0.50001, 1.58091...)   [0.00049975 / 0.001999 = 0.25 exactly]
//   dp = -0.1 / 0.19 * m / denom = (-0.1/0.19 * 0.095/0.50001, +0.1/0.19 * 0.08/1.58092...)
// step 3, g = (0, 0): only momentum moves the parameters.
//   m = 0.9 m2 = (0.0855, -0.072)      v = 0.999 v2
//   bc1 = 1 - 0.729 = 0.271, bc2 = 1 - 0.997002999 = 0.002997001
TEST(Adam, MatchesHandComputedTorchUpdate) {
  AdamT<double> adam(AdamConfig{0.9, 0.999, 1e-5});
  std::array<double, 2> p{1.0, -1.0};
  std::array<double, 2> g{0.5, -2.0};
  const std::array<AdamBlock<double>, 1> blocks{{{p.data(), g.data(), 2}}};

  adam.step(blocks, 0.1);
  double e0 = 1.0 - 0.1 * 0.5 / 0.50001, e1 = -1.0 + 0.1 * 2.0 / 2.00001;
  EXPECT_NEAR(p[0], e0, 1e-15);
  EXPECT_NEAR(p[1], e1, 1e-15);
  EXPECT_NEAR(p[0], 0.9000019999600007, 1e-15);

  g = {0.5, 1.0};
  adam.step(blocks, 0.1);
  const double d1 = std::sqrt(0.004996 / 0.001999) + 1e-5;
  e0 -= 0.1 / 0.19 * 0.095 / 0.50001;
  e1 -= 0.1 / 0.19 * -0.08 / d1;
  EXPECT_NEAR(p[0], e0, 1e-14);
  EXPECT_NEAR(p[1], e1, 1e-14);

  g = {0.0, 0.0};
  adam.step(blocks, 0.1);
  const double bc2 = 1 - 0.999 * 0.999 * 0.999;
  const double v0 = 0.999 * 0.00049975, v1 = 0.999 * 0.004996;
  e0 -= 0.1 / 0.271 * 0.0855 / (std::sqrt(v0) / std::sqrt(bc2) + 1e-5);
  e1 -= 0.1 / 0.271 * -0.072 / (std::sqrt(v1) / std::sqrt(bc2) + 1e-5);
  EXPECT_NEAR(p[0], e0, 1e-14);
  EXPECT_NEAR(p[1], e1, 1e-14);
  EXPECT_EQ(adam.step_count(), 3);
}

TEST(Adam, EpsIsAddedAfterBiasCorrection) {
  // With a tiny gradient the placement of eps dominates: torch's first step is
  // -lr * g / (|g| + eps); the "eps inside sqrt(v_hat)" variant of some other libraries gives
  // the same here, but eps added to sqrt(v) BEFORE correction gives -lr * g / (|g| + eps /
  // sqrt(1 - b2)) = about 32x smaller step for |g| << eps.
  AdamT<double> adam(AdamConfig{0.9, 0.999, 1e-5});
  double p = 0.0, g = 1e-7;
  const std::array<AdamBlock<double>, 1> blocks{{{&p, &g, 1}}};
  adam.step(blocks, 1.0);
  EXPECT_NEAR(p, -1e-7 / (1e-7 + 1e-5), 1e-15);
}

TEST(Adam, RejectsChangedBlocks) {
  AdamT<float> adam;
  std::array<float, 3> p{}, g{};
  const std::array<AdamBlock<float>, 1> a{{{p.data(), g.data(), 3}}};
  const std::array<AdamBlock<float>, 1> b{{{p.data(), g.data(), 2}}};
  adam.step(a, 0.1);
  EXPECT_THROW(adam.step(b, 0.1), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// grad_scale, and the float32 path (a hand-vectorised AVX-512 loop with a masked tail) against
// float64. Tolerances are rounding-error bounds in Higham's notation: a quantity carrying at
// most n rounding factors (1 + d_i), |d_i| <= u, has relative error <= gamma_n = n u / (1 - n u)
// (Lemma 3.1, factors may also divide).
//
// Setup that makes relative bounds valid: the gradient of each element keeps its sign over the
// steps, so m is a sum of same-sign terms (no cancellation; v is a sum of positive terms), and
// relative errors of the terms carry over to the sum. Gradient magnitudes span 10^-6.5 .. 1 so
// that some elements sit below eps = 1e-5, where the update depends on the gradient's scale
// (elsewhere Adam is nearly scale invariant and a wrong grad_scale would hide in p).
// Blocks of 37 (two full vectors of 16 and a masked tail of 5) and 16 (no tail).
// ---------------------------------------------------------------------------------------------

constexpr int kSteps = 3;
constexpr double kLr = 0.01;
constexpr double kScale = 0.3;
const std::vector<Eigen::Index> kBlocks{37, 16};

double gamma_n(int n, double u) { return n * u / (1 - n * u); }
template <class S>
constexpr double unit_roundoff() {
  return std::is_same_v<S, float> ? 0x1p-24 : 0x1p-53;
}

struct AdamInputs {
  std::vector<float> p0;
  std::vector<std::vector<float>> g;  // g[t]: gradient of step t
};

AdamInputs make_inputs() {
  Rng rng(31);
  Eigen::Index n = 0;
  for (auto b : kBlocks) n += b;
  AdamInputs in;
  std::vector<double> sign(static_cast<std::size_t>(n));
  for (auto& s : sign) s = rng.uniform() < 0.5 ? -1.0 : 1.0;
  for (Eigen::Index i = 0; i < n; ++i) in.p0.push_back(static_cast<float>(kLr * rng.normal()));
  for (int t = 0; t < kSteps; ++t) {
    std::vector<float> g;
    for (Eigen::Index i = 0; i < n; ++i)
      g.push_back(static_cast<float>(sign[static_cast<std::size_t>(i)] *
                                     std::pow(10.0, -6.5 * rng.uniform())));
    in.g.push_back(g);
  }
  return in;
}

// Parameters after every step (p[0] = initial) and the final moments, all as double.
struct AdamRun {
  std::vector<Eigen::VectorXd> p;
  Eigen::VectorXd m, v;
};

// kSteps steps of AdamT<S> over kBlocks; the gradient of step t is `grad(t)` (size n, type S).
template <class S, class Grad>
AdamRun run_adam(const std::vector<float>& p0, Grad grad, double grad_scale) {
  AdamT<S> adam(AdamConfig{0.9, 0.999, 1e-5});
  std::vector<S> p(p0.begin(), p0.end());
  std::vector<S> g(p.size());
  std::vector<AdamBlock<S>> blocks;
  Eigen::Index off = 0;
  for (auto b : kBlocks) {
    blocks.push_back({p.data() + off, g.data() + off, b});
    off += b;
  }
  const auto as_double = [&] {
    return Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, 1>>(p.data(), off)
        .template cast<double>()
        .eval();
  };
  AdamRun r;
  r.p.push_back(as_double());
  for (int t = 0; t < kSteps; ++t) {
    const std::vector<S> gt = grad(t);
    std::copy(gt.begin(), gt.end(), g.begin());  // (assigning g would move the blocks' buffer)
    adam.step(blocks, kLr, grad_scale);
    r.p.push_back(as_double());
  }
  r.m.resize(off);
  r.v.resize(off);
  for (std::size_t i = 0, o = 0; i < blocks.size(); o += blocks[i].size, ++i) {
    r.m.segment(o, blocks[i].size) = adam.first_moment(i).template cast<double>();
    r.v.segment(o, blocks[i].size) = adam.second_moment(i).template cast<double>();
  }
  return r;
}

// |p_X - p_Y| after the last step for two runs whose updates have relative errors <= gx, gy
// against the same ideal update u*_t, each rounded into p with unit roundoff ux, uy:
//   p_t = fl(p_{t-1} - u^_t), |fl(...) - (...)| <= u |p_t|, so per run
//   |p^_t - p*_t| <= |p^_{t-1} - p*_{t-1}| + g |u*_t| + u |p^_t|, summed over the steps.
// |u*_t| from run Y's trajectory: u^_t = p_{t-1} - p_t up to uy |p_t|, and |u*| <= |u^| / (1 - gy).
Eigen::VectorXd p_bound(const AdamRun& x, const AdamRun& y, double gx, double gy, double ux,
                        double uy) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(y.p[0].size());
  for (int t = 1; t <= kSteps; ++t) {
    const Eigen::ArrayXd upd =
        ((y.p[t - 1] - y.p[t]).array().abs() + uy * y.p[t].array().abs()) / (1 - gy);
    b.array() += (gx + gy) * upd + ux * x.p[t].array().abs() + uy * y.p[t].array().abs();
  }
  return b;
}

// Run A: gradient g with grad_scale s; run B: gradient s g (rounded to S) with grad_scale 1.
// Both approximate the same ideal (real arithmetic with the same S constants b1, b2, step size,
// 1/sqrt(bc2), eps): m* = b1 m* + (1 - b1) s g, v* = b2 v* + (1 - b2) (s g)^2. Rounding factors
// (double operations count as one factor of u_S, since u64 <= u_S; 1 - b1 and 1 - b2 are exact
// by Sterbenz; the first step adds to m = v = 0 exactly):
//   m term: A: (1-b1)*s in double, cast to S, times g: 3; B: s*g in double, cast to S, (1-b1)
//           cast, product: 4. Each later step: times b1, add: 2 x 2. m: <= 8 factors -> gamma_8.
//   v term: A: ((1-b2)*s)*s, cast, g*g, product: 5; B: (s g) (2 factors) squared (4) + its
//           rounding + (1-b2) cast + product: 7. Later steps 2 x 2. v: <= 11 -> gamma_11.
//   update step * m / (sqrt(v) / sqrt(bc2) + eps): sqrt halves v's error (sqrt(1 + gamma_11)
//           <= 1 + gamma_6) and rounds: 7; times 1/sqrt(bc2): 8; + eps: 9 (eps carries none);
//           numerator step * m: 9; division: 1. Update: <= 19 -> gamma_19.
// Then the parameter difference is p_bound with gamma_19 for both runs, and the moments differ by
// at most 2 gamma_8 |m*| and 2 gamma_11 v*, with |m*| <= |m^_A| / (1 - gamma_8) (same for v).
template <class S>
void check_grad_scale() {
  const AdamInputs in = make_inputs();
  const auto grad_a = [&](int t) { return std::vector<S>(in.g[t].begin(), in.g[t].end()); };
  const auto grad_b = [&](int t) {
    std::vector<S> g;
    for (float x : in.g[t]) g.push_back(static_cast<S>(kScale * static_cast<double>(x)));
    return g;
  };
  const AdamRun a = run_adam<S>(in.p0, grad_a, kScale);
  const AdamRun b = run_adam<S>(in.p0, grad_b, 1.0);
  const double u = unit_roundoff<S>();
  const double gm = gamma_n(8, u), gv = gamma_n(11, u), gp = gamma_n(19, u);
  const Eigen::VectorXd pb = p_bound(a, b, gp, gp, u, u);
  for (Eigen::Index i = 0; i < pb.size(); ++i) {
    EXPECT_LE(std::abs(a.m(i) - b.m(i)), 2 * gm * std::abs(a.m(i)) / (1 - gm)) << "m, element " << i;
    EXPECT_LE(std::abs(a.v(i) - b.v(i)), 2 * gv * a.v(i) / (1 - gv)) << "v, element " << i;
    EXPECT_LE(std::abs(a.p[kSteps](i) - b.p[kSteps](i)), pb(i)) << "p, element " << i;
  }
  // The parameters moved (by ~lr per step), so the comparison of p is not of two unchanged copies.
  EXPECT_GT((a.p[kSteps] - a.p[0]).cwiseAbs().minCoeff(), 0.1 * kLr);
}

TEST(Adam, GradScaleEqualsScaledGradient) {
  check_grad_scale<double>();
  check_grad_scale<float>();
}

// AdamT<float> (AVX-512 loop) against AdamT<double> on the same float inputs, grad_scale 0.3.
// Both compute their constants (bias corrections, step size, (1 - b1) s, ...) in double; the
// ideal is real arithmetic with those double constants. float32 run, rounding factors of u32:
//   m term: c1 cast, product: 2; each later step: b1 cast, multiply, add: 2 x 3. m: gamma_8.
//   v term: c2 cast, g*g, product: 3; later steps 2 x 3. v: gamma_9.
//   update: sqrt (sqrt(1 + gamma_9) <= 1 + gamma_5) + rounding: 6; 1/sqrt(bc2) cast and multiply:
//           8; eps cast (on the eps term) and the add: 9; numerator step cast, multiply, m: 10;
//           division: 1. Update: gamma_20.
// The float64 run has the same structure without the casts: fewer than 20 factors of u64, so
// gamma_20(u64) bounds it (its moments: gamma_8(u64), gamma_9(u64)).
TEST(Adam, FloatMatchesDoubleWithinRoundingBound) {
  const AdamInputs in = make_inputs();
  const AdamRun f = run_adam<float>(in.p0, [&](int t) { return in.g[t]; }, kScale);
  const AdamRun d = run_adam<double>(
      in.p0, [&](int t) { return std::vector<double>(in.g[t].begin(), in.g[t].end()); }, kScale);
  const double u32 = 0x1p-24, u64 = 0x1p-53;
  const Eigen::VectorXd pb = p_bound(f, d, gamma_n(20, u32), gamma_n(20, u64), u32, u64);
  const double gm = gamma_n(8, u32) + gamma_n(8, u64), gv = gamma_n(9, u32) + gamma_n(9, u64);
  for (Eigen::Index i = 0; i < pb.size(); ++i) {
    EXPECT_LE(std::abs(f.m(i) - d.m(i)), gm * std::abs(d.m(i)) / (1 - gamma_n(8, u64)))
        << "m, element " << i;
    EXPECT_LE(std::abs(f.v(i) - d.v(i)), gv * d.v(i) / (1 - gamma_n(9, u64))) << "v, element " << i;
    EXPECT_LE(std::abs(f.p[kSteps](i) - d.p[kSteps](i)), pb(i)) << "p, element " << i;
  }
  EXPECT_GT((d.p[kSteps] - d.p[0]).cwiseAbs().minCoeff(), 0.1 * kLr);
}

}  // namespace
}  // namespace codesign::rl
