#pragma once
// Lowest natural frequencies of a structure about its rest state: the generalised eigenproblem
// K phi = omega^2 M phi restricted to the free DOFs (Dirichlet DOFs removed), solved by
// shift-invert subspace iteration with a sparse LDLT factorisation of K_ff - sigma M_ff and a
// Rayleigh–Ritz step on each iterate.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace codesign::fem {

struct ModalOptions {
  int count = 4;              // number of modes wanted (lowest first)
  int extra = 6;              // guard vectors in the subspace (speeds convergence, separates clusters)
  double shift = 0.0;         // sigma: modes nearest sigma converge first (0: lowest)
  double tolerance = 1e-10;   // relative change of each wanted omega^2 between iterations
  int max_iterations = 300;
};

struct ModalResult {
  Eigen::VectorXd omega;      // circular frequencies [rad/s], ascending, size count
  Eigen::MatrixXd modes;      // full-size mode shapes (zero on fixed DOFs), M-normalised, one per column
  int iterations = 0;
  bool converged = false;
};

// K, M: symmetric n×n (M positive definite on the free DOFs; lumped or consistent).
// fixed: size n, true for a Dirichlet DOF. Throws std::invalid_argument on bad sizes and
// std::runtime_error if the shifted matrix cannot be factorised.
[[nodiscard]] ModalResult lowest_modes(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
                                       const std::vector<bool>& fixed, const ModalOptions& options = {});

}  // namespace codesign::fem
