#include "run/run_telemetry.hpp"

#include <chrono>
#include <limits>

#include "fem/design.hpp"

namespace codesign::run {

namespace {

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

codesign_lcm::sim_step_t sim_step_message(const core::EpisodeSetup& setup, const core::TraceRow& r, std::int64_t t) {
  codesign_lcm::sim_step_t m{};
  m.timestep = t;
  m.t_s = r.t_s;
  m.theta_rad = r.theta_rad;
  m.force_mN = r.force_mN;
  m.strain = r.strain;
  for (int i = 0; i < 3; ++i) m.tip_mm[i] = r.tip_mm[i];
  m.plate_z_mm = r.plate_z_mm;
  m.design = setup.design;
  m.pressures_kPa[0] = setup.p1_kPa;
  m.pressures_kPa[1] = setup.p2_kPa;
  m.decision = r.decision;
  m.action = r.action;
  return m;
}

codesign_lcm::episode_t episode_message(const core::IterationReport& rep, const core::EpisodeRecord& e) {
  const fem::Design d = fem::design_from_index(e.setup.design);
  codesign_lcm::episode_t m{};
  m.timestep = rep.t;
  m.iteration = rep.k;
  m.env = e.env;
  m.design = e.setup.design;
  m.n_chambers = d.n;
  m.l_mm = d.chamber_length_mm;
  m.w_mm = d.wall_mm;
  m.pressures_kPa[0] = e.setup.p1_kPa;
  m.pressures_kPa[1] = e.setup.p2_kPa;
  m.phase_rad = e.setup.plate_phase_rad;
  m.episode_return = e.episode_return;
  m.decisions = e.decisions;
  m.in_band = e.in_band;
  m.first = e.first;
  m.reason = e.reason;
  return m;
}

codesign_lcm::ppo_update_t ppo_message(const core::IterationReport& rep, double steps_per_s) {
  const rl::PpoStats& p = rep.ppo;
  codesign_lcm::ppo_update_t u{};
  u.iteration = rep.k;
  u.timestep = rep.t;
  u.pg_loss = p.pg_loss;
  u.value_loss = p.value_loss;
  u.entropy_loss = p.entropy_loss;
  u.loss = p.loss;
  u.approx_kl = p.approx_kl;
  u.clip_fraction = p.clip_fraction;
  u.explained_variance = p.explained_variance;
  u.learning_rate = rep.learning_rate;
  u.ent_coef = p.ent_coef;
  u.epochs = p.epochs_done;
  u.early_stopped = p.early_stopped;
  u.grad_norm = p.grad_norm;
  u.collect_s = rep.collect_s;
  u.update_s = rep.update_s;
  u.policy_s = rep.policy_s;
  u.steps_per_s = steps_per_s;
  return u;
}

codesign_lcm::distribution_t distribution_message(const core::IterationReport& rep, const DistributionSummary& sum) {
  codesign_lcm::distribution_t q{};
  q.iteration = rep.k;
  q.timestep = rep.t;
  q.phase = core::to_string(sum.phase);
  q.beta = rep.beta;
  q.entropy = sum.entropy;
  q.target_entropy = sum.target_entropy.value_or(std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index j = 0; j < sum.q.size() && j < 110; ++j) q.probabilities[j] = sum.q[j];
  q.best_design = sum.best;
  q.best_score = sum.best_score;
  q.best_mu_kPa[0] = sum.mu[0];
  q.best_mu_kPa[1] = sum.mu[1];
  q.best_sigma_kPa[0] = sum.sigma[0];
  q.best_sigma_kPa[1] = sum.sigma[1];
  return q;
}

}  // namespace

RunTelemetry::Timed::Timed(RunTelemetry& owner, std::int64_t messages) : owner_(owner), start_ns_(now_ns()) {
  owner_.messages_.fetch_add(messages, std::memory_order_relaxed);
}

RunTelemetry::Timed::~Timed() { owner_.ns_.fetch_add(now_ns() - start_ns_, std::memory_order_relaxed); }

RunTelemetry::RunTelemetry(const std::string& url, int train_every)
    : telemetry_(io::make_telemetry(url)), train_every_(train_every) {}

void RunTelemetry::observe_training(core::OuterLoop& loop) {
  start_iteration(loop.timesteps());
  if (!enabled()) return;
  if (train_every_ > 0) {
    loop.envs().set_step_observer(
        0,
        [this](const core::EpisodeSetup& s, const core::TraceRow& r) {
          const Timed timed(*this, 1);
          telemetry_->publish_training(sim_step_message(s, r, iteration_start_t_.load(std::memory_order_relaxed)));
        },
        train_every_);
  }
  if (loop.recurrent_model()) {
    loop.set_memory_observer([this](int decision, int design, const Eigen::VectorXf& a, const Eigen::VectorXf& c) {
      const Timed timed(*this, 1);
      codesign_lcm::policy_memory_t m{};
      m.timestep = iteration_start_t_.load(std::memory_order_relaxed);
      m.decision = decision;
      m.design = design;
      m.units = static_cast<std::int32_t>(a.size());
      m.actor_h.assign(a.data(), a.data() + a.size());
      m.critic_h.assign(c.data(), c.data() + c.size());
      m.actor_norm = a.cast<double>().norm();
      m.critic_norm = c.cast<double>().norm();
      telemetry_->publish(m);
    });
  }
}

void RunTelemetry::publish_iteration(const core::IterationReport& rep, const DistributionSummary& summary,
                                     double steps_per_s) {
  if (!enabled()) return;
  const Timed timed(*this, static_cast<std::int64_t>(rep.episodes.size()) + 2);
  for (const core::EpisodeRecord& e : rep.episodes) telemetry_->publish(episode_message(rep, e));
  telemetry_->publish(ppo_message(rep, steps_per_s));
  telemetry_->publish(distribution_message(rep, summary));
}

void RunTelemetry::publish_trace(const core::DesignEvaluation& e, std::int64_t t) {
  if (!enabled()) return;
  const Timed timed(*this, static_cast<std::int64_t>(e.trace.size()));
  for (const core::TraceRow& r : e.trace) telemetry_->publish(sim_step_message(e.setup, r, t));
}

}  // namespace codesign::run
