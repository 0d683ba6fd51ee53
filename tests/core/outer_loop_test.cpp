// Algorithm 1: thread-count independence, exact state restore, the phases and the baselines.
#include <gtest/gtest.h>

#include <memory>

#include "core/outer_loop.hpp"
#include "tiny_loop.hpp"

namespace {

using namespace codesign;
using namespace codesign::core;
using test_loops::TinyLoop;
using test_loops::tiny_loop;

std::unique_ptr<OuterLoop> make_loop(const TinyLoop& s, std::size_t threads) {
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  auto envs = std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, threads);
  return std::make_unique<OuterLoop>(s.loop, std::move(envs));
}

TEST(OuterLoop, BitIdenticalForOneAndTwoThreads) {
  const TinyLoop s = tiny_loop();
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
  const TinyLoop s = tiny_loop();
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
  const TinyLoop s = tiny_loop();
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
  TinyLoop s = tiny_loop();
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
  TinyLoop s = tiny_loop();
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

// The memory observer (telemetry of the recurrent policy) sees, after each decision of
// environment 0, the hidden states that the model's own steps give from that environment's
// observations, starting from zero at the episode's start.
TEST(OuterLoop, MemoryObserverSeesEnvironmentZerosHiddenStates) {
  TinyLoop s = tiny_loop();
  s.loop.ppo.policy = rl::PolicyKind::Gru;
  s.loop.ppo.gru_hidden = 8;
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  OuterLoop loop(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, 1, false));
  struct Seen {
    int decision, design;
    Eigen::VectorXf actor, critic;
  };
  std::vector<Seen> seen;
  loop.set_memory_observer([&](int decision, int design, const Eigen::VectorXf& a, const Eigen::VectorXf& c) {
    seen.push_back({decision, design, a, c});
  });
  const rl::RecurrentActorCritic model = *loop.recurrent_model();  // the rollout's parameters
  const IterationReport rep = loop.iterate();
  const int n_steps = s.loop.ppo.n_steps;
  ASSERT_EQ(static_cast<int>(seen.size()), n_steps);
  const rl::RolloutBuffer& buf = loop.buffer();
  Eigen::MatrixXf h = Eigen::MatrixXf::Zero(8, 1);
  for (int k = 0; k < n_steps; ++k) {
    // A new episode (the first, or one after an episode that ended early, e.g. lost contact)
    // starts at decision 0 from a zero state; otherwise the count goes on.
    const bool starts = buf.episode_starts()(static_cast<Eigen::Index>(k) * 4) > 0.5f;
    EXPECT_EQ(starts, k == 0 || seen[k].decision == 0) << "decision " << k;
    EXPECT_EQ(seen[k].decision, starts ? 0 : seen[k - 1].decision + 1);
    EXPECT_EQ(seen[k].design, rep.samples[0].design);
    ASSERT_EQ(seen[k].actor.size(), 8);
    ASSERT_EQ(seen[k].critic.size(), 8);
    // Environment 0's column of step k; the same GRU step as the rollout's, so equal to rounding.
    const Eigen::MatrixXf obs = buf.observations().col(static_cast<Eigen::Index>(k) * 4);
    Eigen::RowVectorXf start(1);
    start(0) = starts ? 1.0f : 0.0f;
    model.deterministic_step(obs, start, h);
    EXPECT_LE((seen[k].actor - h.col(0)).cwiseAbs().maxCoeff(), 1e-5f) << "decision " << k;
    EXPECT_GT(seen[k].critic.norm(), 0.0f);
  }
  // Off for the feed-forward policy: never called.
  s.loop.ppo.policy = rl::PolicyKind::Mlp;
  OuterLoop mlp(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, 1, false));
  int calls = 0;
  mlp.set_memory_observer([&](int, int, const Eigen::VectorXf&, const Eigen::VectorXf&) { ++calls; });
  mlp.iterate();
  EXPECT_EQ(calls, 0);
}

// ppo.policy = "gru": the loop trains the recurrent model (both GRUs and both MLPs move), its
// state restores exactly, and a state without the GRU parameters is refused.
TEST(OuterLoop, RecurrentPolicyTrainsAndRestoresExactly) {
  TinyLoop s = tiny_loop();
  s.loop.ppo.policy = rl::PolicyKind::Gru;
  s.loop.ppo.gru_hidden = 8;
  s.loop.ppo.privileged_critic = true;
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  auto make = [&] { return std::make_unique<OuterLoop>(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, 4, 1, true)); };
  auto a = make();
  ASSERT_NE(a->recurrent_model(), nullptr);
  const rl::RecurrentActorCritic before = *a->recurrent_model();
  EXPECT_EQ(before.gru_hidden(), 8);
  EXPECT_EQ(before.obs_dim(), observation_dim(s.loop.task));
  EXPECT_EQ(before.critic_input_dim(), observation_dim(s.loop.task) + kPrivilegedDim);
  a->iterate();
  const LoopState mid = a->state();
  EXPECT_EQ(mid.actor_gru.size(), before.actor_gru().num_params());
  EXPECT_EQ(mid.adam_m.size(), 5u);
  const IterationReport ra = a->iterate();
  EXPECT_GT(ra.ppo.minibatches_applied, 0);
  const rl::RecurrentActorCritic& after = *a->recurrent_model();
  EXPECT_FALSE(after.actor_gru().params() == before.actor_gru().params());
  EXPECT_FALSE(after.critic_gru().params() == before.critic_gru().params());
  EXPECT_FALSE(after.critic().params() == before.critic().params());
  auto b = make();
  b->restore(mid);
  const IterationReport rb = b->iterate();
  ASSERT_EQ(ra.episodes.size(), rb.episodes.size());
  for (std::size_t i = 0; i < ra.episodes.size(); ++i)
    EXPECT_EQ(ra.episodes[i].episode_return, rb.episodes[i].episode_return);
  EXPECT_TRUE(b->recurrent_model()->actor_gru().params() == after.actor_gru().params());
  EXPECT_TRUE(b->recurrent_model()->actor().params() == after.actor().params());
  EXPECT_TRUE(b->recurrent_model()->critic_gru().params() == after.critic_gru().params());
  EXPECT_TRUE(b->policy_contents().recurrent.has_value());
  LoopState bad = mid;
  bad.actor_gru.resize(0);
  EXPECT_THROW(make()->restore(bad), std::invalid_argument);
  // A feed-forward loop refuses a recurrent state.
  s.loop.ppo.policy = rl::PolicyKind::Mlp;
  auto mlp = make();
  LoopState mlp_state = mlp->state();
  mlp_state.actor_gru = mid.actor_gru;
  EXPECT_THROW(mlp->restore(mlp_state), std::invalid_argument);
}

TEST(OuterLoop, RejectsRolloutLengthOtherThanAnEpisode) {
  TinyLoop s = tiny_loop();
  s.loop.ppo.n_steps = 6;
  EXPECT_THROW(make_loop(s, 1), std::invalid_argument);
}

}  // namespace
