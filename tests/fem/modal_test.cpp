// The modal solver on a problem with a closed-form spectrum: a fixed–free chain of n equal
// springs k and masses m has omega_j = 2 sqrt(k/m) sin((2j − 1) π / (2(2n + 1))), j = 1, 2, …
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/SparseCore>

#include "analytic.hpp"
#include "fem/modal.hpp"

namespace {

using namespace codesign::fem;

TEST(ModalSolver, SpringChainSpectrumAndMassNormalisation) {
  const int n = 300;
  const double k = 3.0, m = 2.0;
  std::vector<Eigen::Triplet<double>> tk, tm;
  for (int e = 0; e < n; ++e) {
    tk.emplace_back(e, e, k);
    tk.emplace_back(e + 1, e + 1, k);
    tk.emplace_back(e, e + 1, -k);
    tk.emplace_back(e + 1, e, -k);
  }
  for (int i = 0; i <= n; ++i) tm.emplace_back(i, i, m);
  Eigen::SparseMatrix<double> K(n + 1, n + 1), M(n + 1, n + 1);
  K.setFromTriplets(tk.begin(), tk.end());
  M.setFromTriplets(tm.begin(), tm.end());
  std::vector<bool> fixed(static_cast<std::size_t>(n + 1), false);
  fixed[0] = true;
  ModalOptions opt;
  opt.count = 5;
  const ModalResult r = lowest_modes(K, M, fixed, opt);
  ASSERT_TRUE(r.converged);
  for (int j = 0; j < opt.count; ++j) {
    const double exact =
        2.0 * std::sqrt(k / m) * std::sin((2 * j + 1) * validation::kPi / (2.0 * (2 * n + 1)));
    // Converged to 1e-10 in omega² (options.tolerance) → ~1e-10 relative in omega.
    EXPECT_NEAR(r.omega(j) / exact, 1.0, 1e-9) << j;
    EXPECT_NEAR(r.modes(0, j), 0.0, 0.0);  // fixed DOF
    EXPECT_NEAR(r.modes.col(j).dot(M * r.modes.col(j)), 1.0, 1e-9);
    // Eigen-residual ‖K φ − ω² M φ‖ on the free DOFs, relative to ‖K φ‖.
    Eigen::VectorXd res = K * r.modes.col(j) - r.omega(j) * r.omega(j) * (M * r.modes.col(j));
    res[0] = 0.0;
    EXPECT_LT(res.norm(), 1e-6 * (K * r.modes.col(j)).norm()) << j;
  }
}

TEST(ModalSolver, RejectsBadSizes) {
  Eigen::SparseMatrix<double> K(3, 3), M(3, 3);
  EXPECT_THROW((void)lowest_modes(K, M, std::vector<bool>(2, false)), std::invalid_argument);
}

}  // namespace
