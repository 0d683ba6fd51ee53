// Simulator snapshots: stepping after restore() repeats the steps after snapshot() bit for bit,
// on the same simulator after other work and on another simulator of the same model.
#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "fem/simulator.hpp"
#include "fem/whisker_model.hpp"

namespace {

using namespace codesign::fem;

struct Trace {
  std::vector<double> force;
  Eigen::VectorXd x;
};

// 40 steps with the base turning back and forth (large turns: the fast step refactorises).
Trace steps(Simulator& sim) {
  Trace r;
  for (int k = 0; k < 40; ++k) {
    if (k % 5 == 0) sim.set_base_angle_target(sim.theta() + (k % 10 == 0 ? 0.06 : -0.05), 5);
    const StepResult s = sim.step();
    EXPECT_TRUE(s.ok()) << s.reason;
    r.force.push_back(sim.sensors().contact_force_mN);
  }
  r.x = sim.positions();
  return r;
}

TEST(Snapshot, RestoreRepeatsTheStepsBitForBit) {
  const auto model = build_whisker_model(21, WhiskerModelSpec{});
  SolverConfig so;
  Simulator a(model, SceneConfig{}, so);
  a.set_pressures_kPa(4.0, 0.0);
  a.set_plate_phase(1.0);
  ASSERT_TRUE(a.settle().ok());
  const Simulator::Snapshot snap = a.snapshot();
  const Trace first = steps(a);
  // The same simulator, after more steps and another episode.
  a.reset();
  a.set_pressures_kPa(11.0, 0.0);
  ASSERT_TRUE(a.settle().ok());
  steps(a);
  ASSERT_TRUE(a.restore(snap).ok());
  const Trace again = steps(a);
  EXPECT_EQ(first.force, again.force);
  EXPECT_TRUE(first.x == again.x);
  // Another simulator of the same model.
  Simulator b(model, SceneConfig{}, so);
  ASSERT_TRUE(b.restore(snap).ok());
  const Trace other = steps(b);
  EXPECT_EQ(first.force, other.force);
  EXPECT_TRUE(first.x == other.x);
}

// An episode restarted from the state settle() left (what the whisker task does after an early
// termination) reuses the factor settle() built there instead of factorising it again, and
// still repeats the steps bit for bit; the steps in between refactorised (large turns), so the
// reused factor is not simply the one in use.
TEST(Snapshot, RestoringTheLastSettledStateReusesItsFactor) {
  const auto model = build_whisker_model(21, WhiskerModelSpec{});
  Simulator a(model, SceneConfig{}, SolverConfig{});
  a.set_pressures_kPa(4.0, 0.0);
  a.set_plate_phase(1.0);
  ASSERT_TRUE(a.settle().ok());
  const Simulator::Snapshot snap = a.snapshot();
  const int after_settle = a.factorisations();
  const Trace first = steps(a);
  ASSERT_GT(a.factorisations(), after_settle) << "the turns should have forced a refactorisation";
  const int before_restore = a.factorisations();
  const StepResult r = a.restore(snap);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r.refactorised);
  EXPECT_EQ(a.factorisations(), before_restore);
  const Trace again = steps(a);
  EXPECT_EQ(first.force, again.force);
  EXPECT_TRUE(first.x == again.x);
}

TEST(Snapshot, RejectsEmptyOrForeignSnapshots) {
  const auto m21 = build_whisker_model(21, WhiskerModelSpec{});
  const auto m63 = build_whisker_model(63, WhiskerModelSpec{});
  Simulator a(m21, SceneConfig{}, SolverConfig{});
  Simulator b(m63, SceneConfig{}, SolverConfig{});
  EXPECT_THROW(a.restore(Simulator::Snapshot{}), std::invalid_argument);
  EXPECT_THROW(a.restore(b.snapshot()), std::invalid_argument);
}

// A simulator that gave up its stored factors (what the simulator pool does to the simulators it
// keeps idle) runs an episode bit for bit as a new simulator of the same model does, with the
// fast step and with the exact step; it keeps only the reset placement's references.
TEST(Snapshot, DroppedFactorsLeaveNoTraceInTheNextEpisode) {
  const auto model = build_whisker_model(21, WhiskerModelSpec{});
  for (const StepMethod method : {StepMethod::Fast, StepMethod::Exact}) {
    SolverConfig so;
    so.method = method;
    const auto episode = [&](Simulator& sim) {
      sim.reset();
      sim.set_pressures_kPa(6.0, 0.0);
      sim.set_plate_phase(0.5);
      EXPECT_TRUE(sim.settle().ok());
      return steps(sim);
    };
    Simulator fresh(model, SceneConfig{}, so);
    const int before = fresh.factorisations();
    const Trace want = episode(fresh);
    const int per_episode = fresh.factorisations() - before;
    ASSERT_GT(per_episode, 0);

    Simulator used(model, SceneConfig{}, so);
    used.reset();
    used.set_pressures_kPa(12.0, 0.0);
    ASSERT_TRUE(used.settle().ok());
    steps(used);
    used.drop_stored_factors();
    const int used_before = used.factorisations();
    const Trace got = episode(used);
    EXPECT_EQ(got.force, want.force) << (method == StepMethod::Fast ? "fast" : "exact");
    EXPECT_TRUE(got.x == want.x);
    // Everything but the reset placement's references is built again.
    if (method == StepMethod::Fast) {
      EXPECT_LT(used.factorisations() - used_before, per_episode);
      EXPECT_GT(used.factorisations() - used_before, 0);
    } else {
      EXPECT_EQ(used.factorisations() - used_before, per_episode);
    }
  }
}

}  // namespace
