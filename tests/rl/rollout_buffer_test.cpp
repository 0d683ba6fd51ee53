#include "rl/rollout_buffer.hpp"

#include <stdexcept>

#include <gtest/gtest.h>

namespace codesign::rl {
namespace {

using RowVec = Eigen::RowVectorXf;

RowVec row(float a, float b) {
  RowVec r(2);
  r << a, b;
  return r;
}

// 3 steps x 2 envs, gamma 0.9, lambda 0.8 (gamma lambda = 0.72), worked by hand:
// env 0: r = (1, 2, 3), V = (0.5, 1.0, 1.5), starts (1, 0, 0), last V 2.0, not done.
//   t2: delta = 3 + 0.9 * 2.0 - 1.5 = 3.3                 A = 3.3
//   t1: delta = 2 + 0.9 * 1.5 - 1.0 = 2.35                A = 2.35 + 0.72 * 3.3   = 4.726
//   t0: delta = 1 + 0.9 * 1.0 - 0.5 = 1.4                 A = 1.4  + 0.72 * 4.726 = 4.80272
// env 1: r = (1, 1, 1), V = (0.2, 0.4, 0.6), starts (1, 0, 1) (an episode ended at t1), last V
//   5.0, done at the last step (so the 5.0 must NOT be used).
//   t2: delta = 1 - 0.6 = 0.4 (done)                      A = 0.4
//   t1: delta = 1 - 0.4 = 0.6 (next obs starts an episode) A = 0.6 (no carry from t2)
//   t0: delta = 1 + 0.9 * 0.4 - 0.2 = 1.16                A = 1.16 + 0.72 * 0.6   = 1.592
// Float32 arithmetic on values <= 5 over ~10 operations: error <= 10 * 5 * 2^-24 < 3e-6.
TEST(RolloutBuffer, GaeMatchesHandComputedValuesAcrossEpisodeBoundaries) {
  RolloutBuffer buf(3, 2, 1, 1);
  const Eigen::MatrixXf obs = Eigen::MatrixXf::Zero(1, 2), act = Eigen::MatrixXf::Zero(1, 2);
  const RowVec lp = row(0, 0);
  buf.add(obs, act, row(1, 1), row(1, 1), row(0.5f, 0.2f), lp);
  buf.add(obs, act, row(2, 1), row(0, 0), row(1.0f, 0.4f), lp);
  buf.add(obs, act, row(3, 1), row(0, 1), row(1.5f, 0.6f), lp);
  ASSERT_TRUE(buf.full());
  buf.compute_returns_and_advantage(row(2.0f, 5.0f), row(0, 1), 0.9, 0.8);

  const float expected_adv[3][2] = {{4.80272f, 1.592f}, {4.726f, 0.6f}, {3.3f, 0.4f}};
  const float values[3][2] = {{0.5f, 0.2f}, {1.0f, 0.4f}, {1.5f, 0.6f}};
  for (int t = 0; t < 3; ++t)
    for (int e = 0; e < 2; ++e) {
      EXPECT_NEAR(buf.advantages()(t * 2 + e), expected_adv[t][e], 3e-6) << t << "," << e;
      EXPECT_NEAR(buf.returns()(t * 2 + e), expected_adv[t][e] + values[t][e], 3e-6);
    }
}

TEST(RolloutBuffer, RejectsOverfillAndEarlyGae) {
  RolloutBuffer buf(1, 2, 1, 1);
  const Eigen::MatrixXf z = Eigen::MatrixXf::Zero(1, 2);
  EXPECT_THROW(buf.compute_returns_and_advantage(row(0, 0), row(0, 0), 0.9, 0.9),
               std::logic_error);
  buf.add(z, z, row(0, 0), row(1, 1), row(0, 0), row(0, 0));
  EXPECT_THROW(buf.add(z, z, row(0, 0), row(1, 1), row(0, 0), row(0, 0)), std::logic_error);
  buf.reset();
  EXPECT_FALSE(buf.full());
}

}  // namespace
}  // namespace codesign::rl
