#pragma once
// The design landscape: every design on a pressure grid, each with four tuned baselines —
// the best fixed base angle θ0, the PID on the measured force (oracle), the PID on the strain
// ε (the policy's signal) and the PID on the force estimated from ε and the base angle θ
// (pid_tuning.hpp) — tuned on tuning phases and tested on disjoint evaluation phases.
//
// Here: one row of the landscape (sweep_one); the sweep's folder, its sweep.csv and heat maps
// are run/sweep_folder.hpp's.
#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/enum_names.hpp"
#include "core/evaluation.hpp"
#include "core/pid_tuning.hpp"

namespace codesign::core {

// The best constant base angle found with NLopt: a coarse scan of `scan_points` angles on
// [−0.95, 0.95]·theta_limit (odd counts include θ0 = 0), then a bounded local search (COBYLA,
// one variable) within one scan step of the best, `max_evals` more evaluations. Each evaluation
// is the mean return over `tuning_phases` tuning phases; the result is tested over
// `test_episodes` evaluation phases.
struct FixedThetaConfig {
  int scan_points = 7;
  int max_evals = 8;
  void validate() const;  // scan_points >= 3, max_evals >= 1
};
struct FixedThetaTuning {
  double theta0_rad = 0.0;
  double tuning_return = 0.0;
  int evaluations = 0;
  DesignEvaluation test;
};
FixedThetaTuning tune_fixed_theta(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                  const EpisodeSetup& setup, const FixedThetaConfig& config, int tuning_phases,
                                  int test_episodes, std::size_t threads = 1);

enum class SweepController { FixedTheta, PidForce, PidStrain, PidEstimate };
inline constexpr EnumNames<SweepController, 4> kSweepControllerNames{{{SweepController::FixedTheta, "fixed_theta"},
                                                                     {SweepController::PidForce, "pid_force"},
                                                                     {SweepController::PidStrain, "pid_strain"},
                                                                     {SweepController::PidEstimate, "pid_estimate"}}};
inline const char* to_string(SweepController c) { return name_of(kSweepControllerNames, c).data(); }
SweepController sweep_controller_from_name(const std::string& name);  // else std::invalid_argument

// [sweep] of a config.
struct SweepConfig {
  std::vector<double> pressures_kPa{0.0};  // per chamber; two-chamber designs take every pair
  std::vector<SweepController> controllers{SweepController::FixedTheta, SweepController::PidForce,
                                           SweepController::PidStrain, SweepController::PidEstimate};
  FixedThetaConfig fixed_theta;
  int first_design = 0, last_design = 109;
  void validate() const;  // std::invalid_argument naming the field
};

struct SweepPoint {
  int design = 0;
  double p1_kPa = 0.0, p2_kPa = 0.0;
};
// The (design, pressures) units in order: designs first..last, then the grid (p2 = 0 for n = 1).
std::vector<SweepPoint> sweep_points(const SweepConfig& config);

struct SweepRow {
  SweepPoint point;
  SweepController controller = SweepController::FixedTheta;
  double theta0_rad = 0.0;           // fixed θ
  PidGains gains;                    // PIDs
  double setpoint = 0.0;             // PIDs: F_t (mN) or ε_ref
  double fit_r2 = NAN, fit_rms_mN = NAN;  // estimate PID: the fit of F̂ (NaN for the others)
  double tuning_return = 0.0;
  int evaluations = 0;
  double test_return = 0.0, test_std = 0.0, band_fraction = 0.0;
  int test_episodes = 0;
  double seconds = 0.0;
};
SweepRow sweep_one(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task, const SweepPoint& point,
                   SweepController controller, const SweepConfig& sweep, const PidTuningConfig& pid);

}  // namespace codesign::core
