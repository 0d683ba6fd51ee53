#pragma once
// Co-rotational linear tetrahedron (small strain, large rotation).
//
// For an element with rest nodes X_a and current nodes x_a (a = 0..3):
//   deformation gradient  F = Ds · Dm⁻¹,  Ds = [x1−x0, x2−x0, x3−x0], Dm likewise from X;
//   rotation              R = polar(F) (F = R·S, S symmetric positive definite);
//   strain                ε = S − I  (= sym(Rᵀ F) − I), linear isotropic stress σ = 2μ ε + λ tr(ε) I;
//   energy                W = V (μ ‖ε‖² + λ/2 tr(ε)²);
//   nodal forces          f_a = −V · R σ · ∇N_a  (= −∂W/∂x_a exactly, since R is the polar factor);
//   stiffness             K_e = R K0 Rᵀ (blockwise 3×3), K0 = V Bᵀ C B is the rest stiffness.
// K_e is the SOFA-style co-rotational tangent: it drops the derivative of R, so it equals the
// exact Hessian of W only at rigidly rotated (strain-free) states and differs by O(‖ε‖·‖K0‖)
// otherwise. The rotation is the polar factor (not SOFA's QR variant), computed by a warm-started
// warm-started Newton iteration that converges to the polar rotation (see polar_rotation()).
#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace codesign::fem {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat43 = Eigen::Matrix<double, 4, 3>;

// Per-element rest data, computed once.
struct TetRest {
  Eigen::Matrix3d dm_inv;  // Dm⁻¹
  Mat43 grad;              // rows: ∇N_a in the rest configuration [1/mm]
  double volume = 0.0;     // rest volume [mm³], > 0 for a positively oriented tet
};

// Throws std::invalid_argument if the tet is degenerate or negatively oriented.
TetRest make_tet_rest(const std::array<Eigen::Vector3d, 4>& X);

// F = Ds Dm⁻¹ of the current positions.
Eigen::Matrix3d deformation_gradient(const TetRest& rest, const std::array<Eigen::Vector3d, 4>& x);

// Rotation part of the polar decomposition F = R S (det F > 0 assumed): Newton iteration on
// the symmetry of Rᵀ F, warm-started from `guess` (pass the previous step's rotation; identity
// is fine), with a Müller et al. (2016) step where Newton's matrix is indefinite. Stops when the
// remaining angle error is below `tolerance` [rad] (after a Newton step of size |ω| the error is
// O(|ω|²)), or after 60 iterations. If `rotation` is given, it receives the returned
// quaternion's rotation matrix (exactly its toRotationMatrix(), computed once inside).
Eigen::Quaterniond polar_rotation(const Eigen::Matrix3d& F, const Eigen::Quaterniond& guess, double tolerance,
                                  Eigen::Matrix3d* rotation = nullptr);
// Same, converged to 1e-14 rad.
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F, const Eigen::Matrix3d& guess);
// Reference implementation through the SVD (used by tests).
Eigen::Matrix3d polar_rotation_svd(const Eigen::Matrix3d& F);

// Rest stiffness K0 = V Bᵀ C B, 12×12, DOF order (node a, component c) → 3a + c.
Mat12 rest_stiffness(const TetRest& rest, double mu, double lambda);

// Elastic energy and forces at positions x with rotation R (the polar factor of F).
double corotated_energy(const TetRest& rest, const Eigen::Matrix3d& F, const Eigen::Matrix3d& R,
                        double mu, double lambda);
// Forces f_a on the four nodes, as a 12-vector (node-major).
Vec12 corotated_force(const TetRest& rest, const Eigen::Matrix3d& F, const Eigen::Matrix3d& R,
                      double mu, double lambda);
// Co-rotated stiffness R K0 Rᵀ (blockwise).
Mat12 corotated_stiffness(const Mat12& k0, const Eigen::Matrix3d& R);
// y = (R K0 Rᵀ) u without forming the matrix, through the stress form:
// dF = Σ u_a ∇N_aᵀ, dε = sym(Rᵀ dF), y_a = V R (2μ dε + λ tr dε I) ∇N_a.
Vec12 corotated_stiffness_times(const TetRest& rest, const Eigen::Matrix3d& R, const Vec12& u,
                                double mu, double lambda);

}  // namespace codesign::fem
