#include "analytic.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

namespace codesign::fem::validation {

double cantilever_tip_deflection_eb(double P, double L, double E, double I) { return P * L * L * L / (3.0 * E * I); }

double cantilever_tip_deflection_timoshenko(double P, double L, double E, double nu, double r) {
  const double G = E / (2.0 * (1.0 + nu));
  const double shear = P * L / (circle_shear_coefficient(nu) * G * circle_area(r));
  return cantilever_tip_deflection_eb(P, L, E, circle_second_moment(r)) + shear;
}

namespace {

// Length parameter sqrt(P L^2 / EI) reached by modulus k: K(k) - F(phi1(k), k).
double elastica_length_parameter(double k) {
  const double phi1 = std::asin(std::min(1.0, 1.0 / (k * std::sqrt(2.0))));
  return std::comp_ellint_1(k) - std::ellint_1(k, phi1);
}

}  // namespace

ElasticaTip bisshopp_drucker(double load_parameter) {
  if (!(load_parameter > 0.0)) throw std::invalid_argument("bisshopp_drucker: load parameter must be > 0");
  const double alpha = std::sqrt(load_parameter);
  double lo = 1.0 / std::sqrt(2.0);  // tip angle 0
  double hi = 1.0 - 1e-15;           // tip angle -> 90 degrees
  if (elastica_length_parameter(hi) < alpha) throw std::invalid_argument("bisshopp_drucker: load parameter too large");
  for (int it = 0; it < 200 && hi - lo > 1e-16; ++it) {
    const double mid = 0.5 * (lo + hi);
    (elastica_length_parameter(mid) < alpha ? lo : hi) = mid;
  }
  const double k = 0.5 * (lo + hi);
  const double phi1 = std::asin(std::min(1.0, 1.0 / (k * std::sqrt(2.0))));
  const double sin_theta0 = 2.0 * k * k - 1.0;
  const double x_ratio = std::sqrt(2.0 * sin_theta0) / alpha;
  const double y_ratio = 1.0 - 2.0 * (std::comp_ellint_2(k) - std::ellint_2(k, phi1)) / alpha;
  return {1.0 - x_ratio, y_ratio, std::asin(sin_theta0)};
}

double lame_radial_displacement(double p, double a, double b, double E, double nu, double r, LameEnds ends) {
  const double C = p * a * a / (b * b - a * a);
  switch (ends) {
    case LameEnds::PlaneStrain: return (1.0 + nu) * C / E * ((1.0 - 2.0 * nu) * r + b * b / r);
    case LameEnds::Open: return C / E * ((1.0 - nu) * r + (1.0 + nu) * b * b / r);
    case LameEnds::Closed: return C / E * ((1.0 - 2.0 * nu) * r + (1.0 + nu) * b * b / r);
  }
  return 0.0;
}

double lame_axial_strain(double p, double a, double b, double E, double nu, LameEnds ends) {
  const double C = p * a * a / (b * b - a * a);
  switch (ends) {
    case LameEnds::PlaneStrain: return 0.0;
    case LameEnds::Open: return -2.0 * nu * C / E;           // sigma_z = 0, sigma_r + sigma_theta = 2C
    case LameEnds::Closed: return (1.0 - 2.0 * nu) * C / E;  // sigma_z = C
  }
  return 0.0;
}

double lame_radial_stress(double p, double a, double b, double r) {
  const double C = p * a * a / (b * b - a * a);
  return C * (1.0 - b * b / (r * r));
}

double lame_hoop_stress(double p, double a, double b, double r) {
  const double C = p * a * a / (b * b - a * a);
  return C * (1.0 + b * b / (r * r));
}

double cantilever_first_omega_eb(double E, double I, double rho, double A, double L) {
  return kCantileverBeta1L * kCantileverBeta1L * std::sqrt(E * I / (rho * A * L * L * L * L));
}

namespace {

// Timoshenko clamped-free frequency determinant at circular frequency w (shooting with RK4).
// State y = (w, w', psi, psi').
double timoshenko_determinant(double E, double nu, double rho, double r, double L, double omega) {
  const double G = E / (2.0 * (1.0 + nu));
  const double kGA = circle_shear_coefficient(nu) * G * circle_area(r);
  const double EI = E * circle_second_moment(r);
  const double rhoA = rho * circle_area(r);
  const double rhoI = rho * circle_second_moment(r);
  const double w2 = omega * omega;
  using State = std::array<double, 4>;
  const auto rhs = [&](const State& y) -> State {
    const double wpp = y[3] - rhoA * w2 * y[0] / kGA;
    const double psipp = -(kGA * (y[1] - y[2]) + rhoI * w2 * y[2]) / EI;
    return {y[1], wpp, y[3], psipp};
  };
  const auto shoot = [&](State y) {
    constexpr int n = 4000;
    const double h = L / n;
    for (int i = 0; i < n; ++i) {
      State k1 = rhs(y), tmp{};
      for (int j = 0; j < 4; ++j) tmp[j] = y[j] + 0.5 * h * k1[j];
      State k2 = rhs(tmp);
      for (int j = 0; j < 4; ++j) tmp[j] = y[j] + 0.5 * h * k2[j];
      State k3 = rhs(tmp);
      for (int j = 0; j < 4; ++j) tmp[j] = y[j] + h * k3[j];
      State k4 = rhs(tmp);
      for (int j = 0; j < 4; ++j) y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
    return y;
  };
  // Two independent starts satisfying the clamped conditions; scaled so both columns are O(1).
  const State a = shoot({0.0, 1.0, 0.0, 0.0});
  const State b = shoot({0.0, 0.0, 0.0, 1.0 / L});
  // Free-end residuals: moment ~ psi'(L) * L, shear ~ w'(L) - psi(L).
  return (a[3] * L) * (b[1] - b[2]) - (b[3] * L) * (a[1] - a[2]);
}

}  // namespace

double cantilever_first_omega_timoshenko(double E, double nu, double rho, double r, double L) {
  const double w_eb = cantilever_first_omega_eb(E, circle_second_moment(r), rho, circle_area(r), L);
  // Shear and rotary inertia only lower the frequency: scan up from 0.3 w_eb to the first sign change.
  double lo = 0.3 * w_eb;
  double f_lo = timoshenko_determinant(E, nu, rho, r, L, lo);
  const double step = 0.01 * w_eb;
  double hi = lo;
  double f_hi = f_lo;
  while (true) {
    hi = lo + step;
    f_hi = timoshenko_determinant(E, nu, rho, r, L, hi);
    if ((f_lo < 0.0) != (f_hi < 0.0)) break;
    lo = hi;
    f_lo = f_hi;
    if (lo > 1.05 * w_eb) throw std::runtime_error("cantilever_first_omega_timoshenko: no root below 1.05 w_EB");
  }
  for (int it = 0; it < 100 && hi - lo > 1e-13 * w_eb; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double f_mid = timoshenko_determinant(E, nu, rho, r, L, mid);
    if ((f_lo < 0.0) == (f_mid < 0.0)) {
      lo = mid;
      f_lo = f_mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace codesign::fem::validation
