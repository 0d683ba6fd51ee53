// Numerical failure injection ([faults], TaskConfig::faults): an injected NaN pressure or
// inverted element ends exactly the episode it is injected into, with a "numerical: ..." reason,
// after the same rewards as a clean episode up to that decision; the episode restarted after it
// is bit-identical to a clean one.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "core/failure_count.hpp"
#include "core/whisker_env.hpp"

namespace {

using namespace codesign;
using core::EpisodeSetup;
using core::Fault;
using core::TaskConfig;
using core::WhiskerEnv;

std::shared_ptr<core::SimulatorPool> pool() {
  static auto p = std::make_shared<core::SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  return p;
}

struct Steps {
  std::vector<double> rewards;
  std::vector<Eigen::VectorXd> obs;
  std::string reason;
};

// Up to `n` decisions of a small constant action, from the current reset.
Steps run(WhiskerEnv& env, int n) {
  Steps s;
  Eigen::VectorXd a = Eigen::VectorXd::Constant(1, 0.05);
  for (int k = 0; k < n; ++k) {
    const rl::StepResult r = env.step(a);
    s.rewards.push_back(r.reward);
    s.obs.push_back(r.obs);
    if (r.done()) {
      s.reason = r.reason;
      break;
    }
  }
  return s;
}

void expect_only_the_faulted_episode_ends(Fault fault, const std::string& status) {
  TaskConfig task;
  task.faults.at_decision = 2;
  EpisodeSetup setup;
  setup.design = 21;
  setup.p1_kPa = 5.0;

  WhiskerEnv clean(pool(), task);
  clean.set_episode(setup);
  clean.reset(std::nullopt);
  const Steps reference = run(clean, 5);
  ASSERT_EQ(reference.rewards.size(), 5u) << reference.reason;  // a clean episode goes past decision 2

  WhiskerEnv env(pool(), task);
  EpisodeSetup faulted = setup;
  faulted.fault = fault;
  env.set_episode(faulted);
  env.reset(std::nullopt);
  const Steps broken = run(env, 5);
  ASSERT_EQ(broken.rewards.size(), 3u) << "ends at decision 2, not before or after: " << broken.reason;
  EXPECT_EQ(broken.reason.rfind("numerical: " + status + ": ", 0), 0u) << broken.reason;
  EXPECT_TRUE(core::is_numerical_failure(broken.reason));
  for (int k = 0; k < 2; ++k) EXPECT_EQ(broken.rewards[k], reference.rewards[k]) << "decision " << k;
  EXPECT_EQ(broken.rewards[2], 0.0);
  EXPECT_TRUE(broken.obs[2].allFinite());

  // The restart (reset() alone, as the rollout does after an early end) runs clean.
  env.reset(std::nullopt);
  const Steps again = run(env, 5);
  ASSERT_EQ(again.rewards.size(), reference.rewards.size()) << again.reason;
  for (std::size_t k = 0; k < again.rewards.size(); ++k) {
    EXPECT_EQ(again.rewards[k], reference.rewards[k]) << "decision " << k;
    EXPECT_EQ(again.obs[k], reference.obs[k]) << "decision " << k;
  }
}

TEST(FaultInjection, NanPressureEndsOnlyItsEpisode) { expect_only_the_faulted_episode_ends(Fault::NanPressure, "non_finite"); }

TEST(FaultInjection, InvertedElementEndsOnlyItsEpisode) {
  expect_only_the_faulted_episode_ends(Fault::InvertedElement, "inverted_element");
}

TEST(FaultInjection, WhichEpisodesGetAFault) {
  core::FaultConfig f;
  EXPECT_FALSE(f.enabled());
  EXPECT_EQ(f.fault_for(3, 1, 4), Fault::None);
  f.nan_pressure_every = 3;
  f.inverted_element_every = 5;
  // c = k * 4 + i + 1 over 3 iterations of 4 environments: 1..12.
  std::vector<Fault> got;
  for (int k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < 4; ++i) got.push_back(f.fault_for(k, i, 4));
  const Fault N = Fault::None, P = Fault::NanPressure, I = Fault::InvertedElement;
  EXPECT_EQ(got, (std::vector<Fault>{N, N, P, N, I, P, N, N, P, I, N, P}));
}

}  // namespace
