#pragma once
// Closed-form (or quasi-closed-form) reference answers that the FEM validation tests compare with.
// Nothing here depends on the FEM code: these are textbook solid/structural mechanics results.
// Units are whatever the caller uses consistently (the project uses mm, g, s -> µN, Pa).
#include <cmath>

namespace codesign::fem::validation {

inline constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Solid circular cross-section.
// ---------------------------------------------------------------------------------------------
[[nodiscard]] inline double circle_area(double r) { return kPi * r * r; }
[[nodiscard]] inline double circle_second_moment(double r) { return kPi * r * r * r * r / 4.0; }

// Cowper's (1966) shear coefficient of a solid circular section: kappa = 6(1+nu)/(7+6nu).
[[nodiscard]] inline double circle_shear_coefficient(double nu) { return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu); }

// ---------------------------------------------------------------------------------------------
// Small-load cantilever (clamped at x = 0, transverse tip load P at x = L).
// ---------------------------------------------------------------------------------------------
// Euler–Bernoulli: delta = P L^3 / (3 E I).
[[nodiscard]] double cantilever_tip_deflection_eb(double P, double L, double E, double I);

// Timoshenko: delta = P L^3 / (3 E I) + P L / (kappa G A), G = E / (2(1+nu)), solid circle of radius r.
[[nodiscard]] double cantilever_tip_deflection_timoshenko(double P, double L, double E, double nu, double r);

// ---------------------------------------------------------------------------------------------
// Large-deflection cantilever under a dead (direction-fixed) transverse tip load: the elastica of
// Bisshopp & Drucker (1945). Inextensible, shear-rigid rod; load parameter a2 = P L^2 / (E I).
// With theta the rod slope and theta0 the tip slope, k^2 = (1 + sin theta0)/2,
// phi1 = asin(1/(k sqrt 2)):
//   sqrt(a2)           = K(k) - F(phi1, k)
//   x_tip / L          = sqrt(2 sin theta0) / sqrt(a2)
//   y_tip / L          = 1 - 2 (E(k) - E(phi1, k)) / sqrt(a2)
// Solved for k by bisection (the left side is monotone in k).
// ---------------------------------------------------------------------------------------------
struct ElasticaTip {
  double horizontal_ratio;  // (L - x_tip) / L : shortening of the projection on the undeformed axis
  double vertical_ratio;    // y_tip / L       : deflection along the load
  double tip_angle;         // theta0 [rad]
};
[[nodiscard]] ElasticaTip bisshopp_drucker(double load_parameter);

// ---------------------------------------------------------------------------------------------
// Lamé thick-walled cylinder, inner radius a, outer radius b, internal pressure p, no external
// pressure. Radial displacement u(r) = A r + B / r with C = p a^2 / (b^2 - a^2):
//   plane strain (eps_z = 0)       : u = (1+nu) C / E * ((1 - 2nu) r + b^2 / r)
//   open ends (sigma_z = 0)        : u = C / E * ((1 - nu) r + (1 + nu) b^2 / r)
//   closed ends (sigma_z = C)      : u = C / E * ((1 - 2nu) r + (1 + nu) b^2 / r)
// The stresses sigma_r = C (1 - b^2/r^2), sigma_theta = C (1 + b^2/r^2) are the same in all three.
// ---------------------------------------------------------------------------------------------
enum class LameEnds { PlaneStrain, Open, Closed };
[[nodiscard]] double lame_radial_displacement(double p, double a, double b, double E, double nu, double r,
                                              LameEnds ends);
// Uniform axial strain of the tube (0 for plane strain).
[[nodiscard]] double lame_axial_strain(double p, double a, double b, double E, double nu, LameEnds ends);
[[nodiscard]] double lame_radial_stress(double p, double a, double b, double r);
[[nodiscard]] double lame_hoop_stress(double p, double a, double b, double r);

// ---------------------------------------------------------------------------------------------
// First bending frequency of a uniform cantilever.
// ---------------------------------------------------------------------------------------------
// First root of 1 + cos(x) cosh(x) = 0.
inline constexpr double kCantileverBeta1L = 1.8751040687119611;
// Euler–Bernoulli: omega1 = (beta1 L)^2 sqrt(E I / (rho A L^4))  [rad/s].
[[nodiscard]] double cantilever_first_omega_eb(double E, double I, double rho, double A, double L);
// Timoshenko beam (shear deformation + rotary inertia), solid circle of radius r: the first root of
// the clamped-free frequency determinant, found by shooting the Timoshenko ODEs
//   kappa G A (w'' - psi') + rho A w^2 w = 0,   E I psi'' + kappa G A (w' - psi) + rho I w^2 psi = 0
// with w = psi = 0 at x = 0 and psi' = 0, w' - psi = 0 at x = L. Lower than EB by a relative amount
// of order (beta1 L)^2 (r_g/L)^2 (1 + E/(kappa G)) / 2, r_g = r/2 the radius of gyration.
[[nodiscard]] double cantilever_first_omega_timoshenko(double E, double nu, double rho, double r, double L);

// ---------------------------------------------------------------------------------------------
// Backward (implicit) Euler on an undamped oscillator x'' = -w^2 x with step h: the amplification
// factor is z = 1/(1 - i w h), so the discrete motion rotates by atan(w h) per step (period
// elongation) and shrinks by 1/sqrt(1 + (w h)^2) per step (numerical damping).
// ---------------------------------------------------------------------------------------------
[[nodiscard]] inline double implicit_euler_apparent_omega(double omega, double h) { return std::atan(omega * h) / h; }
[[nodiscard]] inline double implicit_euler_step_amplitude_ratio(double omega, double h) {
  return 1.0 / std::sqrt(1.0 + omega * h * omega * h);
}

// Observed convergence order from errors e1, e2 at mesh sizes h1, h2: log(e1/e2)/log(h1/h2).
[[nodiscard]] inline double observed_order(double h1, double e1, double h2, double e2) {
  return std::log(e1 / e2) / std::log(h1 / h2);
}

}  // namespace codesign::fem::validation
