#pragma once
// Central finite differences for the gradient checks (float64).
//
// Error bound used by every check: for f with |f| <= F and third derivative <= D near x, the
// central difference (f(x+h) - f(x-h)) / 2h differs from f'(x) by at most
//   h^2 D / 6  (truncation)  +  eps F / h  (rounding of the two evaluations, eps = 2^-52).
// With h = 1e-5 and F, D <= 100 (small tanh networks with unit-scale inputs, losses of order 1):
//   1e-10 * 100 / 6 + 2.2e-16 * 100 / 1e-5  ~  1.7e-9 + 2.2e-9  <  5e-9.
// The checks allow kFdTolerance = 1e-6 * (1 + |g|), a margin of ~200 over that bound, while any
// real error in a backward pass (a missing term, a wrong sign, a transposed index) changes a
// gradient entry by O(|g|) and cannot pass.
#include <cmath>
#include <functional>

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace codesign::rl::test {

inline constexpr double kFdStep = 1e-5;
inline constexpr double kFdRelTolerance = 1e-6;

// Checks `analytic` against central differences of f over every entry of x (modified in place
// and restored).
inline void expect_gradient_matches(Eigen::Ref<Eigen::VectorXd> x,
                                    const std::function<double()>& f,
                                    const Eigen::VectorXd& analytic, const char* what) {
  ASSERT_EQ(analytic.size(), x.size()) << what;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double x0 = x(i);
    x(i) = x0 + kFdStep;
    const double fp = f();
    x(i) = x0 - kFdStep;
    const double fm = f();
    x(i) = x0;
    const double fd = (fp - fm) / (2 * kFdStep);
    EXPECT_NEAR(analytic(i), fd, kFdRelTolerance * (1 + std::abs(fd)))
        << what << " entry " << i;
  }
}

}  // namespace codesign::rl::test
