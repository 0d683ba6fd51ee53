#include "fem/modal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

namespace codesign::fem {

namespace {

using SpMat = Eigen::SparseMatrix<double>;

// Submatrix A(free, free) with `map` taking a full index to its free index (-1 if fixed).
SpMat restrict_to_free(const SpMat& A, const std::vector<int>& map, int n_free) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(A.nonZeros()));
  for (int col = 0; col < A.outerSize(); ++col) {
    const int jc = map[static_cast<std::size_t>(col)];
    if (jc < 0) continue;
    for (SpMat::InnerIterator it(A, col); it; ++it) {
      const int ir = map[static_cast<std::size_t>(it.row())];
      if (ir >= 0) trip.emplace_back(ir, jc, it.value());
    }
  }
  SpMat out(n_free, n_free);
  out.setFromTriplets(trip.begin(), trip.end());
  return out;
}

}  // namespace

ModalResult lowest_modes(const SpMat& K, const SpMat& M, const std::vector<bool>& fixed, const ModalOptions& options) {
  const Eigen::Index n = K.rows();
  if (K.cols() != n || M.rows() != n || M.cols() != n || static_cast<Eigen::Index>(fixed.size()) != n)
    throw std::invalid_argument("lowest_modes: K, M and fixed must all have the same size");
  if (options.count < 1) throw std::invalid_argument("lowest_modes: count must be >= 1");

  std::vector<int> map(static_cast<std::size_t>(n), -1);
  std::vector<int> free_to_full;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!fixed[static_cast<std::size_t>(i)]) {
      map[static_cast<std::size_t>(i)] = static_cast<int>(free_to_full.size());
      free_to_full.push_back(static_cast<int>(i));
    }
  const int nf = static_cast<int>(free_to_full.size());
  const int p = std::min(nf, options.count + std::max(0, options.extra));
  if (p < options.count) throw std::invalid_argument("lowest_modes: fewer free DOFs than requested modes");

  const SpMat Kf = restrict_to_free(K, map, nf);
  const SpMat Mf = restrict_to_free(M, map, nf);
  const SpMat A = Kf - options.shift * Mf;
  Eigen::SimplicialLDLT<SpMat> solver(A);
  if (solver.info() != Eigen::Success) throw std::runtime_error("lowest_modes: factorisation of K - sigma M failed");

  // Deterministic start: smooth, distinct columns (cos/sin of the DOF index) plus a ramp, which
  // project onto every low mode with non-negligible weight.
  Eigen::MatrixXd X(nf, p);
  for (int j = 0; j < p; ++j)
    for (int i = 0; i < nf; ++i) {
      const double t = static_cast<double>(i) / std::max(1, nf - 1);
      X(i, j) = std::cos((j + 1) * 1.7 * t + 0.3 * j) + 0.01 * ((i * 7919 + j * 104729) % 1000) / 1000.0;
    }

  ModalResult result;
  Eigen::VectorXd lambda_prev = Eigen::VectorXd::Constant(p, std::numeric_limits<double>::infinity());
  Eigen::VectorXd lambda(p);
  for (int iter = 1; iter <= options.max_iterations; ++iter) {
    const Eigen::MatrixXd MX = Mf * X;
    const Eigen::MatrixXd Y = solver.solve(MX);
    // Rayleigh–Ritz on span(Y).
    const Eigen::MatrixXd Kr = Y.transpose() * (Kf * Y);
    const Eigen::MatrixXd Mr = Y.transpose() * (Mf * Y);
    const Eigen::MatrixXd Krs = 0.5 * (Kr + Kr.transpose());
    const Eigen::MatrixXd Mrs = 0.5 * (Mr + Mr.transpose());
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(Krs, Mrs);
    if (ges.info() != Eigen::Success) throw std::runtime_error("lowest_modes: Rayleigh-Ritz eigen-solve failed");
    // Order by distance from the shift (ascending omega^2 for shift 0 with K SPD).
    std::vector<int> order(static_cast<std::size_t>(p));
    for (int j = 0; j < p; ++j) order[static_cast<std::size_t>(j)] = j;
    const Eigen::VectorXd ev = ges.eigenvalues();
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return std::abs(ev(a) - options.shift) < std::abs(ev(b) - options.shift);
    });
    Eigen::MatrixXd Q(p, p);
    for (int j = 0; j < p; ++j) {
      Q.col(j) = ges.eigenvectors().col(order[static_cast<std::size_t>(j)]);
      lambda(j) = ev(order[static_cast<std::size_t>(j)]);
    }
    X = Y * Q;  // M-orthonormal (Q^T Mr Q = I)
    result.iterations = iter;
    bool done = true;
    for (int j = 0; j < options.count; ++j)
      if (!(std::abs(lambda(j) - lambda_prev(j)) <= options.tolerance * std::abs(lambda(j)))) done = false;
    lambda_prev = lambda;
    if (done) {
      result.converged = true;
      break;
    }
  }

  // Return the wanted modes in ascending omega.
  std::vector<int> idx(static_cast<std::size_t>(options.count));
  for (int j = 0; j < options.count; ++j) idx[static_cast<std::size_t>(j)] = j;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return lambda(a) < lambda(b); });
  result.omega.resize(options.count);
  result.modes = Eigen::MatrixXd::Zero(n, options.count);
  for (int j = 0; j < options.count; ++j) {
    const int s = idx[static_cast<std::size_t>(j)];
    result.omega(j) = std::sqrt(std::max(0.0, lambda(s)));
    for (int i = 0; i < nf; ++i) result.modes(free_to_full[static_cast<std::size_t>(i)], j) = X(i, s);
  }
  return result;
}

}  // namespace codesign::fem
