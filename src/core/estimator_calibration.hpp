#pragma once
// The lab calibration of the force estimator (force_estimator.hpp): open-loop episodes at the
// design and pressures being tuned, the base driven along a fixed schedule, and a least-squares
// fit of ε against (1, F, θ) over their samples.
//
// Samples: one per decision, read after the decision's hold (the sensors a feedback controller
// sees before its next decision, and the state after the last decision), kept only in contact
// (F > 0). A sample after a numerical failure is dropped.
//
// Plate phases: episode i of E starts at tuning phase 2π(i mod n + g)/n, n = [pid]
// tuning_phases, g = kTuningPhaseOffset — never at a test phase 2π(k + ½)/m (g is irrational, so
// the two sets are disjoint for every n, m): the estimator, like the gains, is fitted without
// seeing the episodes it is scored on.
//
// Base schedules: the base must sweep θ over the range a controller uses while the plate moves F
// (otherwise θ and F are collinear and c2 is not identifiable). A controller holds F near F_t,
// so the schedules are centred on θ*, the base angle at which the settled F (after reset, at the
// first tuning phase) equals F_t — found by a line through the settled F at θ0 = 0 and 2°
// (θ* = 0 if that line does not rise), clamped to ±θ_limit/2. Episode i then starts at
// θc_i = θ* − 1.5° + 3°·i/(E − 1) (θ* for E = 1) and follows the slow sinusoid
//     θ_i(k) = θc_i ± 1°·sin(2πk/K),  k = decision, K = decisions per episode,
// with the sign alternating between episodes (opposite sweep directions): θ covers θ* ± 2.5°,
// i.e. ±2.5° of base turn, or about ±17 mN on j21 (7 mN per degree), over the band (±4 mN) and
// the plate's swing (the force PID turns the base over −1.4°..1.3° on j47, θ* = 0.88°). The sinusoid
// turns the base by at most 2π·1°/K ≈ 0.13° per decision (K = 50): an action of 0.013, far from
// the clip. Episodes that lose contact end early and give fewer samples.
#include <cstddef>
#include <memory>
#include <string>

#include "core/force_estimator.hpp"
#include "core/simulator_pool.hpp"
#include "core/task_config.hpp"
#include "core/whisker_env.hpp"

namespace codesign::core {

struct EstimatorCalibration {
  ForceFit fit;
  int episodes = 0;             // open-loop episodes run
  double theta_centre_rad = 0;  // θ*
  // Why the samples could not identify the model (fit_force_estimator's message, e.g. too few
  // samples when every episode lost contact at once); empty when the fit succeeded. On failure
  // the coefficients, R² and rms are NaN, so F̂ is NaN and a PID on it holds the base (a
  // non-finite error gives action 0): a sweep row, not an aborted sweep.
  std::string failure;
  bool ok() const { return failure.empty(); }
};

// episodes and tuning_phases must be >= 1 (else std::invalid_argument).
EstimatorCalibration calibrate_force_estimator(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                               const EpisodeSetup& setup, int episodes, int tuning_phases,
                                               std::size_t threads = 1);

}  // namespace codesign::core
