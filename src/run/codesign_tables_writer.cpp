#include "run/codesign_tables_writer.hpp"

#include <sstream>

#include "codesign/outer_loop.hpp"
#include "io/config_writer.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/codesign)

void write_task_table(std::ostream& out, const TaskConfig& c) {
  io::TomlTableWriter t(out, "task");
  t.integer("episode_steps", c.episode_steps);
  t.integer("action_hold_steps", c.action_hold_steps);
  t.number("theta_max_rad", c.theta_max_rad);
  t.number("target_force_mN", c.target_force_mN);
  t.number("tolerance_fraction", c.tolerance_fraction);
  t.number("kappa", c.kappa);
  t.number("smooth_penalty", c.smooth_penalty);
  t.number("flip_penalty", c.flip_penalty);
  t.string("observation", to_string(c.observation));
  // Written only when set, so that the config.toml (and the checkpoint fingerprint) of a run
  // without history is what it was before the key existed: such runs still resume.
  if (c.history != 0) t.integer("history", c.history);
  t.number("strain_min", c.strain_min);
  t.number("strain_max", c.strain_max);
  t.string("strain_offset", to_string(c.strain_offset));
  t.number("zeroed_strain_min", c.zeroed_strain_min);
  t.number("zeroed_strain_max", c.zeroed_strain_max);
  t.number("pressure_max_kPa", c.pressure_max_kPa);
}

void write_faults_table(std::ostream& out, const FaultConfig& c) {
  io::TomlTableWriter t(out, "faults");
  t.integer("nan_pressure_every", c.nan_pressure_every);
  t.integer("inverted_element_every", c.inverted_element_every);
  t.integer("at_decision", c.at_decision);
}

void write_codesign_table(std::ostream& out, const CodesignConfig& c) {
  io::TomlTableWriter t(out, "codesign");
  t.integer("total_timesteps", c.total_timesteps);
  t.integer("designs_per_update", c.designs_per_update);
  t.integer("exploitation_start", c.distribution.exploitation_start);
  t.integer("exploration_end", c.distribution.exploration_end);
  t.number("alpha", c.distribution.alpha);
  t.number("phi", c.distribution.phi);
  t.number("beta_start", c.distribution.beta_start);
  t.number("beta_end", c.distribution.beta_end);
  // Both written only when not the default, so that a ramp run's config.toml (and checkpoint
  // fingerprint) is what it was before the keys existed.
  if (c.distribution.beta_schedule != CodesignConfig{}.distribution.beta_schedule) t.string("beta_schedule", to_string(c.distribution.beta_schedule));
  if (c.distribution.entropy_end != CodesignConfig{}.distribution.entropy_end) t.number("entropy_end", c.distribution.entropy_end);
  t.integer("reward_buffer", c.distribution.reward_buffer);
  t.number("latent_mu0", c.distribution.latent_mu0);
  t.number("latent_sigma0", c.distribution.latent_sigma0);
  t.number("latent_sigma_min", c.distribution.latent_sigma_min);
  t.string("baseline", to_string(c.baseline));
  t.integer("single_design_index", c.single_design_index);
  t.number("single_design_p1_kPa", c.single_design_p1_kPa);
  t.number("single_design_p2_kPa", c.single_design_p2_kPa);
  t.boolean("random_plate_phase", c.random_plate_phase);
  t.degrees("plate_phase_deg", c.plate_phase_rad);
  t.integer("eval_episodes", c.eval_episodes);
  // Written only when not the default, so that the config fingerprints of runs from before the
  // key existed are unchanged (they resume).
  if (c.fixed_theta_phases != CodesignConfig{}.fixed_theta_phases) t.integer("fixed_theta_phases", c.fixed_theta_phases);
  t.integer("checkpoint_every", c.checkpoint_every);
  t.integer("seed", static_cast<std::int64_t>(c.seed));
}

std::string resolved_run_config(const fem::WhiskerModelSpec& spec, const fem::SceneConfig& scene,
                                const fem::SolverConfig& solver, const LoopConfig& loop) {
  std::ostringstream out;
  out << "# resolved by codesign: every key the run reads, with the value used\n\n";
  io::write_fem_tables(out, spec, scene, solver);
  write_task_table(out, loop.task);
  // Only a run that injects faults has the table: other runs keep their config text (and the
  // fingerprint of their checkpoints).
  if (loop.task.faults.enabled()) write_faults_table(out, loop.task.faults);
  write_codesign_table(out, loop.codesign);
  io::write_ppo_table(out, loop.ppo);
  return out.str();
}

}  // namespace codesign::run
