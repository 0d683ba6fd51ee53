#include "core/open_loop_scenario.hpp"

#include <algorithm>
#include <numbers>

namespace codesign::core {

ScenarioEnd run_open_loop_scenario(fem::Simulator& sim, const fem::SimScenario& sc, const ScenarioObserver& observe) {
  sim.set_pressures_kPa(sc.pressures_kPa[0], sc.pressures_kPa.size() > 1 ? sc.pressures_kPa[1] : 0.0);
  ScenarioEnd end;
  end.last = sim.settle();
  observe(0, 0, end.last);
  for (int k = 0; k < sc.steps && end.last.ok(); ++k) {
    const int hold = k / sc.theta_hold_steps;
    if (k % sc.theta_hold_steps == 0) {
      const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(hold), sc.theta_deg.size() - 1);
      sim.set_base_angle_target(sc.theta_deg[i] * std::numbers::pi / 180.0, sc.theta_hold_steps);
    }
    end.last = sim.step();
    end.steps = k + 1;
    observe(k + 1, hold, end.last);
  }
  return end;
}

}  // namespace codesign::core
