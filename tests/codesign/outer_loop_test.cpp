// Algorithm 1: thread-count independence, exact state restore, the phases and the baselines.
#include <gtest/gtest.h>

#include <memory>

#include "codesign/outer_loop.hpp"
#include "test_setup.hpp"

namespace {

using namespace codesign;
using namespace codesign::coopt;

std::unique_ptr<OuterLoop> make_loop(const RunSettings& s, std::size_t threads) {
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  auto envs = std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, threads);
  return std::make_unique<OuterLoop>(s.loop, std::move(envs));
}

TEST(OuterLoop, BitIdenticalForOneAndTwoThreads) {
  const RunSettings s = test::tiny_run();
  auto a = make_loop(s, 1), b = make_loop(s, 2);
  for (int k = 0; k < 3; ++k) {
    const IterationReport ra = a->iterate(), rb = b->iterate();
    ASSERT_EQ(ra.episodes.size(), rb.episodes.size());
    for (std::size_t i = 0; i < ra.episodes.size(); ++i)
      EXPECT_EQ(ra.episodes[i].episode_return, rb.episodes[i].episode_return);
  }
  EXPECT_TRUE(a->model().actor().params() == b->model().actor().params());
  EXPECT_TRUE(a->model().critic().params() == b->model().critic().params());
}

TEST(OuterLoop, RestoredStateContinuesIdentically) {
  const RunSettings s = test::tiny_run();
  auto a = make_loop(s, 1);
  a->iterate();
  a->iterate();
  const LoopState mid = a->state();
  const IterationReport ra = a->iterate();
  auto b = make_loop(s, 1);
  b->restore(mid);
  const IterationReport rb = b->iterate();
  ASSERT_EQ(ra.samples.size(), rb.samples.size());
  for (std::size_t i = 0; i < ra.samples.size(); ++i) {
    EXPECT_EQ(ra.samples[i].design, rb.samples[i].design);
    EXPECT_EQ(ra.samples[i].pressures_kPa, rb.samples[i].pressures_kPa);
  }
  EXPECT_TRUE(a->model().actor().params() == b->model().actor().params());
  EXPECT_EQ(a->state().rng_design, b->state().rng_design);
  EXPECT_EQ(a->state().distribution.score, b->state().distribution.score);
}

TEST(OuterLoop, PhasesEndCollapsedOnOneDesign) {
  const RunSettings s = test::tiny_run();
  auto a = make_loop(s, 2);
  std::vector<Phase> phases;
  IterationReport last;
  while (!a->finished()) {
    last = a->iterate();
    phases.push_back(last.phase);
  }
  ASSERT_EQ(phases.size(), 6u);  // 120 timesteps in iterations of 4 x 5
  EXPECT_EQ(phases[0], Phase::Exploration);   // t = 0, 20
  EXPECT_EQ(phases[2], Phase::Transition);    // t = 40, 60
  EXPECT_EQ(phases[4], Phase::Exploitation);  // t = 80, 100
  ASSERT_TRUE(a->distribution().state().collapsed);
  const int best = a->distribution().state().best_design;
  for (const DesignSample& d : last.samples) EXPECT_EQ(d.design, best);
}

TEST(OuterLoop, SingleDesignBaselineSamplesOnlyItsDesign) {
  RunSettings s = test::tiny_run();
  s.loop.codesign.baseline = Baseline::SingleDesign;
  s.loop.codesign.single_design_index = 63;
  s.loop.codesign.single_design_p1_kPa = 2.0;
  s.loop.codesign.single_design_p2_kPa = 3.0;
  auto a = make_loop(s, 1);
  const IterationReport r = a->iterate();
  for (const EpisodeRecord& e : r.episodes) {
    EXPECT_EQ(e.setup.design, 63);
    EXPECT_EQ(e.setup.p1_kPa, 2.0);
    EXPECT_EQ(e.setup.p2_kPa, 3.0);
  }
}

// ppo.privileged_critic: the critic reads the environments' kPrivilegedDim extra rows, the
// actor and the policy the loop hands out (its normalisation too) only the task's observation.
TEST(OuterLoop, PrivilegedCriticReadsTheExtraRowsAndThePolicyDoesNot) {
  RunSettings s = test::tiny_run();
  s.loop.ppo.privileged_critic = true;
  s.loop.ppo.normalize_observations = true;
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  OuterLoop loop(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, 1, true));
  const int obs = observation_dim(s.loop.task);
  EXPECT_EQ(loop.model().obs_dim(), obs);
  EXPECT_EQ(loop.model().critic_input_dim(), obs + kPrivilegedDim);
  const Eigen::VectorXf before = loop.model().critic().params();
  for (int k = 0; k < 2; ++k) loop.iterate();
  EXPECT_FALSE(loop.model().critic().params() == before);  // it trained
  ASSERT_TRUE(loop.obs_normalization().has_value());
  EXPECT_EQ(loop.obs_normalization()->mean.size(), obs);
  EXPECT_EQ(loop.obs_normalization()->var.size(), obs);
  // The config and the environments must agree.
  EXPECT_THROW(OuterLoop(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, 1, false)),
               std::invalid_argument);
  s.loop.ppo.privileged_critic = false;
  EXPECT_THROW(OuterLoop(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, 1, true)),
               std::invalid_argument);
}

TEST(OuterLoop, RejectsRolloutLengthOtherThanAnEpisode) {
  RunSettings s = test::tiny_run();
  s.loop.ppo.n_steps = 6;
  EXPECT_THROW(make_loop(s, 1), std::invalid_argument);
}

}  // namespace
