#pragma once
// The co-design's config tables, each key described once (base/config_keys.hpp says how the
// readers, the writer, the checks and the reference page use these lists):
//
//   [task]      core::TaskConfig (the episode, the reward, the observation)
//   [faults]    core::FaultConfig (injected failures, for testing a run's robustness)
//   [codesign]  core::CodesignConfig (the outer loop and its design distribution)
//   [pid]       core::PidTuningConfig (the PID baselines' tuning, `codesign baseline`)
//   [sweep]     core::SweepConfig (the design landscape, `codesign sweep`)
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "base/config_keys.hpp"
#include "core/codesign_config.hpp"
#include "core/design_sweep.hpp"
#include "core/pid_tuning.hpp"
#include "core/task_config.hpp"
#include "fem/design.hpp"

namespace codesign::core {

template <class V>
void describe_task_table(V& v, TaskConfig& c) {
  v.integer({"episode_steps", "", "simulation steps per episode (paper: 250)"}, c.episode_steps, {1, 100000});
  v.integer({.name = "action_hold_steps", .unit = "", .meaning = "steps an action is held: a decision every this many steps (paper: 5)", .range_note = "[1, episode_steps], dividing it"},
            c.action_hold_steps, {1, c.episode_steps});
  v.require(c.episode_steps % c.action_hold_steps == 0, "action_hold_steps",
            [&] { return "must divide task.episode_steps (" + std::to_string(c.episode_steps) + ")"; });
  const int decisions = c.episode_steps / c.action_hold_steps;
  v.number({"theta_max_rad", "rad", "largest change of the base angle per decision, Δθ = a θ_max"}, c.theta_max_rad,
           {1e-6, 1.5707963267948966});
  v.number({"target_force_mN", "mN", "target contact force F_t"}, c.target_force_mN, {1e-3, 1e4});
  v.number({"tolerance_fraction", "", "half-width of the reward's band, as a fraction of F_t (paper: 0.2)"},
           c.tolerance_fraction, {1e-3, 1.0});
  v.number({"kappa", "", "exponent of the raised-cosine force reward (paper: 1.5)"}, c.kappa, {0.1, 10.0});
  v.number({"smooth_penalty", "", "penalty per |Δθ| / θ_max of a decision"}, c.smooth_penalty, {0.0, 10.0});
  v.number({"flip_penalty", "", "penalty when Δθ changes sign"}, c.flip_penalty, {0.0, 10.0});
  v.choice({"observation", "", "what the policy observes (docs/codesign.md, \"Observation\")"}, c.observation,
           kObservationSetNames);
  v.integer({.name = "history", .unit = "", .meaning = "earlier decisions' observations appended to the observation", .written = config::Written::UnlessDefault, .at_default = c.history == TaskConfig{}.history, .range_note = "[0, decisions per episode − 1]"},
            c.history, {0, decisions - 1});
  v.number({"strain_min", "", "strain ε mapped to −1 in the observation (surveyed over the designs)"}, c.strain_min,
           {-1.0, 1.0});
  v.number({.name = "strain_max", .unit = "", .meaning = "strain ε mapped to +1 in the observation",
            .range_note = "[-1, 1], above strain_min"},
           c.strain_max, {-1.0, 1.0});
  v.require(c.strain_max > c.strain_min, "strain_max",
            [&] { return "must exceed task.strain_min (" + std::to_string(c.strain_min) + ")"; });
  v.choice({"strain_offset", "", "strain observed as is (\"none\") or less the strain at inflation (\"inflated\")"},
           c.strain_offset, kStrainOffsetNames);
  v.number({"zeroed_strain_min", "", "ε − ε₀ mapped to −1 (strain_offset = \"inflated\")"}, c.zeroed_strain_min,
           {-1.0, 1.0});
  v.number({.name = "zeroed_strain_max", .unit = "", .meaning = "ε − ε₀ mapped to +1", .range_note = "[-1, 1], above zeroed_strain_min"},
           c.zeroed_strain_max, {-1.0, 1.0});
  v.require(c.zeroed_strain_max > c.zeroed_strain_min, "zeroed_strain_max", [&] {
    return "must exceed task.zeroed_strain_min (" + std::to_string(c.zeroed_strain_min) + ")";
  });
  v.choice({.name = "stiffness_cue", .unit = "",
            .meaning = "stiffness reading appended to the observation: \"inflation\" (the gauge at p less at 0) or "
                       "\"true_modulus\" (a reference bound)",
            .written = config::Written::UnlessDefault, .at_default = c.stiffness_cue == TaskConfig{}.stiffness_cue},
           c.stiffness_cue, kStiffnessCueNames);
  v.number({"pressure_max_kPa", "kPa", "largest chamber pressure a design may be given (paper: 20)"},
           c.pressure_max_kPa, {1e-3, 100.0});
}

// decisions: decisions per episode ([task]).
template <class V>
void describe_faults_table(V& v, FaultConfig& c, int decisions) {
  v.integer({"nan_pressure_every", "", "every n-th episode gets a NaN chamber pressure (0: never)"},
            c.nan_pressure_every, {0, 1'000'000});
  v.integer({"inverted_element_every", "", "every n-th episode gets an inverted element (0: never)"},
            c.inverted_element_every, {0, 1'000'000});
  v.integer({.name = "at_decision", .unit = "", .meaning = "the decision at which a fault strikes", .range_note = "[0, decisions per episode − 1]"},
            c.at_decision, {0, decisions - 1});
}

// pressure_max_kPa: [task] pressure_max_kPa.
template <class V>
void describe_codesign_table(V& v, CodesignConfig& c, double pressure_max_kPa) {
  DistributionConfig& d = c.distribution;
  const CodesignConfig defaults;
  v.integer({"total_timesteps", "", "T: decisions over all environments (paper: 1 000 000)"}, c.total_timesteps,
            {1, 1'000'000'000});
  v.integer({"designs_per_update", "", "ψ: designs sampled, and environments, per iteration (paper: 40)"},
            c.designs_per_update, {1, 1024});
  v.integer({"exploitation_start", "", "T2: decisions after which β stays at beta_end"}, d.exploitation_start,
            {1, 1'000'000'000});
  v.integer({.name = "exploration_end", .unit = "", .meaning = "T1: decisions of uniform exploration (paper: 220 000)", .range_note = "[0, exploitation_start − 1]"},
            d.exploration_end, {0, d.exploitation_start - 1});
  v.number({"alpha", "", "step of the distribution's natural-gradient update (paper: 0.1)"}, d.alpha, {1e-9, 1.0});
  v.number({"phi", "", "tracking rate of the reward baseline (paper: 0.05)"}, d.phi, {0.0, 1.0});
  v.number({"beta_start", "", "β of q_disc = softmax(β R̂) at T1 (ramp)"}, d.beta_start, {0.0, 1e3});
  v.number({"beta_end", "", "β at T2 (ramp)"}, d.beta_end, {0.0, 1e3});
  v.choice({.name = "beta_schedule", .unit = "", .meaning = "β from T1 on: \"ramp\" (linear) or \"entropy\" (q_disc's entropy decays to "
                                 "entropy_end)", .written = config::Written::UnlessDefault, .at_default = d.beta_schedule == defaults.distribution.beta_schedule},
           d.beta_schedule, kBetaScheduleNames);
  // At most ln 110 = 4.70048: the entropy of the uniform distribution over the designs.
  v.number({.name = "entropy_end", .unit = "nats", .meaning = "entropy of q_disc at T2 (beta_schedule = \"entropy\")", .written = config::Written::UnlessDefault, .at_default = d.entropy_end == defaults.distribution.entropy_end, .range_note = "[0, ln 110]"},
           d.entropy_end, {0.0, std::log(static_cast<double>(fem::kDesignCount))});
  v.integer({"reward_buffer", "", "recent returns kept per design for its running statistics"}, d.reward_buffer,
            {2, 100000});
  v.number({"latent_mu0", "", "initial mean of the pressures' latent Gaussian"}, d.latent_mu0, {-10.0, 10.0});
  v.number({"latent_sigma0", "", "initial standard deviation of the latent Gaussian"}, d.latent_sigma0, {1e-6, 10.0});
  v.number({.name = "latent_sigma_min", .unit = "", .meaning = "floor of the latent Gaussian's standard deviation", .range_note = "[1e-9, latent_sigma0]"},
           d.latent_sigma_min, {1e-9, d.latent_sigma0});
  v.choice({"baseline", "", "\"none\" (co-design) or \"single_design\" (train on one fixed design)"}, c.baseline,
           kBaselineNames);
  v.integer({"single_design_index", "", "design j of the single-design baseline"}, c.single_design_index,
            {0, fem::kDesignCount - 1});
  v.number({.name = "single_design_p1_kPa", .unit = "kPa", .meaning = "chamber 1 pressure of the single-design baseline", .range_note = "[0, task.pressure_max_kPa]"},
           c.single_design_p1_kPa, {0.0, pressure_max_kPa});
  v.number({.name = "single_design_p2_kPa", .unit = "kPa", .meaning = "chamber 2 pressure of the single-design baseline", .range_note = "[0, task.pressure_max_kPa]"},
           c.single_design_p2_kPa, {0.0, pressure_max_kPa});
  v.boolean({"random_plate_phase", "", "each training episode draws the plate's phase"}, c.random_plate_phase);
  v.degrees({"plate_phase_deg", "deg", "the plate's phase when random_plate_phase is false"}, c.plate_phase_rad,
            {-360.0, 360.0});
  v.integer({"eval_episodes", "", "final evaluation: episodes (plate phases) per design"}, c.eval_episodes,
            {1, 100000});
  v.integer({.name = "fixed_theta_phases", .unit = "", .meaning = "plate phases of the fixed-θ reference of the evaluation", .written = config::Written::UnlessDefault, .at_default = c.fixed_theta_phases == defaults.fixed_theta_phases},
            c.fixed_theta_phases, {0, 10000});
  v.integer({"checkpoint_every", "", "decisions between checkpoints"}, c.checkpoint_every, {1, 1'000'000'000});
  v.integer({"seed", "", "seed of every random stream of the run"}, c.seed, {0, std::int64_t{1} << 62});
}

// A [lo, hi] pair of numbers in `each`, lo ≤ hi.
template <class V>
void describe_pair(V& v, const config::Key& k, std::array<double, 2>& f, Range<double> each) {
  std::vector<double> x{f[0], f[1]};
  v.numbers(k, x, each, {2, 2});
  v.require(x[0] <= x[1], k.name, [&] {
    return "lower bound " + std::to_string(x[0]) + " is above upper bound " + std::to_string(x[1]);
  });
  f = {x[0], x[1]};
}

template <class V>
void describe_pid_table(V& v, PidTuningConfig& c) {
  describe_pair(v, {"kp_range", "", "search box of the proportional gain [lo, hi] (action per band unit)"}, c.box.kp,
                {0.0, 100.0});
  describe_pair(v, {"ki_range", "", "search box of the integral gain [lo, hi]"}, c.box.ki, {0.0, 100.0});
  describe_pair(v, {"kd_range", "", "search box of the derivative gain [lo, hi]"}, c.box.kd, {0.0, 100.0});
  describe_pair(v, {"strain_offset_range", "", "search box of the strain PID's setpoint offset, band units"},
                c.box.offset, {-100.0, 100.0});
  std::vector<double> gains{c.start.kp, c.start.ki, c.start.kd};
  v.numbers({"start_gains", "", "first start of the search [kp, ki, kd]"}, gains, {0.0, 100.0}, {3, 3});
  c.start = {gains[0], gains[1], gains[2]};
  v.number({"strain_scale", "", "strain per band half-width of the strain PID"}, c.strain_scale, {1e-9, 1.0});
  v.integer({"tuning_phases", "", "plate phases of each tuning evaluation"}, c.tuning_phases, {1, 1000});
  v.integer({"test_episodes", "", "test episodes of each tuned PID"}, c.test_episodes, {1, 100000});
  v.integer({"estimator_fit_episodes", "", "open-loop episodes of the force estimate's fit"}, c.estimator_fit_episodes,
            {1, 1000});
  v.choice({"method", "", "NLopt local method of the search"}, c.search.method, kLocalMethodNames);
  v.integer({"starts", "", "starts of the local search"}, c.search.starts, {1, 100});
  v.integer({.name = "max_evals", .unit = "", .meaning = "evaluations over all starts", .range_note = "[starts, 100000]"},
            c.search.max_evals, {c.search.starts, 100000});
  v.number({"xtol_rel", "", "a start stops when its steps are below this × the box"}, c.search.xtol_rel, {0.0, 0.5});
  v.number({"ftol_abs", "", "a start stops when the return changes by less"}, c.search.ftol_abs, {0.0, 1.0});
}

// pressure_max_kPa: [task] pressure_max_kPa.
template <class V>
void describe_sweep_table(V& v, SweepConfig& c, double pressure_max_kPa) {
  v.numbers({.name = "pressures_kPa", .unit = "kPa", .meaning = "pressures of each chamber swept (pairs for n = 2)",
             .range_note = "each in [0, task.pressure_max_kPa], 1 to 21 of them"},
            c.pressures_kPa, {0.0, pressure_max_kPa}, {1, 21});
  const auto has = [&](SweepController s) {
    for (SweepController x : c.controllers)
      if (x == s) return true;
    return false;
  };
  std::array<bool, 4> on{has(SweepController::FixedTheta), has(SweepController::PidForce),
                         has(SweepController::PidStrain), has(SweepController::PidEstimate)};
  v.boolean({"fixed_theta", "", "sweep the best fixed base angle"}, on[0]);
  v.boolean({"pid_force", "", "sweep a PID on the true force"}, on[1]);
  v.boolean({"pid_strain", "", "sweep a PID on the strain"}, on[2]);
  v.boolean({"pid_estimate", "", "sweep a PID on the force estimated from the strain"}, on[3]);
  v.require(on[0] || on[1] || on[2] || on[3], "pid_estimate", [] {
    return std::string("fixed_theta, pid_force, pid_strain and pid_estimate are all false: nothing to sweep");
  });
  c.controllers.clear();
  for (std::size_t i = 0; i < on.size(); ++i)
    if (on[i]) c.controllers.push_back(kSweepControllerNames[i].value);
  v.integer({"fixed_theta_scan_points", "", "fixed θ: points of the first scan"}, c.fixed_theta.scan_points, {3, 1001});
  v.integer({"fixed_theta_max_evals", "", "fixed θ: evaluations of the refinement"}, c.fixed_theta.max_evals,
            {1, 10000});
  v.integer({"first_design", "", "first design j swept"}, c.first_design, {0, fem::kDesignCount - 1});
  v.integer({.name = "last_design", .unit = "", .meaning = "last design j swept", .range_note = "[first_design, 109]"},
            c.last_design, {c.first_design, fem::kDesignCount - 1});
}

}  // namespace codesign::core
