#include "core/force_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace codesign::core {

namespace {

// A spread below this fraction of the values' own size is rounding, not information.
constexpr double kSpreadFloor = 1e-12;
// 1 − ρ² of F and θ below this: the centred 2×2 system has a condition number above ~4e9 and
// the split of ε's variation between F and θ keeps fewer than ~6 digits. Refused.
constexpr double kCollinearFloor = 1e-9;

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument("force estimator fit: " + why); }

}  // namespace

ForceFit fit_force_estimator(const std::vector<ForceSample>& samples) {
  const std::size_t n = samples.size();
  if (n < 3)
    refuse(std::to_string(n) + " samples; at least 3 are needed for the 3 coefficients (c0, c1, c2)");
  double me = 0.0, mf = 0.0, mt = 0.0, max_e = 0.0, max_f = 0.0, max_t = 0.0;
  for (const ForceSample& s : samples) {
    if (!std::isfinite(s.strain) || !std::isfinite(s.force_mN) || !std::isfinite(s.theta_rad))
      refuse("a sample is not finite");
    me += s.strain, mf += s.force_mN, mt += s.theta_rad;
    max_e = std::max(max_e, std::abs(s.strain));
    max_f = std::max(max_f, std::abs(s.force_mN));
    max_t = std::max(max_t, std::abs(s.theta_rad));
  }
  const double dn = static_cast<double>(n);
  me /= dn, mf /= dn, mt /= dn;
  // Centred sums (two passes: the means first, so no cancellation of large squares).
  double sff = 0.0, stt = 0.0, sft = 0.0, sfe = 0.0, ste = 0.0, see = 0.0;
  for (const ForceSample& s : samples) {
    const double f = s.force_mN - mf, t = s.theta_rad - mt, e = s.strain - me;
    sff += f * f, stt += t * t, sft += f * t, sfe += f * e, ste += t * e, see += e * e;
  }
  if (!(std::sqrt(sff / dn) > kSpreadFloor * max_f)) refuse("F does not vary over the samples");
  if (!(std::sqrt(stt / dn) > kSpreadFloor * max_t)) refuse("theta does not vary over the samples (theta constant)");
  const double one_minus_rho2 = 1.0 - sft * sft / (sff * stt);
  if (!(one_minus_rho2 > kCollinearFloor))
    refuse("F and theta are collinear over the samples (1 - rho^2 = " + std::to_string(one_minus_rho2) +
           "); their effects on the strain cannot be told apart");
  const double det = sff * stt * one_minus_rho2;
  ForceFit out;
  ForceEstimator& c = out.estimator;
  c.c1 = (sfe * stt - ste * sft) / det;
  c.c2 = (ste * sff - sfe * sft) / det;
  c.c0 = me - c.c1 * mf - c.c2 * mt;
  if (!(std::abs(c.c1) * std::sqrt(sff / dn) > kSpreadFloor * max_e))
    refuse("the strain does not depend on F (c1 = " + std::to_string(c.c1) + "): F cannot be estimated from it");
  double ss_res = 0.0;
  for (const ForceSample& s : samples) {
    const double r = s.strain - (c.c0 + c.c1 * s.force_mN + c.c2 * s.theta_rad);
    ss_res += r * r;
  }
  out.r2 = see > 0.0 ? 1.0 - ss_res / see : 1.0;
  out.rms_mN = std::sqrt(ss_res / dn) / std::abs(c.c1);
  out.samples = static_cast<int>(n);
  return out;
}

}  // namespace codesign::core
