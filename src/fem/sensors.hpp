#pragma once
// What the controller and the logs read from the simulator.
#include <Eigen/Core>

namespace codesign::fem {

struct Sensors {
  double time_s = 0.0;
  double theta_rad = 0.0;          // base angle θ (relative to the inclination α)
  double contact_force_mN = 0.0;   // F = Σ normal contact multipliers (≥ 0), vertical, in mN
  // ε: volume-weighted mean over the chamber-region tets of the axial engineering strain
  // ‖F_e x̂‖ − 1 (stretch of the material line that is axial at rest, minus one). Rotation
  // invariant; pressure lengthens the chamber (ε up), the axial component of the tip load
  // shortens it (ε down) while bending cancels to first order across the section.
  double axial_strain = 0.0;
  Eigen::Vector3d tip_position_mm = Eigen::Vector3d::Zero();  // mean of the tip-face nodes, world
  double plate_z_mm = 0.0;
  int active_contacts = 0;         // nodes on the plate this step
  bool in_contact = false;         // F > 0
  bool theta_extreme = false;      // |θ| > theta_limit
};

}  // namespace codesign::fem
