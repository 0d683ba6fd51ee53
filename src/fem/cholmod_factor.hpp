#pragma once
// A thin owner of one CHOLMOD Cholesky factorisation of a symmetric positive definite matrix
// with a fixed sparsity pattern (upper triangle, compressed sparse columns, sorted rows).
// analyse() once (fill-reducing ordering + symbolic factor), factorise() per new values.
//
// With dofs_per_node = 3 (nodal unknowns of a 3-D mesh, the matrix's 3×3 blocks dense), the
// ordering is AMD on the node graph with each node's three unknowns kept together, and after
// each factorisation the factor is copied into 3×3 blocks: solve() then runs its own block
// triangular solves (one row index per nine values instead of one per value), which measured
// about twice as fast as CHOLMOD's scalar simplicial solves here. CHOLMOD's own solve stays
// the fallback where the factor does not have that block structure.
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

  void analyse(int n, const std::vector<int>& colptr, const std::vector<int>& rowind, int dofs_per_node = 1);
  // False when the matrix is not positive definite (or CHOLMOD failed); never throws.
  bool factorise(const std::vector<double>& values);
  bool factorised() const;
  int size() const;
  // x = A⁻¹ b (b, x of length n; may alias).
  void solve(const double* b, double* x);
  // X = A⁻¹ B for several right-hand sides (columns).
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X);
  long factor_nonzeros() const;
  // Frees the analysis and the factor: the object is as newly constructed.
  void clear();
  // True when the last factorisation is solved by the 3×3 block solves.
  bool block_solves() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace codesign::fem
