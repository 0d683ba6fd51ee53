#pragma once
// Physical uncertainty in training ([randomize]; off by default): every episode an environment
// starts meets a body, a plate and sensors drawn around the nominal ones, so that a controller
// trained under it holds on a real robot whose silicone, casting, plate and gauges are known only
// to a tolerance (docs/codesign.md, "Physical uncertainty").
//
// The draws are a pure function of (seed, iteration k, environment i): no stream of the run is
// consumed, so a run without the table draws nothing and is the run it was before the table
// existed, and a run with it is bit-identical on resume and for any thread or rank count. Each
// parameter is drawn uniformly in its range (relative ranges: nominal × U[1 − r, 1 + r]); the
// per-decision sensor noises are normal with the stated standard deviation, from a stream seeded
// by the same function (noise_seed).
#include <cstdint>

#include "base/config_keys.hpp"
#include "fem/model_scaling.hpp"
#include "fem/scene.hpp"

namespace codesign::core {

struct RandomizeConfig {
  // Relative half-ranges r (0: nominal).
  double youngs_modulus = 0.0;   // the silicone's E
  double fibre_stiffness = 0.0;  // the fibre springs' axial stiffness
  double damping = 0.0;          // both Rayleigh coefficients, by one factor
  double mass = 0.0;             // the body's total mass
  double plate_amplitude = 0.0;  // U
  double plate_frequency = 0.0;  // f
  double pressure_error = 0.0;   // each chamber gets p (1 + e), e ∈ [−r, r], the policy sees p
  double strain_gain = 0.0;      // the gauge reads g ε, g ∈ [1 − r, 1 + r]
  // Absolute half-ranges.
  double plate_height_mm = 0.0;  // the plate's mean height (preload) ± this
  double strain_offset = 0.0;    // the gauge reads g ε + b, b ∈ [−r, r] (strain)
  // Standard deviations of per-decision noise.
  double strain_noise = 0.0;     // on the strain the policy observes
  double encoder_noise_deg = 0.0;  // on the base angle θ where it is observed
  // The policy's action reaches the base one decision late.
  bool actuation_delay = false;
  // Casting tolerance of the wall: the body is cast with the wall w + δ, δ one of {−r, 0, +r}
  // (three mesh levels per design, each meshed once).
  double wall_mm = 0.0;

  // Whether any draw differs from the nominal physics.
  bool enabled() const {
    return youngs_modulus > 0 || fibre_stiffness > 0 || damping > 0 || mass > 0 || plate_amplitude > 0 ||
           plate_frequency > 0 || pressure_error > 0 || strain_gain > 0 || plate_height_mm > 0 || strain_offset > 0 ||
           strain_noise > 0 || encoder_noise_deg > 0 || actuation_delay || wall_mm > 0;
  }
};

// What one episode meets: factors on the nominal values (1 = nominal) and offsets (0 = nominal).
struct PhysicsDraw {
  bool operator==(const PhysicsDraw&) const = default;
  double youngs_scale = 1.0, fibre_scale = 1.0, damping_scale = 1.0, mass_scale = 1.0;
  double plate_amplitude_scale = 1.0, plate_frequency_scale = 1.0, plate_height_offset_mm = 0.0;
  double pressure_scale_1 = 1.0, pressure_scale_2 = 1.0;
  double strain_gain = 1.0, strain_offset = 0.0;
  double strain_noise = 0.0, encoder_noise_rad = 0.0;
  bool actuation_delay = false;
  std::uint64_t noise_seed = 0;  // the episode's per-decision noise stream
  double wall_offset_mm = 0.0;   // the cast wall is the design's w + this

  // The draw with the sensors and the actuation nominal: what the simulation depends on (the key
  // of the environment's caches of ε₀ and of the settled state).
  PhysicsDraw simulation_part() const {
    PhysicsDraw d;
    d.youngs_scale = youngs_scale, d.fibre_scale = fibre_scale, d.damping_scale = damping_scale;
    d.mass_scale = mass_scale, d.plate_amplitude_scale = plate_amplitude_scale;
    d.plate_frequency_scale = plate_frequency_scale, d.plate_height_offset_mm = plate_height_offset_mm;
    d.pressure_scale_1 = pressure_scale_1, d.pressure_scale_2 = pressure_scale_2;
    d.wall_offset_mm = wall_offset_mm;
    return d;
  }
  fem::BodyScale body() const { return {youngs_scale, mass_scale, damping_scale, fibre_scale}; }
  // The scene of this draw around the nominal one.
  fem::SceneConfig scene(fem::SceneConfig nominal) const {
    nominal.plate_amplitude_mm *= plate_amplitude_scale;
    nominal.plate_frequency_Hz *= plate_frequency_scale;
    nominal.preload_mm += plate_height_offset_mm;
    return nominal;
  }
  // What the strain gauge reads for a strain: g ε + b (ε itself, to the bit, when nominal).
  double gauge(double strain) const {
    if (strain_gain != 1.0) strain *= strain_gain;
    if (strain_offset != 0.0) strain += strain_offset;
    return strain;
  }
};

// The draw of environment `env` in iteration k of a run seeded `seed`; the nominal PhysicsDraw{}
// when the table is off.
PhysicsDraw draw_physics(const RandomizeConfig& c, std::uint64_t seed, std::int64_t k, std::size_t env);

template <class V>
void describe_randomize_table(V& v, RandomizeConfig& c) {
  v.number({"youngs_modulus", "", "relative half-range of Young's modulus: E × U[1 − r, 1 + r]"}, c.youngs_modulus,
           {0.0, 0.9});
  v.number({"fibre_stiffness", "", "relative half-range of the fibres' axial stiffness"}, c.fibre_stiffness,
           {0.0, 0.9});
  v.number({"damping", "", "relative half-range of both Rayleigh coefficients (one factor)"}, c.damping, {0.0, 0.9});
  v.number({"mass", "", "relative half-range of the body's mass"}, c.mass, {0.0, 0.9});
  v.number({"plate_amplitude", "", "relative half-range of the plate's amplitude U"}, c.plate_amplitude, {0.0, 0.9});
  v.number({"plate_frequency", "", "relative half-range of the plate's frequency f"}, c.plate_frequency, {0.0, 0.9});
  v.number({"plate_height_mm", "mm", "half-range of the plate's mean height about the nominal preload"},
           c.plate_height_mm, {0.0, 5.0});
  v.number({"pressure_error", "", "relative half-range of each chamber's pressure error (the policy sees p)"},
           c.pressure_error, {0.0, 0.5});
  v.number({"strain_gain", "", "relative half-range of the strain gauge's gain"}, c.strain_gain, {0.0, 0.5});
  v.number({"strain_offset", "", "half-range of the strain gauge's offset (strain)"}, c.strain_offset, {0.0, 0.01});
  v.number({"strain_noise", "", "standard deviation of the observed strain's noise per decision (strain)"},
           c.strain_noise, {0.0, 0.01});
  v.number({"encoder_noise_deg", "deg", "standard deviation of the observed base angle's noise per decision"},
           c.encoder_noise_deg, {0.0, 5.0});
  v.boolean({"actuation_delay", "", "the action reaches the base one decision late"}, c.actuation_delay);
  v.number({.name = "wall_mm", .unit = "mm",
            .meaning = "casting tolerance of the wall: it is w − r, w or w + r (three mesh levels)",
            .written = config::Written::UnlessDefault, .at_default = c.wall_mm == RandomizeConfig{}.wall_mm},
           c.wall_mm, {0.0, 0.25});
}

}  // namespace codesign::core
