#include "core/physics_randomization.hpp"

#include <numbers>

#include "rl/rng.hpp"

namespace codesign::core {

PhysicsDraw draw_physics(const RandomizeConfig& c, std::uint64_t seed, std::int64_t k, std::size_t env) {
  if (!c.enabled()) return {};
  // A stream of its own per (seed, k, env): the constant keeps it apart from the run's streams,
  // which are split from Rng(seed).
  using rl::splitmix64;
  rl::Rng rng(splitmix64(splitmix64(splitmix64(seed ^ 0x52414E444F4D495AULL) + static_cast<std::uint64_t>(k)) + env));
  // Every factor is drawn, in this fixed order, whether or not its range is zero: widening one
  // range leaves the others' draws as they were.
  const auto relative = [&](double r) { return 1.0 + r * (2.0 * rng.uniform() - 1.0); };  // 1 exactly for r = 0
  const auto absolute = [&](double r) {
    const double u = 2.0 * rng.uniform() - 1.0;
    return r == 0.0 ? 0.0 : r * u;  // never −0 (a zero range reads as 0 in episodes.csv)
  };
  PhysicsDraw d;
  d.youngs_scale = relative(c.youngs_modulus);
  d.fibre_scale = relative(c.fibre_stiffness);
  d.damping_scale = relative(c.damping);
  d.mass_scale = relative(c.mass);
  d.plate_amplitude_scale = relative(c.plate_amplitude);
  d.plate_frequency_scale = relative(c.plate_frequency);
  d.plate_height_offset_mm = absolute(c.plate_height_mm);
  d.pressure_scale_1 = relative(c.pressure_error);
  d.pressure_scale_2 = relative(c.pressure_error);
  d.strain_gain = relative(c.strain_gain);
  d.strain_offset = absolute(c.strain_offset);
  d.strain_noise = c.strain_noise;
  d.encoder_noise_rad = c.encoder_noise_deg * std::numbers::pi / 180.0;
  d.actuation_delay = c.actuation_delay;
  d.noise_seed = rng.next_u64();
  // Drawn after the others, so that the table's earlier draws are what they were before it.
  const double u = rng.uniform();
  d.wall_offset_mm = c.wall_mm == 0.0 ? 0.0 : u < 1.0 / 3.0 ? -c.wall_mm : u < 2.0 / 3.0 ? 0.0 : c.wall_mm;
  return d;
}

}  // namespace codesign::core
