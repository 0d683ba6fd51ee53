#pragma once
// Assembly of the implicit-Euler system matrix A = c_m M + c_k K(x) on the free DOFs
// (all nodes except the clamped ones), upper triangle in CSC form for CHOLMOD.
// K(x) = Σ_e R_e K0_e R_eᵀ + fibre spring tangents; M lumped.
#include <vector>

#include <Eigen/Core>

#include "fem/model.hpp"

namespace codesign::fem {

class SystemMatrix {
 public:
  // free_index[node] = index among free nodes, or −1 for a clamped node.
  SystemMatrix(const Model& model, const std::vector<int>& free_index);

  int dofs() const { return 3 * free_nodes_; }
  const std::vector<int>& colptr() const { return colptr_; }
  const std::vector<int>& rowind() const { return rowind_; }
  std::vector<double>& values() { return values_; }

  void clear();
  // Adds the 3×3 block B at (free node i rows, free node j cols) — and its transpose at (j, i):
  // only the upper triangle is stored, so add each unordered pair once (i == j allowed).
  void add_block(int fi, int fj, const Eigen::Matrix3d& B);
  void add_diagonal(int fi, double d);

 private:
  int free_nodes_ = 0;
  std::vector<std::vector<int>> lower_;  // per column node: neighbour free nodes i < j, sorted
  std::vector<int> colptr_, rowind_;
  std::vector<double> values_;
  int slot(int fi, int fj) const;        // fi < fj: position of fi in lower_[fj]
};

// Fills `a` with c_m M + c_k K(x) from per-tet rotations and the fibres' current tangents.
void assemble_system(const Model& model, const std::vector<int>& free_index,
                     const std::vector<Eigen::Matrix3d>& rotations, const Eigen::VectorXd& x,
                     double c_m, double c_k, SystemMatrix& a);

// Fibre spring force on end a (−force on end b) at positions x [µN]: −k (ℓ − ℓ0) n, zero when
// slack (ℓ ≤ ℓ0) for tension-only fibres (model.fibres_tension_only).
Eigen::Vector3d fibre_force(const Model& model, const FibreSpring& s, const Eigen::VectorXd& x);
// Its tangent (3×3, positive semi-definite): k n nᵀ + k max(0, 1 − ℓ0/ℓ)(I − n nᵀ); zero when
// a tension-only fibre is slack. (The geometric part is clamped at 0 under compression.)
Eigen::Matrix3d fibre_tangent(const Model& model, const FibreSpring& s, const Eigen::VectorXd& x);

}  // namespace codesign::fem
