// Tests of the analytic references themselves (tabulated literature values, limits, and
// independent numerical re-derivations), so the FEM validation compares against trusted numbers.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "analytic.hpp"

namespace {

using namespace codesign::fem::validation;

// Elastica by direct shooting (independent of the elliptic-integral route): in s in [0, 1],
// theta'' = -a2 cos(theta), theta(0) = 0, theta'(1) = 0; x = int cos, y = int sin.
ElasticaTip elastica_by_shooting(double a2) {
  const auto run = [a2](double kappa0, double& x, double& y) {
    constexpr int n = 4000;
    const double h = 1.0 / n;
    using S = std::array<double, 4>;  // theta, theta', x, y
    const auto f = [a2](const S& s) -> S { return {s[1], -a2 * std::cos(s[0]), std::cos(s[0]), std::sin(s[0])}; };
    S s{0.0, kappa0, 0.0, 0.0};
    for (int i = 0; i < n; ++i) {
      S k1 = f(s), t{};
      for (int j = 0; j < 4; ++j) t[j] = s[j] + 0.5 * h * k1[j];
      S k2 = f(t);
      for (int j = 0; j < 4; ++j) t[j] = s[j] + 0.5 * h * k2[j];
      S k3 = f(t);
      for (int j = 0; j < 4; ++j) t[j] = s[j] + h * k3[j];
      S k4 = f(t);
      for (int j = 0; j < 4; ++j) s[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    x = s[2];
    y = s[3];
    return s;
  };
  // Root curvature kappa0 = (bending moment at the clamp)/EI in [0, a2]; theta'(1) is monotone in it.
  double lo = 0.0, hi = a2, x = 0, y = 0;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    (run(mid, x, y)[1] < 0.0 ? lo : hi) = mid;
  }
  const auto s = run(0.5 * (lo + hi), x, y);
  return {1.0 - x, y, s[0]};
}

// Mattiasson, K. (1981), "Numerical results from large deflection beam and frame problems analysed
// by means of elliptic integrals", IJNME 17:145–153, Table 1 (5 decimals): the classic
// Bisshopp–Drucker tip-load values. PL^2/EI -> (vertical v/L, horizontal u/L).
// Note: the horizontal value at PL^2/EI = 1 is 0.05643 (not 0.0566).
struct Tabulated {
  double a2, v, u;
};
constexpr std::array<Tabulated, 4> kMattiasson{{{1.0, 0.30172, 0.05643},
                                                {2.0, 0.49346, 0.16064},
                                                {5.0, 0.71379, 0.38763},
                                                {10.0, 0.81061, 0.55500}}};

TEST(AnalyticBisshoppDrucker, MatchesTabulatedValues) {
  for (const auto& t : kMattiasson) {
    const ElasticaTip tip = bisshopp_drucker(t.a2);
    // Table rounded to 5 decimals: half a unit in the last place plus margin.
    EXPECT_NEAR(tip.vertical_ratio, t.v, 1e-5) << "PL^2/EI = " << t.a2;
    EXPECT_NEAR(tip.horizontal_ratio, t.u, 1e-5) << "PL^2/EI = " << t.a2;
  }
}

TEST(AnalyticBisshoppDrucker, AgreesWithDirectShooting) {
  for (double a2 : {0.3, 1.0, 1.5, 2.0, 4.0}) {
    const ElasticaTip e = bisshopp_drucker(a2);
    const ElasticaTip s = elastica_by_shooting(a2);
    // RK4 with 4000 steps: truncation ~1e-14; bisection on kappa0 to 2^-80 a2.
    EXPECT_NEAR(e.vertical_ratio, s.vertical_ratio, 1e-9) << a2;
    EXPECT_NEAR(e.horizontal_ratio, s.horizontal_ratio, 1e-9) << a2;
    EXPECT_NEAR(e.tip_angle, s.tip_angle, 1e-9) << a2;
  }
}

TEST(AnalyticBisshoppDrucker, SmallLoadLimitIsLinearTheory) {
  // theta(s) -> a2 (s - s^2/2): v/L -> a2/3 (EB), u/L -> (1/2) int theta^2 = a2^2/15, theta0 -> a2/2.
  const double a2 = 1e-3;
  const ElasticaTip tip = bisshopp_drucker(a2);
  EXPECT_NEAR(tip.vertical_ratio / (a2 / 3.0), 1.0, 1e-4);
  EXPECT_NEAR(tip.horizontal_ratio / (a2 * a2 / 15.0), 1.0, 1e-3);
  EXPECT_NEAR(tip.tip_angle / (a2 / 2.0), 1.0, 1e-4);
}

TEST(AnalyticCantilever, EulerBernoulliAndTimoshenko) {
  // r = 2, L = 60, E = 5e5, nu = 0.4, P = 10: I = 4 pi, A = 4 pi, kappa = 8.4/9.4, G = 5e5/2.8.
  const double I = circle_second_moment(2.0);
  EXPECT_NEAR(I, 4.0 * kPi, 1e-12);
  const double eb = 10.0 * 216000.0 / (3.0 * 5e5 * 4.0 * kPi);
  EXPECT_NEAR(cantilever_tip_deflection_eb(10.0, 60.0, 5e5, I), eb, 1e-12 * eb);
  const double shear = 10.0 * 60.0 / ((8.4 / 9.4) * (5e5 / 2.8) * 4.0 * kPi);
  EXPECT_NEAR(cantilever_tip_deflection_timoshenko(10.0, 60.0, 5e5, 0.4, 2.0), eb + shear, 1e-12 * eb);
  EXPECT_NEAR(circle_shear_coefficient(0.3), 7.8 / 8.8, 1e-15);
}

TEST(AnalyticLame, StressesSatisfyBoundaryConditionsAndHooke) {
  const double p = 1e4, a = 3.0, b = 5.0, E = 5e5, nu = 0.4;
  EXPECT_NEAR(lame_radial_stress(p, a, b, a), -p, 1e-9 * p);
  EXPECT_NEAR(lame_radial_stress(p, a, b, b), 0.0, 1e-9 * p);
  const double C = p * a * a / (b * b - a * a);
  for (LameEnds ends : {LameEnds::PlaneStrain, LameEnds::Open, LameEnds::Closed}) {
    const double sz_expected = ends == LameEnds::Open ? 0.0 : ends == LameEnds::Closed ? C : 2.0 * nu * C;
    for (double r : {3.0, 3.7, 4.4, 5.0}) {
      // Strains from the displacement field: eps_r = du/dr (central difference), eps_t = u/r.
      const double h = 1e-5;
      const double er = (lame_radial_displacement(p, a, b, E, nu, r + h, ends) -
                         lame_radial_displacement(p, a, b, E, nu, r - h, ends)) /
                        (2 * h);
      const double et = lame_radial_displacement(p, a, b, E, nu, r, ends) / r;
      const double ez = lame_axial_strain(p, a, b, E, nu, ends);
      // Isotropic Hooke: sigma = lambda tr(eps) + 2 mu eps.
      const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
      const double tr = er + et + ez;
      const double scale = p * 1e-7;
      EXPECT_NEAR(lam * tr + 2 * mu * er, lame_radial_stress(p, a, b, r), scale);
      EXPECT_NEAR(lam * tr + 2 * mu * et, lame_hoop_stress(p, a, b, r), scale);
      EXPECT_NEAR(lam * tr + 2 * mu * ez, sz_expected, scale);
    }
  }
}

TEST(AnalyticLame, ThinWallLimitIsHoopFormula) {
  // Open thin tube: hoop strain p a / (E t) dominates, u(a) -> p a^2 / (E t) (1 + O(t/a)).
  const double p = 100.0, a = 10.0, t = 0.01, E = 5e5, nu = 0.4;
  const double u = lame_radial_displacement(p, a, a + t, E, nu, a, LameEnds::Open);
  EXPECT_NEAR(u / (p * a * a / (E * t)), 1.0, 5.0 * t / a);
}

TEST(AnalyticFrequency, EulerBernoulliRoot) {
  const double x = kCantileverBeta1L;
  EXPECT_NEAR(1.0 + std::cos(x) * std::cosh(x), 0.0, 1e-14);
  EXPECT_NEAR(x * x, 3.5160, 1e-4);  // the classic 3.516 coefficient
  const double w = cantilever_first_omega_eb(2.0, 3.0, 5.0, 7.0, 11.0);
  EXPECT_NEAR(w, x * x * std::sqrt(6.0 / (35.0 * 11.0 * 11.0 * 11.0 * 11.0)), 1e-14);
}

TEST(AnalyticFrequency, TimoshenkoTendsToEulerBernoulliAndScalesWithSlenderness) {
  const double E = 5e5, nu = 0.4, rho = 1e-3, L = 80.0;
  const auto rel_drop = [&](double r) {
    const double eb = cantilever_first_omega_eb(E, circle_second_moment(r), rho, circle_area(r), L);
    return 1.0 - cantilever_first_omega_timoshenko(E, nu, rho, r, L) / eb;
  };
  // Very slender: shooting error and shear effect both < 1e-6.
  EXPECT_NEAR(rel_drop(0.08), 0.0, 1e-5);
  // First-order theory: the drop is proportional to (r/L)^2.
  const double d1 = rel_drop(1.0), d2 = rel_drop(2.0);
  EXPECT_GT(d1, 0.0);
  EXPECT_NEAR(d2 / d1, 4.0, 0.1);
  // Order of magnitude: (beta1 L)^2 (r_g/L)^2 (1 + E/(kappa G)) / 2 with r_g = r/2.
  const double kG = circle_shear_coefficient(nu) * E / (2 * (1 + nu));
  const double estimate = 0.5 * std::pow(kCantileverBeta1L, 2) * std::pow(1.0 / (2.0 * L), 2) * (1.0 + E / kG);
  EXPECT_GT(d1, 0.3 * estimate);
  EXPECT_LT(d1, 3.0 * estimate);
}

TEST(AnalyticImplicitEuler, OscillatorPhaseAndDecay) {
  // Iterate backward Euler on x'' = -w^2 x (as the first-order system) and compare.
  const double w = 10.0, h = 0.02;
  double x = 1.0, v = 0.0;
  constexpr int n = 50;
  for (int i = 0; i < n; ++i) {
    // [1, -h; w^2 h, 1] [x+; v+] = [x; v]
    const double det = 1.0 + w * w * h * h;
    const double xn = (x + h * v) / det;
    const double vn = (v - w * w * h * x) / det;
    x = xn;
    v = vn;
  }
  const double amp = std::hypot(x, v / w);
  EXPECT_NEAR(amp, std::pow(implicit_euler_step_amplitude_ratio(w, h), n), 1e-12);
  const double phase = std::atan2(-v / w, x);  // x = A cos(phi), v/w = -A sin(phi)
  const double expected = std::remainder(n * implicit_euler_apparent_omega(w, h) * h, 2.0 * kPi);
  EXPECT_NEAR(phase, expected, 1e-12);
}

}  // namespace
