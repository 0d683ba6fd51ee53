// The polish of `codesign refine`: its bounds and budget on a shortened task (its [refined]
// table in result.toml is tests/run/refined_table_test.cpp's).
#include <gtest/gtest.h>

#include "core/refine.hpp"

namespace codesign::core {
namespace {

TEST(Refine, PolishKeepsBoundsAndBudgetAndNeverWorsens) {
  // The polish keeps p* unless the search found a strictly higher tuning return, stays in
  // [0, p_max], keeps p2 = 0 for a one-chamber design, and spends at most its budget (+1 for
  // p* itself). Shortened task: 5 decisions, base held still.
  fem::SceneConfig scene;
  scene.settle_steps = 5;
  auto sims = std::make_shared<SimulatorPool>(fem::WhiskerModelSpec{}, scene, fem::SolverConfig{});
  TaskConfig task;
  task.episode_steps = 25;
  RefineConfig c;
  c.tuning_phases = 1;
  c.test_episodes = 2;
  c.search.starts = 1;
  c.search.max_evals = 4;
  const Controller still = [](const Eigen::VectorXd&) { return 0.0; };
  const RefineResult r = refine_pressures(still, sims, task, 21, {5.0, 7.0}, c);
  EXPECT_EQ(r.p_before[1], 0.0);
  EXPECT_EQ(r.p_after[1], 0.0);
  EXPECT_GE(r.p_after[0], 0.0);
  EXPECT_LE(r.p_after[0], task.pressure_max_kPa);
  EXPECT_GE(r.tuning_after, r.tuning_before);
  EXPECT_LE(r.evaluations, 4 + 1);
  EXPECT_EQ(r.test_after.returns.size(), 2u);
  EXPECT_THROW(refine_pressures(still, sims, task, 21, {25.0, 0.0}, c), std::invalid_argument);
}

}  // namespace
}  // namespace codesign::core
