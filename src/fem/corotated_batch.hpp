#pragma once
// The element loops of the co-rotational tetrahedron over a whole mesh: the force pass (F, polar
// rotation, elastic force, K(R) u) and the stiffness product y += K(R) u. Element data are
// stored lane by lane (kLanes elements per group, structure of arrays), so the compiler
// vectorises across elements instead of inside one element's 3×3 algebra.
// The same quantities as deformation_gradient(), polar_rotation(), corotated_force() and
// corotated_stiffness_times() element by element, in another order of operations
// (tests/fem/corotated_batch_test.cpp compares them).
#include <vector>

#include <Eigen/Core>

#include "fem/corotational_tet.hpp"
#include "fem/mesh.hpp"

namespace codesign::fem {

class CorotatedBatch {
 public:
  static constexpr int kLanes = 8;

  CorotatedBatch() = default;
  CorotatedBatch(const std::vector<Tet>& tets, const std::vector<TetRest>& rest, double mu, double lambda);

  // The rotation of element e (as the force pass computes it).
  void set_rotation(int e, const Eigen::Matrix3d& R) {
    const int b = e / kLanes, l = e % kLanes;
    double* r = &rot_[static_cast<std::size_t>(b) * 9 * kLanes];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[(3 * i + j) * kLanes + l] = R(i, j);
  }
  // y += K(R) u over all elements (u, y: all DOFs, 3 per node).
  void add_stiffness_times(const Eigen::VectorXd& u, Eigen::VectorXd& y) const;

  // The element pass of a force evaluation at positions x: per element F, its polar rotation
  // (warm-started from q, to `tolerance` as polar_rotation() defines it), written to q, rot and
  // this object's own copy; f += elastic forces, and ku += K(R) u when u is given.
  // Returns -1, or the first element with det F <= 0 or not finite (its det in *bad_det); then
  // f, ku, q and rot are partly updated and the caller must treat the state as failed.
  int elastic_pass(const Eigen::VectorXd& x, double tolerance, std::vector<Eigen::Quaterniond>& q,
                   std::vector<Eigen::Matrix3d>& rot, Eigen::VectorXd& f, const Eigen::VectorXd* u,
                   Eigen::VectorXd* ku, double* bad_det);

 private:
  int elements_ = 0, groups_ = 0;
  double mu_ = 0.0, lambda_ = 0.0;
  std::vector<int> dof_;      // [group][node a][lane]: 3 × node index (padding lanes: 0)
  std::vector<double> grad_;  // [group][row a-1 (1..3)][column][lane]: ∇N_a (padding: 0)
  std::vector<double> vol_;   // [group][lane] (padding: 0)
  std::vector<double> rot_;   // [group][3i+j][lane]
};

}  // namespace codesign::fem
