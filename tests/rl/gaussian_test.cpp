#include "rl/gaussian.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

#include "fd_check.hpp"

namespace codesign::rl {
namespace {

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;
using RowVec = Eigen::RowVectorXd;

TEST(Gaussian, SampleWithTheStreamsDrawsIsTheSample) {
  Mat mean(3, 4);
  mean << 0.1, -0.2, 0.3, 0.4, 1.0, 2.0, -3.0, 0.5, 0.0, 0.25, -0.75, 1.5;
  Vec log_std(3);
  log_std << -1.0, 0.0, 0.5;
  Rng a(11), b(11), c(11);
  const Mat z = standard_normals(3, 4, b);
  EXPECT_EQ(gaussian_sample<double>(mean, log_std, a), gaussian_sample_with<double>(mean, log_std, z));
  EXPECT_EQ(a.save(), b.save());
  // Column by column: draw k is row k % 3 of column k / 3.
  for (Eigen::Index k = 0; k < 12; ++k) EXPECT_EQ(z(k % 3, k / 3), c.normal()) << "draw " << k;
  EXPECT_THROW(gaussian_sample_with<double>(mean, log_std, Mat::Zero(3, 3)), std::invalid_argument);
}

TEST(Gaussian, LogProbAndEntropyMatchClosedForm) {
  Mat mean(2, 1);
  mean << 0.5, -1.0;
  Vec log_std(2);
  log_std << 0.0, std::log(2.0);
  Mat a(2, 1);
  a << 1.5, 0.0;
  // dim 0: z = 1, sigma 1; dim 1: z = 0.5, sigma 2.
  const double expected = -0.5 * 1.0 - 0.0 - 0.5 * 0.25 - std::log(2.0) -
                          std::log(2 * std::numbers::pi);
  EXPECT_NEAR(gaussian_log_prob<double>(mean, log_std, a)(0), expected, 1e-14);
  EXPECT_NEAR(gaussian_entropy<double>(log_std),
              1.0 + std::log(2 * std::numbers::pi) + std::log(2.0), 1e-14);
}

TEST(Gaussian, LogProbGradientsMatchFiniteDifferences) {
  Rng rng(11);
  const int A = 3, B = 4;
  Mat mean(A, B), actions(A, B);
  for (int j = 0; j < B; ++j)
    for (int i = 0; i < A; ++i) {
      mean(i, j) = rng.normal();
      actions(i, j) = rng.normal();
    }
  Vec log_std(A);
  log_std << -0.3, 0.1, 0.4;
  RowVec upstream(B);
  for (int j = 0; j < B; ++j) upstream(j) = rng.normal();  // L = upstream . log_prob

  Mat d_mean;
  Vec d_log_std = Vec::Zero(A);
  gaussian_log_prob_backward<double>(mean, log_std, actions, upstream, d_mean, d_log_std);

  Vec mean_flat = mean.reshaped();
  auto loss_mean = [&] {
    return upstream.dot(
        gaussian_log_prob<double>(mean_flat.reshaped(A, B), log_std, actions));
  };
  test::expect_gradient_matches(mean_flat, loss_mean, d_mean.reshaped(), "d log_prob / d mean");
  auto loss_std = [&] { return upstream.dot(gaussian_log_prob<double>(mean, log_std, actions)); };
  test::expect_gradient_matches(log_std, loss_std, d_log_std, "d log_prob / d log_std");
}

TEST(Gaussian, EntropyGradientMatchesFiniteDifferences) {
  Vec log_std(2);
  log_std << -0.5, 0.7;
  Vec g = Vec::Zero(2);
  gaussian_entropy_backward<double>(1.0, g);
  test::expect_gradient_matches(log_std, [&] { return gaussian_entropy<double>(log_std); }, g,
                                "d entropy / d log_std");
}

TEST(Gaussian, SamplesHaveTheRequestedMeanAndStd) {
  Rng rng(2);
  const int n = 100000;
  Mat mean = Mat::Constant(1, n, 3.0);
  Vec log_std = Vec::Constant(1, std::log(0.5));
  const Mat s = gaussian_sample<double>(mean, log_std, rng);
  const double m = s.mean();
  const double sd = std::sqrt((s.array() - m).square().sum() / (n - 1));
  // Standard error of the mean: 0.5 / sqrt(1e5) = 1.6e-3; of the std: 0.5 / sqrt(2e5) = 1.1e-3.
  // Five standard errors.
  EXPECT_NEAR(m, 3.0, 5 * 1.6e-3);
  EXPECT_NEAR(sd, 0.5, 5 * 1.1e-3);
}

}  // namespace
}  // namespace codesign::rl
