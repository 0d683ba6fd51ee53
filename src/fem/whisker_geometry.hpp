#pragma once
// Parametric whisker geometry: a truncated cone with internal pressure chamber(s).
//
// Frame as in mesh.hpp: axis along +x, clamped base disc at x = 0 (radius R0 = base_diameter/2),
// tip disc at x = L (radius R1 = tip_diameter/2); outer radius R(x) = R0 + (R1 - R0) x / L.
//
// Chamber placement (our choice; the paper shows the chamber at the thick end but gives no
// drawing dimensions):
//  * The chamber region starts at x0 = max(proximal_cap_mm, w) and ends at x1 = x0 + l, so the
//    proximal end wall (the cap between the clamped face and the cavity) is never thinner than w.
//    The distal end is closed by the remaining solid cone (≥ 100 - 44 mm long for all designs).
//  * n = 1: one coaxial cylindrical cavity of length l and radius r_c = R(x1) - w. The cone
//    narrows towards the tip, so R(x1) is the smallest outer radius over the chamber and every
//    side wall is ≥ w thick (exactly w at the distal end of the chamber).
//  * n = 2: the same cylinder minus a septum slab |z| < w/2, i.e. two D-shaped cavities lying in
//    the bending plane x–z: chamber 0 at z > 0, chamber 1 at z < 0.  The septum is w thick.
// All 110 designs are valid with the defaults: the tightest is l = 40, w = 4 where
// r_c = 12 - 10*44/100 - 4 = 3.6 mm > w/2, so each D-chamber keeps ≥ 1.6 mm of height.
#include "fem/design.hpp"

namespace codesign::fem {

struct WhiskerGeometry {
  double length_mm = 100.0;
  double base_diameter_mm = 24.0;
  double tip_diameter_mm = 4.0;
  double proximal_cap_mm = 4.0;  // requested proximal end-wall thickness (raised to w if thinner)
  Design design{};

  double base_radius() const { return 0.5 * base_diameter_mm; }
  double tip_radius() const { return 0.5 * tip_diameter_mm; }
  // Outer radius of the cone at axial position x.
  double outer_radius(double x) const {
    return base_radius() + (tip_radius() - base_radius()) * x / length_mm;
  }
  double chamber_start() const {
    return proximal_cap_mm > design.wall_mm ? proximal_cap_mm : design.wall_mm;
  }
  double chamber_end() const { return chamber_start() + design.chamber_length_mm; }
  double cavity_radius() const { return outer_radius(chamber_end()) - design.wall_mm; }
};

// Throws std::invalid_argument when the geometry cannot hold its chamber(s) (cavity radius not
// positive, the D-chambers of n = 2 vanish, the chamber runs past the tip, or non-positive sizes).
void validate(const WhiskerGeometry& g);

// Analytic ("CAD") volumes in mm³: the cone, the cavities, and the solid (cone minus cavities).
double cone_volume(const WhiskerGeometry& g);
double cavity_volume(const WhiskerGeometry& g);  // all chambers together
double solid_volume(const WhiskerGeometry& g);

}  // namespace codesign::fem
