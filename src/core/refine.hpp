#pragma once
// Polishing p* of a finished co-design run: with the policy π and the structure j* fixed, NLopt
// searches the chamber pressures p ∈ [0, p_max]² (p2 = 0 for one chamber) for the highest
// deterministic return. The search's objective is the mean return over `tuning_phases` plate
// phases 2π(i + g)/n (kTuningPhaseOffset); p* before and after are then both tested on the run's
// evaluation phases 2π(k + ½)/m, which the search never saw.
//
// The result goes into the run's result.toml as a [refined] table appended at the end; every
// byte before it stays as it was (an earlier [refined] table is replaced), written atomically.
#include <array>
#include <cstddef>
#include <memory>
#include <string>

#include "core/evaluation.hpp"
#include "core/nlopt_search.hpp"

namespace codesign::core {

struct RefineConfig {
  int tuning_phases = 4;
  int test_episodes = 100;   // the run's eval_episodes
  SearchOptions search{LocalMethod::Bobyqa, 2, 20, 1e-3, 1e-4};
  void validate() const;     // std::invalid_argument naming the field
};

struct RefineResult {
  int design = 0;
  std::array<double, 2> p_before{0.0, 0.0}, p_after{0.0, 0.0};  // kPa
  double tuning_before = 0.0, tuning_after = 0.0;   // mean return over the tuning phases
  int evaluations = 0;                              // objective calls (tuning_phases episodes each)
  DesignEvaluation test_before, test_after;         // over the evaluation phases
  RefineConfig config;
};

// `policy` makes the controller of each episode (policy_controller.hpp: a recurrent policy starts
// every episode from a zero state); a memoryless controller may be given as it is.
RefineResult refine_pressures(const ControllerFactory& policy, const std::shared_ptr<SimulatorPool>& sims,
                              const TaskConfig& task, int design, std::array<double, 2> p_before,
                              const RefineConfig& config, std::size_t threads = 1);
RefineResult refine_pressures(const Controller& policy, const std::shared_ptr<SimulatorPool>& sims,
                              const TaskConfig& task, int design, std::array<double, 2> p_before,
                              const RefineConfig& config, std::size_t threads = 1);

}  // namespace codesign::core
