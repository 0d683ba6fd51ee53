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
#include <Eigen/Geometry>

#include "fem/corotational_tet.hpp"
#include "fem/mesh.hpp"

namespace codesign::fem {

class CorotatedBatch {
 public:
  static constexpr int kLanes = 8;

  // The element rotations, lane by lane: the one store of them in the simulator. Per element
  // its polar rotation R (as the last force pass computed it, or as set) and the same rotation
  // as a unit quaternion, the warm start of the next pass's polar iteration. A value: copied
  // into snapshots and put back whole.
  struct Rotations {
    std::vector<double> q;  // [group][w, x, y, z][lane] (padding lanes: identity)
    std::vector<double> R;  // [group][3i+j][lane] (padding lanes: identity)
    bool operator==(const Rotations&) const = default;
  };

  CorotatedBatch() = default;
  CorotatedBatch(const std::vector<Tet>& tets, const std::vector<TetRest>& rest, double mu, double lambda);

  // Every element's rotation set to G (quaternion Eigen::Quaterniond(G), matrix G itself).
  void set_all_rotations(const Eigen::Matrix3d& G);
  // Every element's matrix set to G, the quaternions (warm starts) kept.
  void set_all_rotation_matrices(const Eigen::Matrix3d& G);
  // The rotation of element e, as a matrix and as a unit quaternion (inline: the simulator's
  // node rotations read every element's quaternion once per fast step).
  Eigen::Matrix3d rotation(int e) const;
  Eigen::Quaterniond quaternion(int e) const {
    const std::size_t b = static_cast<std::size_t>(e) / kLanes, l = static_cast<std::size_t>(e) % kLanes;
    const double* q = &rot_.q[b * 4 * kLanes];
    return Eigen::Quaterniond(q[0 * kLanes + l], q[1 * kLanes + l], q[2 * kLanes + l], q[3 * kLanes + l]);
  }
  // All matrices, element by element (for the assembly of a system matrix).
  std::vector<Eigen::Matrix3d> rotation_matrices() const;
  const Rotations& rotations() const { return rot_; }
  // Puts back rotations taken from a batch of the same mesh (throws std::invalid_argument
  // when the sizes differ).
  void set_rotations(const Rotations& r);

  // y += K(R) u over all elements (u, y: all DOFs, 3 per node).
  void add_stiffness_times(const Eigen::VectorXd& u, Eigen::VectorXd& y) const;

  // The element pass of a force evaluation at positions x: per element F and its polar
  // rotation (warm-started from the stored quaternion, to `tolerance` as polar_rotation()
  // defines it), stored; f += elastic forces, and ku += K(R) u when u is given.
  // Returns -1, or the first element with det F <= 0 or not finite (its det in *bad_det); then
  // f, ku and the rotations are partly updated and the caller must treat the state as failed.
  int elastic_pass(const Eigen::VectorXd& x, double tolerance, Eigen::VectorXd& f, const Eigen::VectorXd* u,
                   Eigen::VectorXd* ku, double* bad_det);

 private:
  int elements_ = 0, groups_ = 0;
  double mu_ = 0.0, lambda_ = 0.0;
  std::vector<int> dof_;      // [group][node a][lane]: 3 × node index (padding lanes: 0)
  std::vector<double> grad_;  // [group][row a-1 (1..3)][column][lane]: ∇N_a (padding: 0)
  std::vector<double> vol_;   // [group][lane] (padding: 0)
  Rotations rot_;
};

}  // namespace codesign::fem
