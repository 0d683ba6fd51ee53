#pragma once
// Material and damping parameters of the whisker body.
//
// Units throughout src/fem: length mm, mass g, time s. Derived: force g·mm/s² = 1 µN,
// stress µN/mm² = 1 Pa, energy µN·mm = 1 nJ. A user-facing kPa value becomes Pa by ×1e3,
// a force in µN becomes mN by ×1e-3.
namespace codesign::fem {

struct Material {
  double youngs_modulus_Pa = 5.0e5;  // E = 500 kPa (paper, Table II)
  double poisson_ratio = 0.4;        // ν (paper, Table II)
  double total_mass_g = 20.0;        // whole body; density = mass / meshed volume (paper: 20 g)
  double gravity_mm_s2 = 9800.0;     // along −z of the world frame (paper: 9800)
  // Rayleigh damping C = rayleigh_mass·M + rayleigh_stiffness·K (see docs/physics.md).
  double rayleigh_mass_per_s = 0.5;
  double rayleigh_stiffness_s = 0.005;

  // Lamé parameters [Pa].
  double lame_mu() const { return youngs_modulus_Pa / (2.0 * (1.0 + poisson_ratio)); }
  double lame_lambda() const {
    return youngs_modulus_Pa * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
};

}  // namespace codesign::fem
