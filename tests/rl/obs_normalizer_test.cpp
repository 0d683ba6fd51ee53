// Running observation statistics (SB3's RunningMeanStd) against the moments of the pooled data
// computed directly, and the frozen transform.
#include <gtest/gtest.h>

#include <cmath>

#include "rl/obs_normalizer.hpp"
#include "rl/rng.hpp"

namespace codesign::rl {
namespace {

TEST(RunningObsStats, BatchesMergeIntoThePooledMomentsWithTheInitialPrior) {
  // Three batches of 2-component observations with different means and spreads.
  Rng rng(11);
  std::vector<Eigen::MatrixXd> batches;
  for (int b : {5, 1, 12}) {
    Eigen::MatrixXd x(2, b);
    for (Eigen::Index j = 0; j < b; ++j) x.col(j) << 3.0 + 0.5 * rng.normal(), -0.01 + 1e-4 * rng.normal();
    batches.push_back(x);
  }
  RunningObsStats s(2);
  for (const auto& x : batches) s.update(x);
  // The same moments in one pass: the prior is a weight of 1e-4 at mean 0 with variance 1.
  const double prior = 1e-4;
  double n = prior;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const auto& x : batches) n += static_cast<double>(x.cols()), sum += x.rowwise().sum();
  const Eigen::Vector2d mean = sum / n;
  Eigen::Vector2d m2 = prior * (Eigen::Vector2d::Ones() + mean.cwiseProduct(mean));
  for (const auto& x : batches) m2 += (x.colwise() - mean).array().square().rowwise().sum().matrix();
  const Eigen::Vector2d var = m2 / n;
  EXPECT_DOUBLE_EQ(s.count, n);
  // Both are sums of 18 terms of size |x|: a few ulps of relative difference at most.
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(s.mean[i], mean[i], 1e-13 * std::abs(mean[i])) << i;
    EXPECT_NEAR(s.var[i], var[i], 1e-10 * var[i]) << i;
  }
}

TEST(RunningObsStats, FrozenTransformScalesAndClips) {
  RunningObsStats s(2);
  s.mean << 1.0, 0.0;
  s.var << 4.0, 1e-6;
  const ObsNormalization n = s.frozen();
  Eigen::MatrixXd obs(2, 2);
  obs << 3.0, 1.0, 1e-3, 1.0;  // second component: 1 / sqrt(1e-6 + 1e-8) ≈ 995 → clipped to 10
  const Eigen::MatrixXd z = normalize_columns(n, obs);
  EXPECT_NEAR(z(0, 0), 2.0 / std::sqrt(4.0 + 1e-8), 1e-15);
  EXPECT_NEAR(z(0, 1), 0.0, 1e-15);
  EXPECT_NEAR(z(1, 0), 1e-3 / std::sqrt(1e-6 + 1e-8), 1e-12);
  EXPECT_EQ(z(1, 1), 10.0);
}

TEST(RunningObsStats, RejectsABatchOfTheWrongSize) {
  RunningObsStats s(3);
  EXPECT_THROW(s.update(Eigen::MatrixXd::Zero(2, 4)), std::invalid_argument);
  EXPECT_THROW(s.update(Eigen::MatrixXd::Zero(3, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace codesign::rl
