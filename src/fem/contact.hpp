#pragma once
// Frictionless unilateral contact as a linear complementarity problem (LCP).
//
// Given gaps g (m) of the candidate points after the unconstrained step and the Delassus
// operator D (m×m, symmetric positive definite: D = dt² J A⁻¹ Jᵀ, how far each point moves per
// unit multiplier), find multipliers λ with
//     w = g + D λ ≥ 0,   λ ≥ 0,   wᵀ λ = 0.
// Solved by an active-set method (principal pivoting on the set of points held on the plate):
// the points in the active set are held exactly on the plate (w = 0) by solving D_AA λ_A = −g_A;
// a point with λ < 0 is released, the most penetrating free point is added. For SPD D the LCP
// has a unique solution; if pivoting has not finished after its iteration cap, projected
// Gauss–Seidel finishes the job and the result is accepted when its residual is small.
#include <vector>

#include <Eigen/Core>

namespace codesign::fem {

struct LcpResult {
  Eigen::VectorXd lambda;
  bool converged = false;
  int iterations = 0;
  double max_violation = 0.0;  // max(−min w, −min λ, max |w_i λ_i|/scale) at return
};

// `active_guess`: points believed active (warm start, may be empty). gap_tol: penetration
// accepted as "on the plate" [same unit as g].
LcpResult solve_contact_lcp(const Eigen::MatrixXd& D, const Eigen::VectorXd& g,
                            const std::vector<char>& active_guess, double gap_tol);

}  // namespace codesign::fem
