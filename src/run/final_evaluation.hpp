#pragma once
// The final evaluation of a co-design run, with the deterministic final policy on the test plate
// phases (docs/codesign.md, "Final evaluation"): d* at p* (the single design of that baseline;
// else the leading design at its collapsed optimum, or at its mean pressures if the distribution
// never collapsed), the runner-up at its mean pressures (none for the single-design baseline),
// and d*'s best constant base angle without a controller, tuned on phases no test shares
// (codesign.fixed_theta_phases > 0).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "core/design_distribution.hpp"
#include "core/design_sweep.hpp"
#include "core/evaluation.hpp"
#include "core/outer_loop.hpp"
#include "core/simulator_pool.hpp"
#include "rl/policy_file.hpp"
#include "run/run_telemetry.hpp"

namespace codesign::run {

struct FinalEvaluation {
  core::DesignEvaluation best;
  std::optional<core::DesignEvaluation> runner_up;
  std::optional<core::FixedThetaTuning> fixed_theta;
  // A signal (SIGTERM, SIGINT) that stopped the evaluation after one of its designs; 0: complete.
  int stop_signal = 0;
};

// Evaluates the designs above in turn, each written to eval/<best|runner_up>*.csv in run_dir and
// its trace published (stamped with timestep t) as soon as it is done; after each it checks
// stop_signal() and returns at once if a signal asked to stop.
FinalEvaluation evaluate_final(const core::DesignDistribution& dist, const core::LoopConfig& lc,
                               const std::shared_ptr<const rl::Policy>& policy,
                               const std::shared_ptr<core::SimulatorPool>& sims, std::size_t threads,
                               const std::filesystem::path& run_dir, RunTelemetry& telemetry, std::int64_t t);

}  // namespace codesign::run
