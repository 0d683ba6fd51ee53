// The least-squares fit of the force estimator ε = c0 + c1·F + c2·θ (force_estimator.hpp):
// known coefficients recovered from synthetic samples to rounding, and degenerate samples
// refused with a message saying why.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/force_estimator.hpp"

namespace codesign::core {
namespace {

// Magnitudes like the whisker's: ε ~ 4e-4, −4.7e-6 per mN, a few 1e-4 per rad.
constexpr ForceEstimator kTrue{4.2e-4, -4.7e-6, 3.1e-4};

std::vector<ForceSample> synthetic(int n) {
  std::vector<ForceSample> s;
  for (int i = 0; i < n; ++i) {
    const double f = 5.0 + 0.7 * i + 3.0 * std::sin(i), th = 0.02 * std::cos(1.3 * i) + 0.001 * i;
    s.push_back({kTrue.c0 + kTrue.c1 * f + kTrue.c2 * th, f, th});
  }
  return s;
}

std::string refusal(const std::vector<ForceSample>& s) {
  try {
    fit_force_estimator(s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ForceEstimator, RecoversKnownCoefficientsToRounding) {
  const std::vector<ForceSample> s = synthetic(60);
  const double n = static_cast<double>(s.size()), u = std::numeric_limits<double>::epsilon() / 2;
  double mf = 0, mt = 0, max_f = 0, max_t = 0, max_e = 0;
  for (const ForceSample& x : s) {
    mf += x.force_mN / n, mt += x.theta_rad / n;
    max_f = std::max(max_f, std::abs(x.force_mN)), max_t = std::max(max_t, std::abs(x.theta_rad));
    max_e = std::max(max_e, std::abs(kTrue.c0) + std::abs(kTrue.c1 * x.force_mN) + std::abs(kTrue.c2 * x.theta_rad));
  }
  double sff = 0, stt = 0, sft = 0;
  for (const ForceSample& x : s)
    sff += (x.force_mN - mf) * (x.force_mN - mf), stt += (x.theta_rad - mt) * (x.theta_rad - mt),
        sft += (x.force_mN - mf) * (x.theta_rad - mt);
  const double sd_f = std::sqrt(sff / n), sd_t = std::sqrt(stt / n), rho = sft / std::sqrt(sff * stt);
  // The tolerance. In standardised variables x = (F − F̄)/sd_F, y = (θ − θ̄)/sd_θ the fit solves
  // R·b = r with R = [[1, ρ], [ρ, 1]], b = (c1·sd_F, c2·sd_θ), r = (mean x·ε, mean y·ε), and
  // ‖R⁻¹‖ = 1/(1 − |ρ|). Errors in r and R come from (i) the data: each ε is c0 + c1F + c2θ
  // rounded three times, |δε| ≤ 3u·E (E = max |c0| + |c1F| + |c2θ|), which moves r by at most
  // 3u·E (mean x² = 1); (ii) the means: F̄ and θ̄ carry n·u·max|F|, n·u·max|θ|, i.e. the
  // standardised values are off by n·u·max|F|/sd_F (resp. θ), which moves r by that times E and
  // R by that times 1 (|b| ≤ E too); (iii) the sums: n terms, n·u relative each. So
  //   |Δb| ≤ T = 4·n·u·(3 + max|F|/sd_F + max|θ|/sd_θ)·E / (1 − |ρ|)   (factor 4: the three
  // sources and a margin), and c0 = ε̄ − c1F̄ − c2θ̄ is off by ≤ T·(1 + |F̄|/sd_F + |θ̄|/sd_θ) + n·u·E.
  const double t = 4.0 * n * u * (3.0 + max_f / sd_f + max_t / sd_t) * max_e / (1.0 - std::abs(rho));
  const double t0 = t * (1.0 + std::abs(mf) / sd_f + std::abs(mt) / sd_t) + n * u * max_e;
  // The bound is tight enough to mean something: ≤ 1e-9 of each coefficient's effect.
  ASSERT_LT(t, 1e-9 * std::abs(kTrue.c1) * sd_f);
  ASSERT_LT(t, 1e-9 * std::abs(kTrue.c2) * sd_t);
  const ForceFit fit = fit_force_estimator(s);
  EXPECT_NEAR(fit.estimator.c1, kTrue.c1, t / sd_f);
  EXPECT_NEAR(fit.estimator.c2, kTrue.c2, t / sd_t);
  EXPECT_NEAR(fit.estimator.c0, kTrue.c0, t0);
  EXPECT_EQ(fit.samples, 60);
  EXPECT_GT(fit.r2, 1.0 - 1e-12);
  // The residual of ε is rounding (≤ 3u·E + the coefficients' errors), in mN divided by |c1|.
  EXPECT_LT(fit.rms_mN, (3.0 * u * max_e + 3.0 * t0) / std::abs(kTrue.c1));
  // F̂ inverts the model: F back from ε and θ.
  EXPECT_NEAR(fit.estimator.force_mN(s[7].strain, s[7].theta_rad), s[7].force_mN, 1e-6);
}

TEST(ForceEstimator, RefusesDegenerateSamples) {
  std::vector<ForceSample> s = synthetic(2);
  EXPECT_EQ(refusal(s), "force estimator fit: 2 samples; at least 3 are needed for the 3 coefficients (c0, c1, c2)");
  EXPECT_NE(refusal({}), "");
  // θ constant (a base that never turned): c2 cannot be told from c0.
  s = synthetic(20);
  for (ForceSample& x : s) x.theta_rad = 0.1, x.strain = kTrue.c0 + kTrue.c1 * x.force_mN + kTrue.c2 * 0.1;
  EXPECT_EQ(refusal(s), "force estimator fit: theta does not vary over the samples (theta constant)");
  // F an affine function of θ (a still plate: F follows the base alone).
  s = synthetic(20);
  for (ForceSample& x : s) x.force_mN = 3.0 + 100.0 * x.theta_rad, x.strain = kTrue.c0 + kTrue.c1 * x.force_mN;
  EXPECT_NE(refusal(s).find("F and theta are collinear over the samples"), std::string::npos) << refusal(s);
  // F constant.
  s = synthetic(20);
  for (ForceSample& x : s) x.force_mN = 20.0;
  EXPECT_EQ(refusal(s), "force estimator fit: F does not vary over the samples");
  // ε blind to F.
  s = synthetic(20);
  for (ForceSample& x : s) x.strain = kTrue.c0 + kTrue.c2 * x.theta_rad;
  EXPECT_NE(refusal(s).find("the strain does not depend on F"), std::string::npos) << refusal(s);
  // A non-finite reading.
  s = synthetic(20);
  s[4].strain = NAN;
  EXPECT_EQ(refusal(s), "force estimator fit: a sample is not finite");
}

}  // namespace
}  // namespace codesign::core
