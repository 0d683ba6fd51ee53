#pragma once
// The whisker force-tracking MDP of the paper (§IV-A, §V-A; docs/codesign.md), as a value type
// with the paper's defaults. Where the paper is silent the choice is ours and is marked "(ours)".
#include <cstddef>
#include <cstdint>
#include <numbers>

#include "base/enum_names.hpp"
#include "core/physics_randomization.hpp"

namespace codesign::core {

// Which observation the policy sees (whisker_env.hpp lists the components):
//   Paper          {j, p, ε}      the paper's main framework (default)
//   Proprioceptive {j, p, ε, θ}   ours: the motor encoder's base angle added
//   NoFeedback     {p}            the paper's no-feedback baseline: ε and morphology removed
enum class ObservationSet { Paper, Proprioceptive, NoFeedback };
inline constexpr EnumNames<ObservationSet, 3> kObservationSetNames{{{ObservationSet::Paper, "paper"},
                                                                    {ObservationSet::Proprioceptive, "proprioceptive"},
                                                                    {ObservationSet::NoFeedback, "no_feedback"}}};
inline const char* to_string(ObservationSet s) { return name_of(kObservationSetNames, s).data(); }

// What the strain observation is measured from (ours; the paper does not say):
//   None      ε as the simulator reports it, scaled by [strain_min, strain_max]. Inflating the
//             chambers moves ε a hundred times more than the contact force does (docs/codesign.md
//             "How hard the task is"), so the force is a 1e-3 sliver of this scale.
//   Inflated  ε − ε₀, with ε₀ the strain of the same design at the same pressures, at θ = 0 and
//             out of contact — the sensor zeroed after inflation, as one tares a strain gauge
//             before use — scaled by [zeroed_strain_min, zeroed_strain_max]. The default: with it
//             PPO learns the task about three times faster (docs/journal/results.md, "Zeroed
//             strain").
enum class StrainOffset { None, Inflated };

inline constexpr EnumNames<StrainOffset, 2> kStrainOffsetNames{{{StrainOffset::None, "none"},
                                                                {StrainOffset::Inflated, "inflated"}}};
inline const char* to_string(StrainOffset s) { return name_of(kStrainOffsetNames, s).data(); }

// What the policy is told of the body's stiffness, beside ε (ours; docs/codesign.md, "Physical
// uncertainty"). The tared ε − ε₀ cannot tell a stiff body from a soft one: in contact the plate
// imposes the displacement, so ε − ε₀ barely moves with E while the force scales with it.
//   None         nothing (the default).
//   Inflation    the gauge's two-point start-up reading g ε(p) + b − (g ε(0) + b) = g (ε(p) − ε(0)),
//                out of contact at the episode's pressures and at none: the chamber as its own
//                stiffness probe (the inflation strain grows as p / E up to the fibres). The offset
//                b cancels; the gain g stays, as it does in the contact reading, so their ratio
//                tracks E / g, what the force needs. Scaled by [0, strain_max]. Taken noiseless:
//                a robot at rest averages many samples at start-up.
//   TrueModulus  E / E_nominal of the episode's draw, scaled by [1 − r, 1 + r] of
//                [randomize] youngs_modulus: an upper bound for reference, not a reading any
//                robot has.
enum class StiffnessCue { None, Inflation, TrueModulus };
inline constexpr EnumNames<StiffnessCue, 3> kStiffnessCueNames{{{StiffnessCue::None, "none"},
                                                                {StiffnessCue::Inflation, "inflation"},
                                                                {StiffnessCue::TrueModulus, "true_modulus"}}};
inline const char* to_string(StiffnessCue s) { return name_of(kStiffnessCueNames, s).data(); }

// Numerical failure injection ([faults]; off by default): a test of the claim that a numerical
// failure of the simulator ends only the episode it happens in, with a logged reason
// ("numerical: <status>: <detail>" in episodes.csv) and a count in the results. A chosen
// training episode gets, just before its decision `at_decision`, either NaN chamber pressures
// (the simulator then reports non_finite) or a jump of the base by 180 degrees within one step,
// which turns the elements at the clamp inside out (inverted_element). Which episodes: the first
// episode of environment i in iteration k, counted c = k·ψ + i + 1 (ψ = designs_per_update),
// gets NaN pressure when c is a multiple of nan_pressure_every, else an inverted element when c
// is a multiple of inverted_element_every (0: never). Episodes restarted after it run clean, and
// the evaluation never injects.
enum class Fault { None, NanPressure, InvertedElement };

inline constexpr EnumNames<Fault, 3> kFaultNames{
    {{Fault::None, "none"}, {Fault::NanPressure, "nan_pressure"}, {Fault::InvertedElement, "inverted_element"}}};
inline const char* to_string(Fault f) { return name_of(kFaultNames, f).data(); }

struct FaultConfig {
  int nan_pressure_every = 0;      // in [0, 1e6]
  int inverted_element_every = 0;  // in [0, 1e6]
  int at_decision = 1;             // in [0, decisions per episode − 1]
  bool enabled() const { return nan_pressure_every > 0 || inverted_element_every > 0; }
  // The fault of the first episode of environment `env` in iteration k (envs per iteration).
  Fault fault_for(std::int64_t k, std::size_t env, std::size_t envs) const {
    const std::int64_t c = k * static_cast<std::int64_t>(envs) + static_cast<std::int64_t>(env) + 1;
    if (nan_pressure_every > 0 && c % nan_pressure_every == 0) return Fault::NanPressure;
    if (inverted_element_every > 0 && c % inverted_element_every == 0) return Fault::InvertedElement;
    return Fault::None;
  }
};

struct TaskConfig {
  int episode_steps = 250;        // simulation steps per episode (paper)
  int action_hold_steps = 5;      // an action is held for 5 steps -> 50 decisions (paper)
  double theta_max_rad = std::numbers::pi / 18.0;  // Δθ = a·θ_max (paper)
  double target_force_mN = 20.0;  // F_t (ours; inside the default scene's force swing at θ = 0)
  double tolerance_fraction = 0.2;  // band ±20 % of F_t (paper)
  double kappa = 1.5;             // raised-cosine exponent (paper)
  double smooth_penalty = 0.05;   // r_smooth = c·|Δθ|/θ_max (spec)
  double flip_penalty = 0.1;      // r_flip when sign(Δθ) flips (spec)
  // The episode ends early when fem::Sensors::theta_extreme is set, i.e. |θ| beyond the scene's
  // fem::SceneConfig::theta_limit_deg ([scene] theta_limit_deg): one limit, stated there.
  ObservationSet observation = ObservationSet::Paper;
  // Memory by stacking (ours): the last `history` decisions' time-varying observation
  // components (ε, and θ where observed) and their actions appended to the observation, in
  // [0, decisions per episode − 1]; 0 (the default, the paper's) appends nothing. With
  // history = decisions − 1 the observation holds the whole episode so far, so θ (the sum of the
  // policy's own actions) and the sum of past errors (a PI's integral) are linear functions of it.
  // whisker_env.hpp states the layout and the padding before the episode's first decision.
  int history = 0;
  // Reference range of ε for the observation's min–max scaling, measured by `codesign survey`
  // over all 110 designs, the pressure corners and θ0 ∈ {−θ_max, 0, θ_max}: ε ∈ [−0.000288,
  // 0.04166], widened by 10 % each side (docs/journal/codesign.md, "The survey as printed at its
  // commits").
  double strain_min = -0.004483;
  double strain_max = 0.04586;
  StrainOffset strain_offset = StrainOffset::Inflated;
  // Reference range of ε − ε₀ (strain_offset = "inflated"), measured by `codesign survey` over the
  // same episodes as strain_min/max: ε − ε₀ ∈ [−0.000893, 0.0000006], widened by 10 % each side
  // (docs/journal/codesign.md, "The survey as printed at its commits").
  double zeroed_strain_min = -0.0009826;
  double zeroed_strain_max = 0.00008997;
  // One more observation component for the body's stiffness (above); appended after the history.
  StiffnessCue stiffness_cue = StiffnessCue::None;
  // Chamber pressures p_i ∈ [0, pressure_max_kPa] (paper: 20 kPa): the observation's pressure
  // scale and the range of the design distribution's latent map.
  double pressure_max_kPa = 20.0;
  // [faults]: numerical failure injection for tests (above); off by default.
  FaultConfig faults;
  // [randomize]: physical uncertainty, drawn per episode (core/physics_randomization.hpp); off by
  // default.
  RandomizeConfig randomize;
};

}  // namespace codesign::core
