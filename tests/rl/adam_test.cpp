#include "rl/adam.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace codesign::rl
