#pragma once
// Static equilibrium of the co-rotational FEM body under dead loads, gravity and follower
// pressure, with per-DOF Dirichlet conditions: Newton–Raphson with load stepping and a
// residual-based backtracking line search.
//
// Equilibrium at the free DOFs:  r(x) = f_el(x) + λ (f_dead + m g + f_p(x)) = 0,
// f_el = Σ_e corotated_force (= −∂W/∂x, W the co-rotated energy), f_p the follower pressure
// force of the current geometry (fem/pressure.hpp: −p n A/3 per face node), λ the load factor
// stepped 1/n, 2/n, …, 1 (each step starts from the secant extrapolation of the last two
// equilibria). Tangents:
//  * Consistent: the exact Hessian of W, including the derivative of the polar rotation
//    (dR = R [w]×, (tr S · I − S) w = axial(Rᵀ dF − dFᵀ R)); quadratic convergence near the
//    solution, and it sees the stress (geometric) stiffness that governs large-deflection beams.
//    Where it is not positive definite (an iterate far from equilibrium under compression) the
//    step falls back to the co-rotational tangent.
//  * Corotational: Σ R K0 Rᵀ (the SOFA-style tangent of the stepper): always SPD, converges
//    linearly to the same equilibrium.
// The pressure load's own stiffness is left out of both (a quasi-Newton step; small for p ≪ E).
// Line search: regula falsi on s(α) = du·r(x + α du) (for conservative loads −dΠ/dα), which
// behaves for slender bodies where ‖r‖ itself is a poor merit function.
// Reaction: at a fixed DOF, the force the constraint exerts on the body, −(f_el + f_ext).
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "fem/mesh.hpp"
#include "fem/model.hpp"

namespace codesign::fem {

struct StaticLoads {
  Eigen::VectorXd dead;                                  // 3N nodal forces [µN] (empty = none)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();     // acceleration [mm/s²], times lumped mass
  std::vector<double> chamber_pressures_Pa;              // follower, per mesh chamber (add_pressure_forces)
};

enum class StaticTangent { Consistent, Corotational };

struct StaticOptions {
  int load_steps = 1;
  int max_iterations = 40;                 // Newton iterations per load step
  // Converged when ‖r_free‖ ≤ rel_tolerance · scale + abs_tolerance_uN + floor, where
  // scale = ‖f_ext,free‖ at the current load factor (‖element forces‖ if that is zero) and
  // floor = 64 ε_mach E sqrt(Σ_e (V_e ‖∇N_e‖)²) is the round-off level of the elastic forces;
  // or when a Newton increment is ≤ rel_tolerance · max |x − x_start| (residual at its round-off floor).
  double rel_tolerance = 1e-9;
  double abs_tolerance_uN = 0.0;
  StaticTangent tangent = StaticTangent::Consistent;
  bool line_search = true;
  // Adds shift · M_ff to the tangent (units 1/s²): removes rigid-body singularity when the
  // Dirichlet set does not (a self-equilibrated load). Does not change the equilibrium reached.
  double mass_shift = 0.0;
};

struct StaticResult {
  Eigen::VectorXd positions;       // 3N
  Eigen::VectorXd reaction;        // 3N, non-zero only on fixed DOFs [µN]
  double residual_norm = 0.0;      // ‖r_free‖ at the end [µN]
  double load_norm = 0.0;          // ‖f_ext,free‖ at full load [µN]
  int iterations = 0;              // total Newton iterations
  int fallbacks = 0;               // consistent → co-rotational tangent fallbacks
  bool converged = false;
};

// x0: start (3N, fixed DOFs hold their prescribed values); empty → rest positions.
// fixed: 3N flags. Throws std::invalid_argument on size mismatches.
[[nodiscard]] StaticResult solve_static(const Model& model, const StaticLoads& loads, const std::vector<bool>& fixed,
                                        const StaticOptions& options = {}, const Eigen::VectorXd& x0 = {});

// Building blocks (also used by the validation tests).
// Elastic nodal forces f_el(x) (3N).
[[nodiscard]] Eigen::VectorXd elastic_forces(const Model& model, const Eigen::VectorXd& x);
// Total co-rotated elastic energy W(x) [nJ].
[[nodiscard]] double elastic_energy(const Model& model, const Eigen::VectorXd& x);
// Element tangent −∂f_el/∂x of one tet at positions x: exact (consistent) or R K0 Rᵀ.
[[nodiscard]] Mat12 element_tangent(const Model& model, int tet, const Eigen::VectorXd& x, StaticTangent kind);
// Global tangent (3N × 3N, symmetric).
[[nodiscard]] Eigen::SparseMatrix<double> tangent_stiffness(const Model& model, const Eigen::VectorXd& x,
                                                            StaticTangent kind);
// Lumped mass as a sparse diagonal 3N × 3N matrix.
[[nodiscard]] Eigen::SparseMatrix<double> lumped_mass_matrix(const Model& model);
// 3N flags fixing every DOF of the base nodes (the clamp).
[[nodiscard]] std::vector<bool> clamped_base_dofs(const Model& model);

}  // namespace codesign::fem
