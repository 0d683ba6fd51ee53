#pragma once
// The survey of the designs (`codesign survey`, docs/codesign.md): what the task's defaults rest
// on, measured on each design.
//  * The range of the strain observation ε over open-loop episodes with the base held at
//    θ0 ∈ {−θ_max, 0, +θ_max} and the pressure corners of [0, p_max] (both chambers for n = 2),
//    plate phase 0; over the same episodes, the range of the zeroed strain ε − ε₀ of
//    strain_offset = "inflated".
//  * The contact force of the episode at zero pressure and θ0 = 0.
//  * Optionally the best fixed base angle θ0 (best_fixed_theta at zero pressure over N plate
//    phases) with its return and band fraction: the no-controller baseline.
#include <memory>
#include <vector>

#include "core/evaluation.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::core {

struct SurveyRow {
  double strain_min = 1e300, strain_max = -1e300;
  double zeroed_min = 1e300, zeroed_max = -1e300;   // ε − ε₀
  double force_mean = 0.0, force_min = 1e300, force_max = -1e300;  // mN, zero pressure, θ0 = 0
  FixedThetaResult fixed;                           // left at its defaults without the search
};

struct SurveyOptions {
  int first_design = 0, last_design = 109;
  int phases = 2;           // plate phases per fixed-θ evaluation
  bool fixed_theta = true;  // search the best fixed base angle of each design
};

// One row per design first_design..last_design; the designs are spread over `pool`.
std::vector<SurveyRow> survey_designs(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                      const SurveyOptions& options, rl::ThreadPool& pool);

}  // namespace codesign::core
