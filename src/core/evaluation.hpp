#pragma once
// Deterministic evaluation of a controller on one design, and the fixed-θ baseline.
//
// An evaluation runs `episodes` episodes of the whisker task on design j with pressures p, the
// plate phase of episode k being 2π(k + ½)/episodes: evenly spread over a period, and distinct
// from training, whose phases are drawn at random (a set of measure zero). The controller is
// deterministic (the policy's mean action), so these phases are the only difference between
// episodes. Episodes run in parallel; each owns its environment, so results do not depend on the
// thread count.
#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/simulator_pool.hpp"
#include "core/task_config.hpp"
#include "core/whisker_env.hpp"
#include "fem/sensors.hpp"

namespace codesign::core {

// Observation -> action (before clipping).
using Controller = std::function<double(const Eigen::VectorXd& obs)>;
// A controller with memory that also reads the sensors after each decision (WhiskerEnv::readings:
// strain and base angle as the episode's gauge and encoder read them, and the true contact force
// F: an oracle the policy does not have), e.g. a PID. A factory makes
// a fresh one for every episode, so episodes (which run in parallel) share no state.
using FeedbackController = std::function<double(const Eigen::VectorXd& obs, const fem::Sensors& sensors)>;
using ControllerFactory = std::function<FeedbackController()>;

// Phase offset of the searches that tune a baseline (PID gains, fixed θ, p*): episode i of n
// tuning episodes starts at plate phase 2π(i + g)/n with g = (√5 − 1)/2. g is irrational, so
// no tuning phase equals an evaluation phase 2π(k + ½)/m for any k, m: tuning and evaluation
// never share a plate phase.
inline constexpr double kTuningPhaseOffset = 0.6180339887498949;

struct EvaluationOptions {
  int episodes = 100;
  double phase_offset = 0.5;   // episode k starts at plate phase 2π(k + phase_offset)/episodes
  std::size_t threads = 1;     // 0: all cores
  bool trace_first = true;     // keep the per-step trace of episode 0
};

struct DesignEvaluation {
  EpisodeSetup setup;                 // plate phase of episode 0
  std::vector<double> returns;        // per episode
  std::vector<double> band_fraction;  // decisions in band / decisions per episode
  std::vector<int> decisions;
  std::vector<std::string> reasons;
  double mean_return = 0.0, std_return = 0.0;  // population std over the episodes
  double mean_band_fraction = 0.0;
  std::vector<TraceRow> trace;        // episode 0, if asked
};

// Half-width of the 95 % interval of e's mean return over its n episodes: 1.96·s/√n with s the
// sample std (std_return is the population one), the normal approximation, fair for n ≥ 30.
inline double ci95_of_mean(const DesignEvaluation& e) {
  const double n = static_cast<double>(e.returns.size());
  return 1.96 * e.std_return * std::sqrt(n / (n - 1.0)) / std::sqrt(n);
}

// Plate phase of evaluation episode k of n: 2π(k + offset)/n.
double evaluation_phase(int k, int n, double offset = 0.5);

DesignEvaluation evaluate_design(const Controller& controller, const std::shared_ptr<SimulatorPool>& sims,
                                 const TaskConfig& task, EpisodeSetup setup, const EvaluationOptions& options);
// The same for a controller with memory and sensor access (one fresh controller per episode).
DesignEvaluation evaluate_feedback(const ControllerFactory& make, const std::shared_ptr<SimulatorPool>& sims,
                                   const TaskConfig& task, EpisodeSetup setup, const EvaluationOptions& options);

// The best constant base angle for a design: θ0 maximising the mean return over `phases`
// plate phases with the base held still (action 0), by golden-section search on
// [−theta_limit, theta_limit] to a bracket of `tolerance_rad` after a coarse scan of
// `scan_points` angles (the return is unimodal in θ0 only near its maximum).
struct FixedThetaResult {
  double theta0_rad = 0.0;
  DesignEvaluation evaluation;  // at θ0 over `phases` phases
  int evaluations = 0;          // episodes run in the search
};
// `phase_offset` places the search's plate phases (2π(k + offset)/phases).
FixedThetaResult best_fixed_theta(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                  EpisodeSetup setup, int phases, std::size_t threads, int scan_points = 13,
                                  double tolerance_rad = 1e-3, double phase_offset = 0.5);

}  // namespace codesign::core
