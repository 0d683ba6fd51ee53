// ThreadEnvPool's step observer: the state at the end of every N-th decision of one environment,
// equal to that environment's own trace; its build seconds: CPU of simulator and model builds only.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "core/env_pool.hpp"

namespace {

using namespace codesign;
using core::EpisodeSetup;
using core::TraceRow;

TEST(ThreadEnvPool, StepObserverSeesTheEndOfEveryNthDecision) {
  auto sims = std::make_shared<core::SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  const core::TaskConfig task;
  core::ThreadEnvPool pool(sims, task, 2, 1);
  std::vector<TraceRow> seen;
  std::vector<int> designs;
  pool.set_step_observer(
      0,
      [&](const EpisodeSetup& s, const TraceRow& r) {
        designs.push_back(s.design);
        seen.push_back(r);
      },
      2);
  const EpisodeSetup a{21, 2.0, 0.0, 0.5, 0.0}, b{63, 1.0, 3.0, 1.5, 0.0};
  pool.start({a, b});
  const int decisions = 7;
  Eigen::MatrixXd actions(1, 2);
  actions << 0.02, -0.4;
  for (int k = 0; k < decisions; ++k) pool.step(actions, true);

  // The same episode on its own, recorded: row 0 is the settled state, then action_hold_steps
  // rows per decision, so decision d (1-based) ends at row d * hold.
  core::WhiskerEnv env(sims, task);
  env.set_recording(true);
  env.set_episode(a);
  env.reset(std::nullopt);
  Eigen::VectorXd act(1);
  act[0] = 0.02;
  for (int k = 0; k < decisions; ++k) ASSERT_FALSE(env.step(act).done()) << k;
  const std::vector<TraceRow>& trace = env.trace();
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(decisions / 2));
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const TraceRow& want = trace[static_cast<std::size_t>(2 * (i + 1) * task.action_hold_steps)];
    EXPECT_EQ(seen[i].t_s, want.t_s) << i;
    EXPECT_EQ(seen[i].force_mN, want.force_mN) << i;
    EXPECT_EQ(seen[i].theta_rad, want.theta_rad) << i;
    EXPECT_EQ(seen[i].strain, want.strain) << i;
    EXPECT_EQ(seen[i].decision, want.decision) << i;
    EXPECT_EQ(seen[i].action, want.action) << i;
    EXPECT_EQ(designs[i], 21);
  }
  // Off: nothing more.
  pool.set_step_observer(0, nullptr, 2);
  for (int k = 0; k < 2; ++k) pool.step(actions, true);
  EXPECT_EQ(seen.size(), static_cast<std::size_t>(decisions / 2));
}

// build_seconds() counts the CPU of meshing designs and constructing simulators, and nothing when
// the environments keep the simulators they have; build_stats().model_seconds is the meshing's part
// of it, and its means per model and per simulator split the builds.
// Swapping the two designs (one thread, in either order) builds exactly one more simulator and no
// model: the first environment to start gives its simulator back and finds the other design's
// still held, the second finds the first one's free.
TEST(ThreadEnvPool, BuildSecondsCountBuildsNotLeases) {
  auto sims = std::make_shared<core::SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  const core::TaskConfig task;
  core::ThreadEnvPool pool(sims, task, 2, 1);
  EXPECT_EQ(pool.build_seconds(), 0.0);
  EXPECT_EQ(sims->build_stats().seconds_per_model(), 0.0);  // no build yet: no mean
  EXPECT_EQ(sims->build_stats().seconds_per_simulator(), 0.0);
  const EpisodeSetup a{21, 2.0, 0.0, 0.5, 0.0}, b{63, 1.0, 3.0, 1.5, 0.0};
  pool.start({a, b});
  EXPECT_EQ(sims->constructed(), 2);
  const double first = pool.build_seconds();
  EXPECT_GT(first, 0.0);
  EXPECT_EQ(first, sims->build_seconds());
  // Two designs meshed; their models are part of the builds, the two simulators the rest.
  EXPECT_EQ(sims->build_stats().models, 2);
  EXPECT_EQ(&pool.simulators(), sims.get());
  const double models = sims->build_stats().model_seconds;
  EXPECT_GT(models, 0.0);
  EXPECT_LT(models, first);
  pool.start({a, b});  // each environment keeps its simulator
  EXPECT_EQ(sims->constructed(), 2);
  EXPECT_EQ(pool.build_seconds(), first);
  pool.start({b, a});
  EXPECT_EQ(sims->constructed(), 3);
  EXPECT_GT(pool.build_seconds(), first);
  EXPECT_EQ(sims->build_stats().models, 2);  // a third simulator, of a design already meshed
  const core::SimulatorPool::BuildStats built = sims->build_stats();
  EXPECT_EQ(built.model_seconds, models);
  EXPECT_DOUBLE_EQ(built.seconds_per_model(), models / 2.0);
  EXPECT_DOUBLE_EQ(built.seconds_per_simulator(), (built.seconds - models) / 3.0);
}

}  // namespace
