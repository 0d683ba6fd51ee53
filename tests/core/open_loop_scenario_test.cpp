// The open-loop scenario of [sim]: which steps the observer sees, and the base angle following
// the θ schedule as the simulator's ramp defines it (linear over each hold interval: after m of
// n steps from θa towards θb, θ = θa + (θb − θa)·m/n; the last target is kept).
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "core/open_loop_scenario.hpp"
#include "fem/whisker_model.hpp"

namespace {

using namespace codesign;

constexpr double kRad = std::numbers::pi / 180.0;

struct Seen {
  int step, hold;
  double theta;
  bool ok;
};

TEST(OpenLoopScenario, FollowsTheThetaScheduleAndKeepsTheLastTarget) {
  fem::SimScenario sc;
  sc.design = 21;
  sc.pressures_kPa = {3.0, 0.0};
  sc.theta_deg = {0.0, 1.0, 2.0};
  sc.theta_hold_steps = 3;
  sc.steps = 11;  // three hold intervals and two steps past the schedule's end
  const auto model = fem::build_whisker_model(sc.design, fem::WhiskerModelSpec{});
  fem::Simulator sim(model, fem::SceneConfig{}, fem::SolverConfig{});
  std::vector<Seen> seen;
  const core::ScenarioEnd end = core::run_open_loop_scenario(sim, sc, [&](int step, int hold, const fem::StepResult& r) {
    seen.push_back({step, hold, sim.theta(), r.ok()});
  });
  ASSERT_TRUE(end.last.ok()) << end.last.reason;
  EXPECT_EQ(end.steps, 11);
  ASSERT_EQ(seen.size(), 12u);  // the settle, then every step
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(seen[i].step, i);
    EXPECT_EQ(seen[i].hold, i == 0 ? 0 : (i - 1) / 3);
    EXPECT_TRUE(seen[i].ok);
  }
  // θ after step k: interval h = (k − 1)/3 ramps from θ(end of h − 1) to theta_deg[min(h, 2)].
  // The ramp's arithmetic is exact to a few ulps of 2° (≈ 1e-17 rad); 1e-12 rad leaves room.
  const double expected_deg[12] = {0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 4.0 / 3, 5.0 / 3, 2, 2, 2};
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(seen[i].theta, expected_deg[i] * kRad, 1e-12) << "step " << i;
  EXPECT_DOUBLE_EQ(sim.sensors().theta_rad, 2.0 * kRad);
}

TEST(OpenLoopScenario, NoStepsIsTheSettleAlone) {
  fem::SimScenario sc;
  sc.steps = 0;
  const auto model = fem::build_whisker_model(sc.design, fem::WhiskerModelSpec{});
  fem::Simulator sim(model, fem::SceneConfig{}, fem::SolverConfig{});
  int calls = 0;
  const core::ScenarioEnd end =
      core::run_open_loop_scenario(sim, sc, [&](int step, int hold, const fem::StepResult&) {
        EXPECT_EQ(step, 0);
        EXPECT_EQ(hold, 0);
        ++calls;
      });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(end.steps, 0);
  EXPECT_TRUE(end.last.ok());
}

}  // namespace
