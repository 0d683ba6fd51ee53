#include "fem/whisker_geometry.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace codesign::fem {

void validate(const WhiskerGeometry& g) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("whisker geometry: " + what); };
  if (!(g.length_mm > 0 && g.base_diameter_mm > 0 && g.tip_diameter_mm > 0 && g.proximal_cap_mm >= 0)) {
    fail("length, diameters must be > 0 and the proximal cap ≥ 0");
  }
  if (g.design.n != 1 && g.design.n != 2) fail("chamber count must be 1 or 2");
  if (!(g.design.chamber_length_mm > 0 && g.design.wall_mm > 0)) fail("chamber length and wall must be > 0");
  if (g.chamber_end() + g.design.wall_mm > g.length_mm) {
    fail("chamber ends at x = " + std::to_string(g.chamber_end()) +
         " mm, leaving less than one wall thickness before the tip");
  }
  const double rc = g.cavity_radius();
  if (rc <= 0) fail("cavity radius R(x1) - w = " + std::to_string(rc) + " mm is not positive");
  if (g.design.n == 2 && rc <= 0.5 * g.design.wall_mm) {
    fail("cavity radius " + std::to_string(rc) + " mm leaves no room beside a septum of " +
         std::to_string(g.design.wall_mm) + " mm");
  }
}

double cone_volume(const WhiskerGeometry& g) {
  const double a = g.base_radius(), b = g.tip_radius();
  return std::numbers::pi * g.length_mm / 3.0 * (a * a + a * b + b * b);
}

double cavity_volume(const WhiskerGeometry& g) {
  const double r = g.cavity_radius();
  double area = std::numbers::pi * r * r;
  if (g.design.n == 2) {
    // Remove the part of the disc with |z| < h: 2 (h sqrt(r² - h²) + r² asin(h / r)).
    const double h = 0.5 * g.design.wall_mm;
    area -= 2.0 * (h * std::sqrt(r * r - h * h) + r * r * std::asin(h / r));
  }
  return area * g.design.chamber_length_mm;
}

double solid_volume(const WhiskerGeometry& g) { return cone_volume(g) - cavity_volume(g); }

}  // namespace codesign::fem
