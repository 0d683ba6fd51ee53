#pragma once
// The whisker force-tracking MDP (paper §IV-A, §V-A; docs/codesign.md) as an rl::Env over
// fem::Simulator.
//
// Episode: the design and chamber pressures of the current EpisodeSetup, θ = 0, the body loaded
// quasi-statically onto the plate (Simulator::settle), then `decisions` = episode_steps /
// action_hold_steps decisions (50 by default). A decision a ∈ [−1, 1] (clipped here) changes
// the base angle by Δθ = a·θ_max, spread evenly over the action_hold_steps simulation steps it
// is held for. After the hold the contact force F is read and
//   R = r_f − r_smooth − r_flip,  δ = |F − F_t| / (tol·F_t),
//   r_f = (½(1 + cos πδ))^κ if δ < 1 else 0,  r_smooth = c_s |Δθ|/θ_max,
//   r_flip = c_f when Δθ changes sign between consecutive decisions (both non-zero).
// Termination (terminated = true): the tip lost contact with the plate (F = 0 after a
// decision), |θ| past the scene's limit (fem::Sensors::theta_extreme: buckling territory), or a
// numerical failure of the simulator (reason "numerical: <status>: <detail>"). Truncation at the
// last decision (reason "time_limit"). An episode therefore returns at most `decisions`.
//
// Observation (ObservationSet), every component min–max scaled onto [−1, 1] by reference
// ranges (ObservationRanges), clipped to ±kObservationClip:
//   paper          {n, l, w, p1, p2, ε}        (6)  the paper's s = {j, p, ε}
//   proprioceptive {n, l, w, p1, p2, ε, θ}     (7)  ours: the motor encoder's θ added
//   no_feedback    {p1, p2}                    (2)  the paper's baseline: ε and morphology removed
// TaskConfig::history = k > 0 appends, after those, the time-varying components of the last k
// decisions' observations, component by component and newest first, then their k actions (the
// clipped actions applied, newest first):
//   paper          ε_{t−1} … ε_{t−k}, a_{t−1} … a_{t−k}                          (+2k)
//   proprioceptive ε_{t−1} … ε_{t−k}, θ_{t−1} … θ_{t−k}, a_{t−1} … a_{t−k}        (+3k)
//   no_feedback    a_{t−1} … a_{t−k}                                              (+k)
// Slots before the episode's first decision hold the episode's first observation (ε, θ after
// settling) and action 0, so that a constant input reads as "no change yet".
// TaskConfig::stiffness_cue other than "none" appends one constant component after the history:
// the gauge's start-up inflation reading or the drawn modulus (task_config.hpp).
// Privileged features (constructed with privileged = true, for a privileged critic during
// training; rl/actor_critic.hpp): after all of the above, kPrivilegedDim components of the true
// state no sensor of the robot gives:
//   (F − F_t)/(tol·F_t) (the signed δ, clipped to ±kObservationClip), θ/θ_limit (the scene's),
//   sin(ω t + φ) and cos(ω t + φ) of the plate, 2·decision/decisions − 1 (time in the episode).
// With TaskConfig::strain_offset = Inflated the ε component is ε − ε₀ (task_config.hpp): ε₀ comes
// from a settle of the same design and pressures with the plate out of reach, once per
// (design, pressures, simulation draw) on this environment; the inflation cue adds one at no
// pressure, on the same key.
// The env draws no random numbers: the caller chooses design, pressures and plate phase
// (EpisodeSetup) before reset(); reset()'s seed is ignored.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/simulator_pool.hpp"
#include "core/task_config.hpp"
#include "rl/rng.hpp"
#include "rl/env.hpp"

namespace codesign::core {

inline constexpr double kObservationClip = 3.0;
inline constexpr int kPrivilegedDim = 5;

struct EpisodeSetup {
  bool operator==(const EpisodeSetup&) const = default;
  int design = 21;
  double p1_kPa = 0.0;
  double p2_kPa = 0.0;          // ignored (0) for one-chamber designs
  double plate_phase_rad = 0.0;
  double theta0_rad = 0.0;      // base angle the episode starts (and settles) at
  // Injected numerical failure (TaskConfig::faults); only the next episode after set_episode()
  // gets it, an episode restarted with reset() alone runs clean.
  Fault fault = Fault::None;
  // The physics the episode meets (TaskConfig::randomize); nominal by default.
  PhysicsDraw physics{};
};

// One simulation step of an episode, for evaluation traces and renders.
struct TraceRow {
  int decision = 0;             // 0-based index of the decision this step belongs to
  double t_s = 0.0;
  double theta_rad = 0.0;
  double force_mN = 0.0;
  double strain = 0.0;
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();
  double plate_z_mm = 0.0;
  double action = 0.0;          // the (clipped) action being applied
  double strain_zero = 0.0;     // ε₀ subtracted from ε in the observation (0 unless "inflated")
};

// The row of the simulator's present state.
inline TraceRow trace_row(const fem::Sensors& s, int decision, double action, double strain_zero = 0.0) {
  return {decision, s.time_s, s.theta_rad, s.contact_force_mN, s.axial_strain, s.tip_position_mm,
          s.plate_z_mm, action, strain_zero};
}

// The force term r_f of the reward (docs/codesign.md, "The whisker task") for a force F.
double force_reward(double force_mN, const TaskConfig& task);
// Whether F lies inside the ±tolerance band around the target.
bool in_band(double force_mN, const TaskConfig& task);
// Dimension of the task's observation: its set's components, plus the history's (above).
int observation_dim(const TaskConfig& task);
// Time-varying components of an observation set (ε; θ where observed).
int dynamic_observation_dim(ObservationSet set);

class WhiskerEnv final : public rl::Env {
 public:
  // privileged: append the privileged features (above) to every observation.
  WhiskerEnv(std::shared_ptr<SimulatorPool> pool, const TaskConfig& task, bool privileged = false);
  ~WhiskerEnv() override;

  // Takes effect at the next reset().
  void set_episode(const EpisodeSetup& setup);
  const EpisodeSetup& episode() const { return setup_; }
  // Keep a TraceRow per simulation step (off by default; cleared at reset()).
  void set_recording(bool on) { recording_ = on; }
  const std::vector<TraceRow>& trace() const { return trace_; }
  // Called with the simulator and the new row each time a trace row is kept (recording on):
  // after settling and after every simulation step. For renders.
  using StepObserver = std::function<void(const fem::Simulator&, const TraceRow&)>;
  void set_step_observer(StepObserver observer) { observer_ = std::move(observer); }

  const rl::EnvSpec& spec() const override { return spec_; }
  Eigen::VectorXd reset(std::optional<std::uint64_t> seed) override;
  rl::StepResult step(const Eigen::VectorXd& action) override;

  int decisions_per_episode() const;
  int decisions_taken() const { return decision_; }
  // Decisions so far whose force ended inside the band.
  int decisions_in_band() const { return in_band_; }
  // CPU seconds of the calling thread spent in settling (reset) and in simulation steps since
  // construction (thread CPU time: other processes on the machine do not inflate them).
  double settle_seconds() const { return settle_s_; }
  double step_seconds() const { return step_s_; }
  // The simulator of the current episode (valid after reset()).
  const fem::Simulator& simulator() const { return *sim_; }
  // The sensors as the robot reads them: the simulator's, with the strain and the base angle
  // through the episode's drawn gauge, encoder and noise (what the policy observes); the contact
  // force stays true. Equal to simulator().sensors() under nominal physics.
  fem::Sensors readings() const;

 private:
  // The observation set's components for the present state (without the history).
  Eigen::VectorXd current_observation() const;
  // The privileged features of the present state (kPrivilegedDim).
  Eigen::VectorXd privileged_features() const;
  Eigen::VectorXd observe() const;
  // Fills the history with the present observation and action 0 (episode start).
  void clear_history();
  // Shifts the history by one decision: `seen` was observed before the action `a` was applied.
  void push_history(const Eigen::VectorXd& seen, double a);
  void record(double action);
  // Computes ε₀ for the current setup if strain_offset = Inflated, and the inflation reading if
  // stiffness_cue = "inflation", when they are not known yet (leaves the simulator in a state
  // that needs reset()).
  fem::StepResult update_strain_zero();
  // Settles the body free of the plate at the given pressures (through the draw's pressure
  // errors) and reads the true strain; leaves the simulator in a state that needs reset().
  fem::StepResult free_strain(double p1_kPa, double p2_kPa, double& strain);
  // The stiffness cue's component, scaled (TaskConfig::stiffness_cue).
  double stiffness_cue() const;
  // A simulator of the setup's design and drawn body and scene: leased from the pool for the
  // nominal ones, built here (on fem::scaled_model, no meshing) for a drawn one.
  void take_simulator();
  void give_back_simulator();
  // The gauge's and the encoder's readings of the present state through the episode's drawn gain,
  // offset and noise (the true values when nominal).
  void take_readings();
  // The simulation part of the setup's draw without its pressure errors: what the simulator is
  // built for.
  PhysicsDraw simulator_draw() const;

  std::shared_ptr<SimulatorPool> pool_;
  TaskConfig task_;
  bool privileged_ = false;
  rl::EnvSpec spec_;
  EpisodeSetup setup_;
  int sim_design_ = -1;
  PhysicsDraw sim_draw_;  // what sim_ was built for (nominal: leased from the pool)
  std::unique_ptr<fem::Simulator> sim_;
  // The settled state of the last setup settled on this environment: an episode restarted with
  // the same setup (after an early termination) restores it instead of settling again, with
  // bit-identical results (fem::Simulator::restore).
  std::optional<EpisodeSetup> settled_setup_;
  fem::Simulator::Snapshot settled_;
  std::string reset_failure_;   // non-empty: settling failed; the first step terminates
  // ε₀ of strain_offset = Inflated (the true strain), for the (design, p1, p2) and simulation
  // draw in strain_zero_key_.
  std::optional<std::pair<std::array<double, 3>, PhysicsDraw>> strain_zero_key_;
  double strain_zero_ = 0.0;
  // The gauge's start-up reading at the setup's pressures less at none (stiffness_cue =
  // "inflation"), for the same key.
  double inflation_reading_ = 0.0;
  // The readings the policy sees now (take_readings), the per-decision noise stream of the
  // episode's draw, and the base turn a delayed actuation still owes.
  double observed_strain_ = 0.0, observed_theta_ = 0.0;
  rl::Rng noise_rng_{0};
  double pending_dtheta_ = 0.0;
  Fault fault_ = Fault::None;   // of the episode set by set_episode(), until its reset()
  Fault episode_fault_ = Fault::None;  // of the running episode
  int decision_ = 0;
  int in_band_ = 0;
  double last_dtheta_ = 0.0;
  // TaskConfig::history: dynamic components (dynamic_observation_dim × history, newest first per
  // component) and actions (newest first).
  Eigen::VectorXd history_obs_, history_actions_;
  bool recording_ = false;
  double settle_s_ = 0.0, step_s_ = 0.0;
  std::vector<TraceRow> trace_;
  StepObserver observer_;
};

}  // namespace codesign::core
