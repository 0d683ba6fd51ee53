#pragma once
// A thin owner of one CHOLMOD Cholesky factorisation of a symmetric positive definite matrix
// with a fixed sparsity pattern (upper triangle, compressed sparse columns, sorted rows).
// analyse() once (fill-reducing ordering + symbolic factor), factorise() per new values.
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace codesign::fem {

class CholmodFactor {
 public:
  CholmodFactor();
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  void analyse(int n, const std::vector<int>& colptr, const std::vector<int>& rowind);
  // False when the matrix is not positive definite (or CHOLMOD failed); never throws.
  bool factorise(const std::vector<double>& values);
  bool factorised() const;
  int size() const;
  // x = A⁻¹ b (b, x of length n; may alias).
  void solve(const double* b, double* x);
  // X = A⁻¹ B for several right-hand sides (columns).
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X);
  long factor_nonzeros() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace codesign::fem
