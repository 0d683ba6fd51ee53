#pragma once
// Tuning PID gains with NLopt (nlopt_search.hpp), generically and on the whisker task.
//
// tune_pid(): maximise an objective of (gains, setpoint offset) over a box of gains (and of the
// offset; a [0, 0] range fixes it) from several starts. Used by tune_whisker_pid() and tested on
// a plant with a known optimum (tests/core/pid_tuning_test.cpp).
//
// tune_whisker_pid(): per design and pressures, the gains (and, for the strain signal, the
// setpoint) that maximise the mean episode return over `tuning_phases` plate phases
// 2π(i + g)/n (kTuningPhaseOffset), then the tuned PID evaluated over `test_episodes` phases
// 2π(k + ½)/m — disjoint from the tuning phases — with mean ± std.
// The strain PID's setpoint is ε_ref = ε_cal + offset·strain_scale: ε_cal is a lab calibration
// (one episode with the base held at θ = 0 at the first tuning phase, least-squares line of ε
// against the measured F, read at F_t), and the offset, in band units, is tuned with the gains
// (ε also moves with θ at a fixed F, so the calibrated value is only a starting point).
// The estimate PID first fits its force estimator F̂(ε, θ) on `estimator_fit_episodes` open-loop
// episodes at the tuning phases (estimator_calibration.hpp), then tunes its gains with the
// setpoint F_t like the force PID. No setpoint offset is tuned: the fit's residual has zero mean
// over its samples, and in closed loop F averaged 20.00 mN over the first test episode of j47
// (docs/journal/baselines.md, "Measured: the estimator PID beside the others"), so there is no
// bias for an offset to remove.
#include <array>
#include <cstddef>
#include <functional>
#include <memory>

#include "core/estimator_calibration.hpp"
#include "core/evaluation.hpp"
#include "core/force_estimator.hpp"
#include "core/nlopt_search.hpp"
#include "core/pid_controller.hpp"

namespace codesign::core {

struct PidBox {
  std::array<double, 2> kp{0.0, 0.5}, ki{0.0, 0.2}, kd{0.0, 0.5};
  std::array<double, 2> offset{0.0, 0.0};  // setpoint offset in band units; [0, 0]: not tuned
  // Throws std::invalid_argument naming the range: finite, lo <= hi, gains >= 0.
  void validate() const;
};

struct PidSearch {
  PidGains gains;
  double offset = 0.0;
  double value = 0.0;      // objective at (gains, offset)
  int evaluations = 0;
};

using PidObjective = std::function<double(const PidGains& gains, double offset)>;

PidSearch tune_pid(const PidObjective& objective, const PidBox& box, const SearchOptions& search,
                   const PidGains& start, double offset_start = 0.0);

// [pid] of a config: bounds, start, budget and the phases of tuning and testing.
struct PidTuningConfig {
  // Gains in action per band unit. Turning the base by one full action (10°) moves F by about
  // 75–150 mN, i.e. G ≈ 19–37 band units, so a loop gain K·G of order one needs K of a few
  // hundredths; gains much above 0.1 make the tip lose contact within a few decisions.
  PidBox box{{0.0, 0.1}, {0.0, 0.1}, {0.0, 0.1}, {-3.0, 3.0}};  // offset: strain signal only
  PidGains start{0.01, 0.01, 0.0};  // first start: slow but stable on every design tried (j21, j51)
  double strain_scale = 1.9e-5;     // ε per band half-width (j21: 4.7e-6 per mN × 4 mN)
  int tuning_phases = 2;
  int test_episodes = 10;
  int estimator_fit_episodes = 25;  // open-loop episodes of the estimate PID's fit
  SearchOptions search{LocalMethod::Bobyqa, 2, 24, 1e-3, 1e-4};
  // Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

// A PID for the whisker: signal, gains and setpoint (F_t in mN, or ε_ref).
struct WhiskerPid {
  PidSignal signal = PidSignal::Force;
  PidGains gains;
  double setpoint = 0.0;
  double strain_scale = 1.9e-5;  // strain signal only
  ForceEstimator estimator;      // estimate signal only
};

// The error of the PID's signal in band units (pid_controller.hpp).
double pid_error(const WhiskerPid& pid, const fem::Sensors& s, const TaskConfig& task);
ControllerFactory pid_factory(const WhiskerPid& pid, const TaskConfig& task);

// ε at F = F_t from one episode with the base held at θ = 0 (see above); phase in rad.
double calibrate_strain_setpoint(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                 EpisodeSetup setup, double phase_rad);

struct PidTuningResult {
  WhiskerPid pid;
  double strain_calibrated = 0.0;  // ε_cal (strain signal)
  double offset = 0.0;             // tuned setpoint offset (strain signal), band units
  EstimatorCalibration estimator;  // the fit of F̂ (estimate signal)
  double tuning_return = 0.0;      // mean return over the tuning phases
  int evaluations = 0;             // objective calls (each tuning_phases episodes)
  DesignEvaluation test;           // over test_episodes evaluation phases
};

PidTuningResult tune_whisker_pid(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                 const EpisodeSetup& setup, PidSignal signal, const PidTuningConfig& config,
                                 std::size_t threads = 1);

}  // namespace codesign::core
