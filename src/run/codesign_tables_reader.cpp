#include "run/codesign_tables_reader.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fem/design.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/codesign)

TaskConfig read_task_config(io::TableReader& root) {
  io::TableReader t = root.table("task");
  TaskConfig c;
  c.episode_steps = static_cast<int>(t.integer("episode_steps", c.episode_steps, 1, 100000));
  c.action_hold_steps =
      static_cast<int>(t.integer("action_hold_steps", c.action_hold_steps, 1, c.episode_steps));
  if (c.episode_steps % c.action_hold_steps != 0) {
    t.fail("action_hold_steps", "must divide task.episode_steps (" +
                                    std::to_string(c.episode_steps) + ")");
  }
  c.theta_max_rad = t.number("theta_max_rad", c.theta_max_rad, 1e-6, std::numbers::pi / 2);
  c.target_force_mN = t.number("target_force_mN", c.target_force_mN, 1e-3, 1e4);
  c.tolerance_fraction = t.number("tolerance_fraction", c.tolerance_fraction, 1e-3, 1.0);
  c.kappa = t.number("kappa", c.kappa, 0.1, 10.0);
  c.smooth_penalty = t.number("smooth_penalty", c.smooth_penalty, 0.0, 10.0);
  c.flip_penalty = t.number("flip_penalty", c.flip_penalty, 0.0, 10.0);
  c.observation = t.choice("observation", c.observation, kObservationSetNames);
  c.history = static_cast<int>(t.integer("history", c.history, 0, c.episode_steps / c.action_hold_steps - 1));
  c.strain_min = t.number("strain_min", c.strain_min, -1.0, 1.0);
  c.strain_max = t.number("strain_max", c.strain_max, -1.0, 1.0);
  if (!(c.strain_max > c.strain_min))
    t.fail("strain_max", "must exceed task.strain_min (" + std::to_string(c.strain_min) + ")");
  c.strain_offset = t.choice("strain_offset", c.strain_offset, kStrainOffsetNames);
  c.zeroed_strain_min = t.number("zeroed_strain_min", c.zeroed_strain_min, -1.0, 1.0);
  c.zeroed_strain_max = t.number("zeroed_strain_max", c.zeroed_strain_max, -1.0, 1.0);
  if (!(c.zeroed_strain_max > c.zeroed_strain_min))
    t.fail("zeroed_strain_max", "must exceed task.zeroed_strain_min (" + std::to_string(c.zeroed_strain_min) + ")");
  c.pressure_max_kPa = t.number("pressure_max_kPa", c.pressure_max_kPa, 1e-3, 100.0);
  t.finish();
  io::TableReader f = root.table("faults");
  FaultConfig& fc = c.faults;
  fc.nan_pressure_every = static_cast<int>(f.integer("nan_pressure_every", fc.nan_pressure_every, 0, 1'000'000));
  fc.inverted_element_every =
      static_cast<int>(f.integer("inverted_element_every", fc.inverted_element_every, 0, 1'000'000));
  fc.at_decision = static_cast<int>(
      f.integer("at_decision", fc.at_decision, 0, c.episode_steps / c.action_hold_steps - 1));
  f.finish();
  return c;
}

CodesignConfig read_codesign_config(io::TableReader& root, const TaskConfig& task) {
  io::TableReader t = root.table("codesign");
  CodesignConfig c;
  c.total_timesteps = t.integer("total_timesteps", c.total_timesteps, 1, 1'000'000'000);
  c.designs_per_update = static_cast<int>(t.integer("designs_per_update", c.designs_per_update, 1, 1024));
  c.distribution.exploitation_start = t.integer("exploitation_start", c.distribution.exploitation_start, 1, 1'000'000'000);
  c.distribution.exploration_end = t.integer("exploration_end", c.distribution.exploration_end, 0, c.distribution.exploitation_start - 1);
  c.distribution.alpha = t.number("alpha", c.distribution.alpha, 1e-9, 1.0);
  c.distribution.phi = t.number("phi", c.distribution.phi, 0.0, 1.0);
  c.distribution.beta_start = t.number("beta_start", c.distribution.beta_start, 0.0, 1e3);
  c.distribution.beta_end = t.number("beta_end", c.distribution.beta_end, 0.0, 1e3);
  c.distribution.beta_schedule = t.choice("beta_schedule", c.distribution.beta_schedule, kBetaScheduleNames);
  // At most ln 110 = 4.70048: the entropy of the uniform distribution over the designs, q_disc at T1.
  const double max_entropy = std::log(static_cast<double>(fem::kDesignCount));
  c.distribution.entropy_end = t.number("entropy_end", c.distribution.entropy_end, 0.0, max_entropy);
  c.distribution.reward_buffer = static_cast<int>(t.integer("reward_buffer", c.distribution.reward_buffer, 2, 100000));
  c.distribution.latent_mu0 = t.number("latent_mu0", c.distribution.latent_mu0, -10.0, 10.0);
  c.distribution.latent_sigma0 = t.number("latent_sigma0", c.distribution.latent_sigma0, 1e-6, 10.0);
  c.distribution.latent_sigma_min = t.number("latent_sigma_min", c.distribution.latent_sigma_min, 1e-9, c.distribution.latent_sigma0);
  c.baseline = t.choice("baseline", c.baseline, kBaselineNames);
  c.single_design_index =
      static_cast<int>(t.integer("single_design_index", c.single_design_index, 0, fem::kDesignCount - 1));
  c.single_design_p1_kPa = t.number("single_design_p1_kPa", c.single_design_p1_kPa, 0.0, task.pressure_max_kPa);
  c.single_design_p2_kPa = t.number("single_design_p2_kPa", c.single_design_p2_kPa, 0.0, task.pressure_max_kPa);
  c.random_plate_phase = t.boolean("random_plate_phase", c.random_plate_phase);
  c.plate_phase_rad = t.number("plate_phase_deg", 0.0, -360.0, 360.0) * std::numbers::pi / 180.0;
  c.eval_episodes = static_cast<int>(t.integer("eval_episodes", c.eval_episodes, 1, 100000));
  c.fixed_theta_phases = static_cast<int>(t.integer("fixed_theta_phases", c.fixed_theta_phases, 0, 10000));
  c.checkpoint_every = t.integer("checkpoint_every", c.checkpoint_every, 1, 1'000'000'000);
  c.seed = static_cast<std::uint64_t>(t.integer("seed", 1, 0, std::int64_t{1} << 62));
  t.finish();
  return c;
}

namespace {

// A [lo, hi] pair of numbers in [min, max] with lo <= hi.
std::array<double, 2> read_pair(io::TableReader& t, const char* key, std::array<double, 2> def, double min, double max) {
  const std::vector<double> v = t.numbers(key, {def[0], def[1]}, min, max, 2, 2);
  if (v[0] > v[1]) t.fail(key, "lower bound " + std::to_string(v[0]) + " is above upper bound " + std::to_string(v[1]));
  return {v[0], v[1]};
}

}  // namespace

PidTuningConfig read_pid_config(io::TableReader& root) {
  io::TableReader t = root.table("pid");
  PidTuningConfig c;
  c.box.kp = read_pair(t, "kp_range", c.box.kp, 0.0, 100.0);
  c.box.ki = read_pair(t, "ki_range", c.box.ki, 0.0, 100.0);
  c.box.kd = read_pair(t, "kd_range", c.box.kd, 0.0, 100.0);
  c.box.offset = read_pair(t, "strain_offset_range", c.box.offset, -100.0, 100.0);
  const std::vector<double> g = t.numbers("start_gains", {c.start.kp, c.start.ki, c.start.kd}, 0.0, 100.0, 3, 3);
  c.start = {g[0], g[1], g[2]};
  c.strain_scale = t.number("strain_scale", c.strain_scale, 1e-9, 1.0);
  c.tuning_phases = static_cast<int>(t.integer("tuning_phases", c.tuning_phases, 1, 1000));
  c.test_episodes = static_cast<int>(t.integer("test_episodes", c.test_episodes, 1, 100000));
  c.estimator_fit_episodes =
      static_cast<int>(t.integer("estimator_fit_episodes", c.estimator_fit_episodes, 1, 1000));
  c.search.method = t.choice("method", c.search.method, kLocalMethodNames);
  c.search.starts = static_cast<int>(t.integer("starts", c.search.starts, 1, 100));
  c.search.max_evals = static_cast<int>(t.integer("max_evals", c.search.max_evals, c.search.starts, 100000));
  c.search.xtol_rel = t.number("xtol_rel", c.search.xtol_rel, 0.0, 0.5);
  c.search.ftol_abs = t.number("ftol_abs", c.search.ftol_abs, 0.0, 1.0);
  t.finish();
  c.validate();  // every field was range-checked above; this cannot fail
  return c;
}

SweepConfig read_sweep_config(io::TableReader& root, const TaskConfig& task) {
  io::TableReader t = root.table("sweep");
  SweepConfig c;
  c.pressures_kPa = t.numbers("pressures_kPa", c.pressures_kPa, 0.0, task.pressure_max_kPa, 1, 21);
  c.controllers.clear();
  if (t.boolean("fixed_theta", true)) c.controllers.push_back(SweepController::FixedTheta);
  if (t.boolean("pid_force", true)) c.controllers.push_back(SweepController::PidForce);
  if (t.boolean("pid_strain", true)) c.controllers.push_back(SweepController::PidStrain);
  if (t.boolean("pid_estimate", true)) c.controllers.push_back(SweepController::PidEstimate);
  if (c.controllers.empty())
    t.fail("pid_estimate", "fixed_theta, pid_force, pid_strain and pid_estimate are all false: nothing to sweep");
  c.fixed_theta.scan_points =
      static_cast<int>(t.integer("fixed_theta_scan_points", c.fixed_theta.scan_points, 3, 1001));
  c.fixed_theta.max_evals = static_cast<int>(t.integer("fixed_theta_max_evals", c.fixed_theta.max_evals, 1, 10000));
  c.first_design = static_cast<int>(t.integer("first_design", c.first_design, 0, fem::kDesignCount - 1));
  c.last_design = static_cast<int>(t.integer("last_design", c.last_design, c.first_design, fem::kDesignCount - 1));
  t.finish();
  c.validate();
  return c;
}

}  // namespace codesign::run
