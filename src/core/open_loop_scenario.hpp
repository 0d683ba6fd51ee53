#pragma once
// The open-loop scenario of [sim] (fem::SimScenario) on one simulator: its chamber pressures,
// the quasi-static settle, then `steps` steps with the base angle driven through theta_deg, each
// target spread over the theta_hold_steps steps of its hold interval (as an action is), the last
// target kept. `codesign sim` records it as a trace and VTK frames, `codesign render --sim` as
// PNG frames.
#include <functional>

#include "fem/simulator.hpp"
#include "fem/config_tables.hpp"

namespace codesign::core {

// Called after the settle (step 0, hold 0) and after every step k = 1..steps (hold (k − 1) /
// theta_hold_steps) with that step's result, ok or not; the scenario ends after the first
// result that is not ok.
using ScenarioObserver = std::function<void(int step, int hold, const fem::StepResult& r)>;

struct ScenarioEnd {
  int steps = 0;           // steps taken after the settle
  fem::StepResult last;    // the settle's result if no step was taken
};

// Runs the scenario on `sim` from its current state (a fresh or reset simulator).
ScenarioEnd run_open_loop_scenario(fem::Simulator& sim, const fem::SimScenario& scenario,
                                   const ScenarioObserver& observe);

}  // namespace codesign::core
