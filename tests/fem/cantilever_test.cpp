// Cantilever validation: small-load tip deflection vs Timoshenko with mesh refinement, and the
// large-deflection (Bisshopp–Drucker elastica) response under a dead tip load.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "analytic.hpp"
#include "fem/static_solve.hpp"
#include "validation_setup.hpp"

namespace {

using namespace codesign::fem;
using namespace codesign::fem::validation;

struct TipResult {
  Eigen::Vector3d u;  // area-weighted tip displacement [mm]
  bool converged;
  int iterations;
};

double tip_load_for(const Model& m, double a2) {
  return a2 * m.material.youngs_modulus_Pa * circle_second_moment(kBeamRadius) / (kBeamLength * kBeamLength);
}

// Dead tip load of load parameter a2 = P L² / (E I) along −z, solved with `steps` load steps.
TipResult solve_tip_load(const Model& m, double a2, int steps) {
  StaticLoads loads;
  loads.dead = tip_traction(m, Eigen::Vector3d(0.0, 0.0, -tip_load_for(m, a2)));
  StaticOptions opt;
  opt.load_steps = steps;
  const StaticResult r = solve_static(m, loads, clamped_base_dofs(m), opt);
  return {tip_displacement(m, r.positions), r.converged, r.iterations};
}

// Small load: a2 = 1e-3 gives δ/L = 3.3e-4 and a tip rotation of 5e-4 rad; geometric
// nonlinearity changes δ by O(a2²) ~ 1e-6 relative, far below everything measured here.
constexpr double kSmallA2 = 1e-3;

// Model-form difference between the 3D clamped cylinder and Timoshenko beam theory: the shear
// term itself is 3EI/(κGAL²) = 0.26 % of δ at L/r = 30, and the 3D clamp (lateral contraction
// and warping suppressed on the base face) and the Saint-Venant zone under the tip traction
// perturb δ by corrections of the same order (r/L)² times O(1) factors. 1 % covers them.
constexpr double kModelForm = 0.01;

// Two-point extrapolation to h → 0 from (h1, d1), (h2, d2), h1 > h2, for d = d∞ − C h^p.
double extrapolate(double h1, double d1, double h2, double d2, double p) {
  return d2 + (d2 - d1) / (std::pow(h1 / h2, p) - 1.0);
}

// Small-load tip deflection at three mesh sizes.
//
// Why the FE is below the reference and how fast it must converge: with the work-conjugate tip
// displacement δ (area-weighted mean under a uniform traction) P δ_h = 2 U_h, and Galerkin
// orthogonality gives δ − δ_h = ‖u − u_h‖²_E / P ≥ 0: the FE compliance is always too small and
// its error is the square of the energy-norm error. Linear tets have energy-norm error O(h) for
// a smooth solution, so the compliance error is O(h²); the clamped edge (clamped base meets the
// free lateral surface) is a singular line with exponent λ ≈ 0.7 (Williams, clamped–free right
// angle), which limits the asymptotic order to 2λ ≈ 1.4 once the smooth bending error is small.
// On these meshes (4–8 elements across the diameter) linear tets lock in bending: the excess
// stiffness c(h/r)² is not small (≈ 0.2–0.6), which lowers the apparent order of the compliance
// error e = c x /(1 + c x), x = (h/r)², to 2/(1 + c x) ≈ 1.3–1.7. Accepted band: p ∈ [1.0, 2.5].
TEST(ValidationCantilever, SmallLoadTipDeflectionConvergesToTimoshenko) {
  const std::array<double, 3> sizes{2.0, 1.4, 1.0};
  std::array<double, 3> h{}, delta{};
  const double nu = 0.4, E = 5e5;
  double delta_T = 0.0;
  for (int i = 0; i < 3; ++i) {
    const auto m = cylinder_model(sizes[static_cast<std::size_t>(i)]);
    ASSERT_EQ(m->material.youngs_modulus_Pa, E);
    ASSERT_EQ(m->material.poisson_ratio, nu);
    const TipResult r = solve_tip_load(*m, kSmallA2, 1);
    ASSERT_TRUE(r.converged);
    // Lateral and axial components vanish by symmetry (to mesh asymmetry, ≪ δ).
    EXPECT_LT(std::abs(r.u.y()), 0.02 * std::abs(r.u.z()));
    h[static_cast<std::size_t>(i)] = effective_size(*m);
    delta[static_cast<std::size_t>(i)] = -r.u.z();
    delta_T = cantilever_tip_deflection_timoshenko(tip_load_for(*m, kSmallA2), kBeamLength, E, nu, kBeamRadius);
    std::printf("[cantilever] h_nominal=%.2f h_eff=%.3f tets=%zu delta=%.6e delta_T=%.6e error=%.4f\n",
                sizes[static_cast<std::size_t>(i)], h[static_cast<std::size_t>(i)], m->mesh.tets.size(),
                delta[static_cast<std::size_t>(i)], delta_T, 1.0 - delta[static_cast<std::size_t>(i)] / delta_T);
  }
  // Too stiff on every mesh (Galerkin), up to the model-form difference of the reference.
  for (double d : delta) EXPECT_LT(d, delta_T * (1.0 + kModelForm));
  // Error decreases monotonically, at an order in the derived band.
  std::array<double, 3> err{};
  for (int i = 0; i < 3; ++i) err[static_cast<std::size_t>(i)] = 1.0 - delta[static_cast<std::size_t>(i)] / delta_T;
  EXPECT_GT(err[0], err[1]);
  EXPECT_GT(err[1], err[2]);
  const double p01 = observed_order(h[0], err[0], h[1], err[1]);
  const double p12 = observed_order(h[1], err[1], h[2], err[2]);
  std::printf("[cantilever] observed order vs Timoshenko: %.3f (coarse pair), %.3f (fine pair)\n", p01, p12);
  for (double p : {p01, p12}) {
    EXPECT_GE(p, 1.0);
    EXPECT_LE(p, 2.5);
  }
  // Unstructured gmsh meshes are not nested, so the error constant fluctuates from mesh to mesh
  // (three-point Richardson is ill-conditioned here). Instead the limit is bracketed: extrapolating
  // the two finest meshes with the band's orders p = 2 (smooth, lowest limit) and p = 1 (slowest
  // accepted, highest limit) must bracket Timoshenko, widened by the model-form difference.
  const double lim_2 = extrapolate(h[1], delta[1], h[2], delta[2], 2.0);
  const double lim_1 = extrapolate(h[1], delta[1], h[2], delta[2], 1.0);
  std::printf("[cantilever] extrapolated delta: p=2 %.6e (%.4f of T), p=1 %.6e (%.4f of T)\n", lim_2,
              lim_2 / delta_T, lim_1, lim_1 / delta_T);
  EXPECT_GE(delta_T, lim_2 * (1.0 - kModelForm));
  EXPECT_LE(delta_T, lim_1 * (1.0 + kModelForm));
  // Finest mesh: its error is bounded by its own largest estimated discretisation error (the
  // p = 1 extrapolation) plus the model-form term.
  EXPECT_LE(err[2], (lim_1 - delta[2]) / delta_T + kModelForm);
  RecordProperty("finest_error", std::to_string(err[2]));
}

// Large deflection under a dead vertical tip load against the Bisshopp–Drucker elastica.
//
// Tolerances (same mesh as the small-load calibration, h = 1.4):
//  * raw: the FE beam is stiffer than EI by the small-load factor c_h = δ_h/δ_EB (measured on
//    the same mesh), i.e. it behaves like an elastica at a2_eff = c_h a2. The elastica's v(a2)
//    is concave with v(0) = 0, so d ln v/d ln a2 ≤ 1 and v(c a2) ≥ c v(a2): the deficit in v is
//    at most 1 − c_h; u(a2) grows at most like a2² (d ln u/d ln a2 ≤ 2): deficit ≤ 1 − c_h².
//    Plus the model-form 1 %.
//  * calibrated: compared with the elastica at a2_eff, what remains is what the calibration does
//    not capture: shear (0.26 % of the compliance) acting on the rotated section, axial stretch
//    P/(EA) ≤ a2 (r/L)²/2 ≈ 1e-3, and a discretisation error that is not exactly a uniform EI
//    scaling (the moment distribution at large deflection weights the beam differently);
//    ≤ 0.5 % each → 1 % on v, doubled for u (d ln u/d ln a2 ≤ 2).
TEST(ValidationCantilever, LargeDeflectionMatchesBisshoppDrucker) {
  const auto m = cylinder_model(1.4);
  const TipResult small = solve_tip_load(*m, kSmallA2, 1);
  ASSERT_TRUE(small.converged);
  const double c_h = (-small.u.z() / kBeamLength) / (kSmallA2 / 3.0);  // δ_h / δ_EB
  ASSERT_GT(c_h, 0.5);
  ASSERT_LT(c_h, 1.01);
  for (const auto& [a2, steps] : {std::pair{1.0, 4}, std::pair{2.0, 8}}) {
    const TipResult r = solve_tip_load(*m, a2, steps);
    ASSERT_TRUE(r.converged) << "a2 = " << a2;
    const double v = -r.u.z() / kBeamLength, u = -r.u.x() / kBeamLength;
    const ElasticaTip bd = bisshopp_drucker(a2);
    const ElasticaTip cal = bisshopp_drucker(a2 * c_h);
    std::printf("[elastica] a2=%.1f c_h=%.4f FE v/L=%.5f u/L=%.5f | BD v=%.5f u=%.5f | BD(a2 c_h) v=%.5f u=%.5f"
                " | calibrated err v=%.4f u=%.4f (%d Newton its)\n",
                a2, c_h, v, u, bd.vertical_ratio, bd.horizontal_ratio, cal.vertical_ratio, cal.horizontal_ratio,
                v / cal.vertical_ratio - 1.0, u / cal.horizontal_ratio - 1.0, r.iterations);
    EXPECT_LT(1.0 - v / bd.vertical_ratio, (1.0 - c_h) + kModelForm);
    EXPECT_GT(1.0 - v / bd.vertical_ratio, -kModelForm);
    EXPECT_LT(1.0 - u / bd.horizontal_ratio, (1.0 - c_h * c_h) + kModelForm);
    EXPECT_GT(1.0 - u / bd.horizontal_ratio, -kModelForm);
    EXPECT_NEAR(v / cal.vertical_ratio, 1.0, 0.01);
    EXPECT_NEAR(u / cal.horizontal_ratio, 1.0, 0.02);
    EXPECT_LT(std::abs(r.u.y()), 0.01 * std::abs(r.u.z()));
  }
}

}  // namespace
