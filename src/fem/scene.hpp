#pragma once
// Placement of the whisker in the world and the moving plate.
//
// World frame: z up (gravity along −z), origin at the centre of the clamped base face. The base
// turns about the world y axis through that centre. A node with rest position X (whisker frame,
// mesh.hpp) sits, while the body is undeformed, at  x = R_y(α + θ) X,  where
//   R_y(φ) = [[cos φ, 0, sin φ], [0, 1, 0], [−sin φ, 0, cos φ]]  maps the axis +x to
//   (cos φ, 0, −sin φ): α > 0 inclines the whisker downwards towards the plate, and θ > 0 turns
//   the base further down (pushes the tip into the plate, raising F).
// Clamped (base-face) nodes always sit exactly at R_y(α + θ(t)) X.
// The plate is the horizontal plane z = z_plate(t) = z0 + U sin(ω t) (ω = 2π f), contact is with
// its upper side. z0 = z_touch + preload, where z_touch is the lowest z of the contact candidate
// nodes in the undeformed placement at θ = 0 (the plate just touching the straight whisker).
#include <cmath>
#include <numbers>

#include <Eigen/Core>

#include "base/range.hpp"

namespace codesign::fem {

struct SceneConfig {
  double inclination_deg = 30.0;    // α
  double preload_mm = 0.5;          // plate mean height above z_touch
  double plate_amplitude_mm = 2.0;  // U
  double plate_frequency_Hz = 0.8;  // f = ω/2π; 2 periods over 250 steps of 0.01 s
  double plate_phase_rad = 0.0;     // z_plate = z0 + U sin(ω t + phase)
  double theta_limit_deg = 30.0;    // |θ| beyond this sets Sensors::theta_extreme
  int settle_steps = 20;            // quasi-static load steps that raise the plate to z0

  double alpha_rad() const { return inclination_deg * std::numbers::pi / 180.0; }
  double omega() const { return 2.0 * std::numbers::pi * plate_frequency_Hz; }
};

inline Eigen::Matrix3d rotation_y(double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  Eigen::Matrix3d r;
  r << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  return r;
}

}  // namespace codesign::fem
