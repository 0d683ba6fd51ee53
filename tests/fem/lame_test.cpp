// Lamé thick-walled cylinder under internal (follower) pressure, plane strain.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "analytic.hpp"
#include "fem/static_solve.hpp"
#include "fem/whisker_mesh.hpp"

namespace {

using namespace codesign::fem;
using namespace codesign::fem::validation;

struct LameErrors {
  double inner, outer, profile_rms, axial_max;  // relative to u(a)
  double h;
};

// Tube a = 3 mm, b = 5 mm, length 10 mm, p = 100 Pa (u(a)/a ≈ 5e-4: geometric nonlinearity and
// the follower load's change of direction/area are O(u/a) ≈ 5e-4 relative, negligible).
// Boundary conditions: u_x = 0 on both end faces (smooth symmetry planes). The plane-strain Lamé
// field (u_x ≡ 0, u_r = u(r), shear-free ends) satisfies them exactly, so it is the exact 3D
// solution of this problem: the only error is discretisation. The rigid motions left free
// (translation in y, z, rotation about x) are removed by a tiny mass shift in the Newton matrix
// (the pressure load is self-equilibrated); the equilibrium is unaffected.
LameErrors solve_lame(double size) {
  constexpr double a = 3.0, b = 5.0, len = 10.0, p = 100.0;
  ModelOptions mo;
  mo.material.gravity_mm_s2 = 0.0;
  const auto m = build_model(mesh_hollow_cylinder(a, b, len, size), mo);
  const double E = m->material.youngs_modulus_Pa, nu = m->material.poisson_ratio;
  std::vector<bool> fixed(static_cast<std::size_t>(3 * m->node_count()), false);
  for (const auto* faces : {&m->mesh.base_faces, &m->mesh.tip_faces})
    for (const Tri& t : *faces)
      for (int k : t) fixed[static_cast<std::size_t>(3 * k)] = true;
  StaticLoads loads;
  loads.chamber_pressures_Pa = {p};
  StaticOptions opt;
  opt.mass_shift = 1e-6 * E / (m->material.total_mass_g / m->volume_mm3) / (b * b);  // ≪ K: 1e-6 relative
  const StaticResult r = solve_static(*m, loads, fixed, opt);
  EXPECT_TRUE(r.converged);
  const double ua = lame_radial_displacement(p, a, b, E, nu, a, LameEnds::PlaneStrain);
  double in_sum = 0, in_n = 0, out_sum = 0, out_n = 0, sq = 0, ax = 0;
  for (int i = 0; i < m->node_count(); ++i) {
    const Eigen::Vector3d X = m->rest_positions.segment<3>(3 * i);
    const Eigen::Vector3d u = r.positions.segment<3>(3 * i) - X;
    const double rr = std::hypot(X.y(), X.z());
    const double ur = (u.y() * X.y() + u.z() * X.z()) / rr;
    const double ref = lame_radial_displacement(p, a, b, E, nu, rr, LameEnds::PlaneStrain);
    sq += (ur - ref) * (ur - ref);
    ax = std::max(ax, std::abs(u.x()));
    if (std::abs(rr - a) < 1e-6 * a) in_sum += ur / ref, in_n += 1;
    if (std::abs(rr - b) < 1e-6 * b) out_sum += ur / ref, out_n += 1;
  }
  EXPECT_GT(in_n, 10);
  EXPECT_GT(out_n, 10);
  LameErrors e{in_sum / in_n - 1.0, out_sum / out_n - 1.0, std::sqrt(sq / m->node_count()) / ua, ax / ua,
               std::cbrt(m->volume_mm3 / static_cast<double>(m->mesh.tets.size()))};
  std::printf("[lame] size=%.2f h_eff=%.3f tets=%zu u(a) err=%.5f u(b) err=%.5f profile rms=%.5f max|u_x|/u(a)=%.2e\n",
              size, e.h, m->mesh.tets.size(), e.inner, e.outer, e.profile_rms, e.axial_max);
  return e;
}

// Tolerance: the FE is stiffer than the exact solution (Galerkin: the pressure work, ∝ the mean
// inner radial displacement, is twice the strain energy and is underestimated), so the errors are
// negative up to the 0.1 % geometric-nonlinearity term. The solution is smooth, so linear tets
// converge at O(h²) asymptotically; at 3–5 elements through the wall (ν = 0.4, mild volumetric
// stiffening) the order is pre-asymptotic: accepted band p ∈ [1.0, 2.5] (same as the cantilever).
// The h → 0 limit is bracketed by two-point extrapolation with p = 1 and p = 2 and must contain
// the exact answer (error 0) within the 0.1 % model-form term. (Measured at size 0.5: −3.1 %,
// order 2.4 from 0.7 → 0.5; not run here to keep the suite fast.)
TEST(ValidationLame, PlaneStrainRadialDisplacementConverges) {
  constexpr double kModelForm = 1e-3;
  const LameErrors c = solve_lame(1.0);
  const LameErrors f = solve_lame(0.7);
  for (const LameErrors& e : {c, f}) {
    EXPECT_LT(e.inner, kModelForm);
    EXPECT_LT(e.outer, kModelForm);
  }
  EXPECT_LT(std::abs(f.inner), std::abs(c.inner));
  EXPECT_LT(std::abs(f.outer), std::abs(c.outer));
  EXPECT_LT(f.profile_rms, c.profile_rms);
  const double r = c.h / f.h;
  for (const auto& [ec, ef] : {std::pair{c.inner, f.inner}, std::pair{c.outer, f.outer}}) {
    const double p = observed_order(c.h, std::abs(ec), f.h, std::abs(ef));
    EXPECT_GE(p, 1.0);
    EXPECT_LE(p, 2.5);
    const double lim1 = ef + (ef - ec) / (r - 1.0);        // p = 1: largest correction
    const double lim2 = ef + (ef - ec) / (r * r - 1.0);    // p = 2
    std::printf("[lame] order %.3f, extrapolated error bracket [%.4f, %.4f]\n", p, std::min(lim1, lim2),
                std::max(lim1, lim2));
    EXPECT_LE(std::min(lim1, lim2), kModelForm);
    EXPECT_GE(std::max(lim1, lim2), -kModelForm);
  }
}

}  // namespace
