#pragma once
// `codesign baseline pid` (docs/baselines.md): what a control engineer would try first on one
// design, and the one writer of its result file DIR/baseline.toml.
//  * A PID on the measured force (an oracle sensor the policy lacks), a PID on the strain ε (the
//    policy's signal) and a PI(D) on the force estimated from ε and the base angle θ (fitted on
//    open-loop episodes), gains tuned by NLopt ([pid] of the config), and the best fixed base
//    angle ([sweep] fixed_theta_*); all tuned on the tuning phases, tested on disjoint
//    evaluation phases (core::tune_whisker_pid, core::tune_fixed_theta).
//  * DIR/eval/<controller>.csv and _trace.csv through run_folder.hpp's write_evaluation.
//  * DIR/baseline.toml:
//      [design]        design, pressures_kPa
//      [pid_force]     kp, ki, kd, setpoint (F_t, mN)
//      [pid_strain]    the same (setpoint in strain), strain_calibrated, setpoint_offset
//      [pid_estimate]  the same as [pid_force], then the fit of F̂ (estimator_c0..c2, fit_*)
//      [fixed_theta]   theta0_deg
//    and in each controller's table its tuning_return, evaluations and the test on the
//    evaluation phases: test_return, test_return_std, test_episodes, band_fraction.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/design_sweep.hpp"
#include "core/pid_tuning.hpp"
#include "run/run_config.hpp"

namespace codesign::run {

inline constexpr const char* kBaselineFile = "baseline.toml";

// What `codesign baseline pid` measured on one design.
struct PidBaselineResult {
  int design = 0;
  double p1_kPa = 0.0, p2_kPa = 0.0;  // p2 is 0 for one chamber
  int tuning_phases = 0;              // [pid] tuning_phases
  int test_episodes = 0;              // [pid] test_episodes
  std::vector<std::pair<core::PidSignal, core::PidTuningResult>> pids;  // a table each, in this order
  core::FixedThetaTuning fixed_theta;
};

// Writes DIR/baseline.toml atomically.
void write_baseline_file(const std::filesystem::path& dir, const PidBaselineResult& r);

struct PidBaselineOptions {
  int design = 21;
  double p1_kPa = 0.0, p2_kPa = 0.0;  // p2 is ignored for one chamber
  std::string out;                    // DIR
  int threads = 0;                    // 0: one per core
  bool force = false;                 // overwrite an earlier baseline.toml
};

// Tunes and tests the four controllers on the design, printing a line each, and writes DIR.
// Throws InputError, before any episode runs, for a design outside [0, 109], a pressure outside
// [0, task.pressure_max_kPa], a DIR that holds baseline.toml without `force`, or one that cannot
// be created.
void run_pid_baseline(const RunConfig& config, const PidBaselineOptions& options);

}  // namespace codesign::run
