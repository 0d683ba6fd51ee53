#include "core/whisker_env.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "base/thread_cpu_seconds.hpp"
#include "fem/design.hpp"

namespace codesign::core {

namespace {

// x ∈ [lo, hi] → [−1, 1], clipped to ±kObservationClip.
// The pressure a chamber holds when the policy asks for p: p (1 + e) under a drawn error.
double actual_kPa(double p, double scale) { return scale == 1.0 ? p : p * scale; }

double scaled(double x, double lo, double hi) {
  const double s = 2.0 * (x - lo) / (hi - lo) - 1.0;
  return std::clamp(s, -kObservationClip, kObservationClip);
}

rl::EnvSpec make_spec(const TaskConfig& task, bool privileged) {
  const auto n = static_cast<Eigen::Index>(observation_dim(task) + (privileged ? kPrivilegedDim : 0));
  rl::EnvSpec s;
  s.observation.low = Eigen::VectorXd::Constant(n, -kObservationClip);
  s.observation.high = Eigen::VectorXd::Constant(n, kObservationClip);
  s.action.low = Eigen::VectorXd::Constant(1, -1.0);
  s.action.high = Eigen::VectorXd::Constant(1, 1.0);
  return s;
}

// A failure reason as one CSV cell of the logs: no comma, quote or line break.
std::string reason_cell(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '"' || c == '\n' || c == '\r') c = c == ',' ? ';' : ' ';
  return s;
}

}  // namespace

double force_reward(double force_mN, const TaskConfig& task) {
  const double delta = std::abs(force_mN - task.target_force_mN) / (task.tolerance_fraction * task.target_force_mN);
  if (!(delta < 1.0)) return 0.0;
  return std::pow(0.5 * (1.0 + std::cos(std::numbers::pi * delta)), task.kappa);
}

bool in_band(double force_mN, const TaskConfig& task) {
  return std::abs(force_mN - task.target_force_mN) < task.tolerance_fraction * task.target_force_mN;
}

namespace {

int set_dim(ObservationSet set) {
  switch (set) {
    case ObservationSet::Paper: return 6;
    case ObservationSet::Proprioceptive: return 7;
    case ObservationSet::NoFeedback: return 2;
  }
  return 0;
}

}  // namespace

int dynamic_observation_dim(ObservationSet set) {
  switch (set) {
    case ObservationSet::Paper: return 1;
    case ObservationSet::Proprioceptive: return 2;
    case ObservationSet::NoFeedback: return 0;
  }
  return 0;
}

int observation_dim(const TaskConfig& task) {
  return set_dim(task.observation) + task.history * (dynamic_observation_dim(task.observation) + 1) +
         (task.stiffness_cue != StiffnessCue::None ? 1 : 0);
}

WhiskerEnv::WhiskerEnv(std::shared_ptr<SimulatorPool> pool, const TaskConfig& task, bool privileged)
    : pool_(std::move(pool)), task_(task), privileged_(privileged), spec_(make_spec(task, privileged)) {
  if (!pool_) throw std::invalid_argument("WhiskerEnv: no simulator pool");
  if (task_.episode_steps % task_.action_hold_steps != 0)
    throw std::invalid_argument("WhiskerEnv: action_hold_steps must divide episode_steps");
  if (task_.history < 0 || task_.history >= decisions_per_episode())
    throw std::invalid_argument("WhiskerEnv: history must lie in [0, decisions per episode - 1]");
  history_obs_ = Eigen::VectorXd::Zero(task_.history * dynamic_observation_dim(task_.observation));
  history_actions_ = Eigen::VectorXd::Zero(task_.history);
}

WhiskerEnv::~WhiskerEnv() { give_back_simulator(); }

PhysicsDraw WhiskerEnv::simulator_draw() const {
  PhysicsDraw d = setup_.physics.simulation_part();
  d.pressure_scale_1 = d.pressure_scale_2 = 1.0;  // set on the simulator, not built into it
  return d;
}

void WhiskerEnv::give_back_simulator() {
  if (!sim_) return;
  if (sim_draw_ == PhysicsDraw{}) pool_->release(sim_design_, std::move(sim_));
  sim_.reset();
}

void WhiskerEnv::take_simulator() {
  const PhysicsDraw draw = simulator_draw();
  if (sim_ && sim_design_ == setup_.design && sim_draw_ == draw) return;
  give_back_simulator();
  if (draw == PhysicsDraw{}) {
    sim_ = pool_->acquire(setup_.design);
  } else {
    const std::shared_ptr<const fem::Model> nominal = pool_->cast_model(setup_.design, draw.wall_offset_mm);
    sim_ = std::make_unique<fem::Simulator>(draw.body().nominal() ? nominal : fem::scaled_model(*nominal, draw.body()),
                                            draw.scene(pool_->scene()), pool_->solver());
  }
  sim_design_ = setup_.design;
  sim_draw_ = draw;
  settled_setup_.reset();
}

void WhiskerEnv::take_readings() {
  const fem::Sensors s = sim_->sensors();
  const PhysicsDraw& d = setup_.physics;
  // Nominal fields leave the true values untouched, to the bit.
  observed_strain_ = d.gauge(s.axial_strain);
  if (d.strain_noise > 0.0) observed_strain_ += d.strain_noise * noise_rng_.normal();
  observed_theta_ = s.theta_rad;
  if (d.encoder_noise_rad > 0.0) observed_theta_ += d.encoder_noise_rad * noise_rng_.normal();
}

fem::Sensors WhiskerEnv::readings() const {
  fem::Sensors s = sim_->sensors();
  s.axial_strain = observed_strain_;
  s.theta_rad = observed_theta_;
  return s;
}

void WhiskerEnv::set_episode(const EpisodeSetup& setup) {
  (void)fem::design_from_index(setup.design);  // throws std::out_of_range for a bad index
  setup_ = setup;
  fault_ = setup.fault;
  setup_.fault = Fault::None;
}

int WhiskerEnv::decisions_per_episode() const { return task_.episode_steps / task_.action_hold_steps; }

Eigen::VectorXd WhiskerEnv::reset(std::optional<std::uint64_t> /*seed*/) {
  take_simulator();
  decision_ = 0;
  pending_dtheta_ = 0.0;
  noise_rng_ = rl::Rng(setup_.physics.noise_seed);
  episode_fault_ = std::exchange(fault_, Fault::None);
  in_band_ = 0;
  last_dtheta_ = 0.0;
  trace_.clear();
  const double t0 = thread_cpu_seconds();
  fem::StepResult r;
  if (settled_setup_ && *settled_setup_ == setup_) {
    r = sim_->restore(settled_);
  } else {
    settled_setup_.reset();
    r = update_strain_zero();
    if (r.ok()) {
      sim_->reset();
      sim_->set_pressures_kPa(actual_kPa(setup_.p1_kPa, setup_.physics.pressure_scale_1),
                              actual_kPa(setup_.p2_kPa, setup_.physics.pressure_scale_2));
      sim_->set_plate_phase(setup_.plate_phase_rad);
      if (setup_.theta0_rad != 0.0) sim_->set_base_angle(setup_.theta0_rad);
      r = sim_->settle();
    }
    if (r.ok()) {
      settled_ = sim_->snapshot();
      settled_setup_ = setup_;
    }
  }
  settle_s_ += thread_cpu_seconds() - t0;
  reset_failure_ = r.ok() ? std::string() : std::string(fem::to_string(r.status)) + ": " + r.reason;
  take_readings();
  if (recording_ && r.ok()) record(0.0);
  clear_history();
  return observe();
}

void WhiskerEnv::clear_history() {
  if (task_.history == 0) return;
  const Eigen::VectorXd now = current_observation();
  const int dyn = dynamic_observation_dim(task_.observation);
  const int first = static_cast<int>(now.size()) - dyn;  // the dynamic components come last
  for (int c = 0; c < dyn; ++c) history_obs_.segment(c * task_.history, task_.history).setConstant(now[first + c]);
  history_actions_.setZero();
}

void WhiskerEnv::push_history(const Eigen::VectorXd& seen, double a) {
  const int k = task_.history;
  if (k == 0) return;
  const int dyn = dynamic_observation_dim(task_.observation);
  const int first = static_cast<int>(seen.size()) - dyn;
  for (int c = 0; c < dyn; ++c) {
    auto slots = history_obs_.segment(c * k, k);
    for (int i = k - 1; i > 0; --i) slots[i] = slots[i - 1];
    slots[0] = seen[first + c];
  }
  for (int i = k - 1; i > 0; --i) history_actions_[i] = history_actions_[i - 1];
  history_actions_[0] = a;
}

fem::StepResult WhiskerEnv::free_strain(double p1_kPa, double p2_kPa, double& strain) {
  // The same quasi-static loading as an episode's settle, with the plate far below the tip (a
  // metre: out of reach of any design at any angle), so the body ends inflated and free.
  constexpr double kPlateAway_mm = 1000.0;
  sim_->reset();
  sim_->set_pressures_kPa(actual_kPa(p1_kPa, setup_.physics.pressure_scale_1),
                          actual_kPa(p2_kPa, setup_.physics.pressure_scale_2));
  sim_->set_plate_mean_z(sim_->plate_touch_z() - kPlateAway_mm);
  const fem::StepResult r = sim_->settle(fem::Simulator::SettleFor::Reading);  // reset() follows
  if (r.ok()) strain = sim_->sensors().axial_strain;
  return r;
}

fem::StepResult WhiskerEnv::update_strain_zero() {
  const bool cue = task_.stiffness_cue == StiffnessCue::Inflation;
  if (task_.strain_offset != StrainOffset::Inflated && !cue) {
    strain_zero_ = 0.0;
    return {};
  }
  const double p2 = fem::design_from_index(setup_.design).n >= 2 ? setup_.p2_kPa : 0.0;
  const std::pair<std::array<double, 3>, PhysicsDraw> key{{static_cast<double>(setup_.design), setup_.p1_kPa, p2},
                                                          setup_.physics.simulation_part()};
  if (strain_zero_key_ && *strain_zero_key_ == key) return {};
  strain_zero_key_.reset();
  double zero = 0.0, rest = 0.0;
  fem::StepResult r = free_strain(setup_.p1_kPa, p2, zero);
  // The body at no pressure: the other point of the start-up reading.
  if (r.ok() && cue) r = free_strain(0.0, 0.0, rest);
  if (!r.ok()) {
    r.reason = "zeroing the strain sensor: " + r.reason;
    return r;
  }
  strain_zero_ = task_.strain_offset == StrainOffset::Inflated ? zero : 0.0;
  inflation_reading_ = setup_.physics.gauge(zero) - setup_.physics.gauge(rest);
  strain_zero_key_ = key;
  return r;
}

double WhiskerEnv::stiffness_cue() const {
  switch (task_.stiffness_cue) {
    case StiffnessCue::None: return 0.0;
    case StiffnessCue::Inflation: return scaled(inflation_reading_, 0.0, task_.strain_max);
    case StiffnessCue::TrueModulus: {
      const double r = task_.randomize.youngs_modulus;
      return r > 0.0 ? scaled(setup_.physics.youngs_scale, 1.0 - r, 1.0 + r) : 0.0;
    }
  }
  return 0.0;
}

Eigen::VectorXd WhiskerEnv::observe() const {
  const bool cue = task_.stiffness_cue != StiffnessCue::None;
  if (task_.history == 0 && !privileged_ && !cue) return current_observation();
  Eigen::VectorXd o(spec_.observation.dim());
  const Eigen::VectorXd now = current_observation();
  const Eigen::VectorXd stiffness = Eigen::VectorXd::Constant(cue ? 1 : 0, stiffness_cue());
  if (privileged_) o << now, history_obs_, history_actions_, stiffness, privileged_features();
  else o << now, history_obs_, history_actions_, stiffness;
  if (!o.allFinite()) o.setZero();
  return o;
}

Eigen::VectorXd WhiskerEnv::privileged_features() const {
  const fem::Sensors s = sim_->sensors();
  const fem::SceneConfig& scene = sim_->scene();
  const double band = task_.tolerance_fraction * task_.target_force_mN;
  const double lim = scene.theta_limit_deg * std::numbers::pi / 180.0;
  const double phase = 2.0 * std::numbers::pi * scene.plate_frequency_Hz * s.time_s + setup_.plate_phase_rad;
  Eigen::VectorXd f(kPrivilegedDim);
  f << std::clamp((s.contact_force_mN - task_.target_force_mN) / band, -kObservationClip, kObservationClip),
      std::clamp(s.theta_rad / lim, -kObservationClip, kObservationClip), std::sin(phase), std::cos(phase),
      2.0 * decision_ / decisions_per_episode() - 1.0;
  return f;
}

Eigen::VectorXd WhiskerEnv::current_observation() const {
  const fem::Design d = fem::design_from_index(setup_.design);
  const std::array<double, 3> j = fem::normalised(d);
  const double pmax = task_.pressure_max_kPa;
  const double p2 = d.n >= 2 ? setup_.p2_kPa : 0.0;
  Eigen::VectorXd o(set_dim(task_.observation));
  switch (task_.observation) {
    case ObservationSet::NoFeedback:
      o << scaled(setup_.p1_kPa, 0.0, pmax), scaled(p2, 0.0, pmax);
      break;
    case ObservationSet::Paper:
    case ObservationSet::Proprioceptive:
      o.head<6>() << j[0], j[1], j[2], scaled(setup_.p1_kPa, 0.0, pmax), scaled(p2, 0.0, pmax),
          task_.strain_offset == StrainOffset::Inflated
              // The tare is the gauge's (noiseless) reading at ε₀: the offset cancels, the gain stays.
              ? scaled(observed_strain_ - setup_.physics.gauge(strain_zero_), task_.zeroed_strain_min,
                       task_.zeroed_strain_max)
              : scaled(observed_strain_, task_.strain_min, task_.strain_max);
      if (task_.observation == ObservationSet::Proprioceptive) {
        const double lim = sim_->scene().theta_limit_deg * std::numbers::pi / 180.0;
        o[6] = scaled(observed_theta_, -lim, lim);
      }
      break;
  }
  if (!o.allFinite()) o.setZero();  // a failed state: the episode ends at this step anyway
  return o;
}

void WhiskerEnv::record(double action) {
  trace_.push_back(trace_row(sim_->sensors(), decision_, action, strain_zero_));
  if (observer_) observer_(*sim_, trace_.back());
}

rl::StepResult WhiskerEnv::step(const Eigen::VectorXd& action) {
  if (!sim_) throw std::logic_error("WhiskerEnv::step before reset");
  rl::StepResult out;
  if (!reset_failure_.empty()) {
    out.obs = observe();
    out.terminated = true;
    out.reason = reason_cell("numerical: settle: " + reset_failure_);
    return out;
  }
  const double a = std::isfinite(action[0]) ? std::clamp(action[0], -1.0, 1.0) : 0.0;
  if (task_.history > 0) push_history(current_observation(), a);
  const double dtheta = a * task_.theta_max_rad;
  const int hold = task_.action_hold_steps;
  // A delayed actuation turns the base by the previous decision's command.
  const double applied = setup_.physics.actuation_delay ? std::exchange(pending_dtheta_, dtheta) : dtheta;
  sim_->set_base_angle_target(sim_->theta() + applied, hold);
  if (episode_fault_ != Fault::None && decision_ == task_.faults.at_decision) {
    if (episode_fault_ == Fault::NanPressure) sim_->set_pressures_kPa(std::nan(""), std::nan(""));
    if (episode_fault_ == Fault::InvertedElement) sim_->set_base_angle(sim_->theta() + std::numbers::pi);
  }
  for (int k = 0; k < hold; ++k) {
    const double t0 = thread_cpu_seconds();
    const fem::StepResult r = sim_->step();
    step_s_ += thread_cpu_seconds() - t0;
    if (!r.ok()) {
      ++decision_;
      take_readings();
      out.obs = observe();
      out.terminated = true;
      out.reason = reason_cell(std::string("numerical: ") + fem::to_string(r.status) + ": " + r.reason);
      return out;
    }
    if (recording_) record(a);
  }
  const fem::Sensors s = sim_->sensors();
  const double r_f = force_reward(s.contact_force_mN, task_);
  const double r_smooth = task_.smooth_penalty * std::abs(a);
  const bool flip = dtheta != 0.0 && last_dtheta_ != 0.0 && (dtheta > 0.0) != (last_dtheta_ > 0.0);
  out.reward = r_f - r_smooth - (flip ? task_.flip_penalty : 0.0);
  last_dtheta_ = dtheta;
  if (in_band(s.contact_force_mN, task_)) ++in_band_;
  ++decision_;
  take_readings();
  out.obs = observe();
  if (!s.in_contact) {
    out.terminated = true;
    out.reason = "lost_contact";
  } else if (s.theta_extreme) {
    out.terminated = true;
    out.reason = "theta_limit";
  }
  if (decision_ >= decisions_per_episode()) {
    out.truncated = true;
    if (out.reason.empty()) out.reason = "time_limit";
  }
  return out;
}

}  // namespace codesign::core
