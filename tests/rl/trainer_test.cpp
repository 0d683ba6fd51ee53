// The training loop's SB3 semantics on toy environments: timeout bootstrapping, episode starts,
// clipped actions to the env / unclipped in the buffer, episode statistics; determinism across
// thread counts; deterministic evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <vector>

#include <unistd.h>

#include "rl/pendulum.hpp"
#include "rl/trainer.hpp"

namespace codesign::rl {
namespace {

// Constant observation, reward 1 per step; the episode ends after 3 steps, by truncation for
// environment 0 and by termination for environment 1. Records the actions it receives.
class ThreeStepEnv final : public Env {
 public:
  explicit ThreeStepEnv(std::size_t index, std::vector<double>* received)
      : index_(index), received_(received) {
    spec_.observation.low = Eigen::Vector2d::Constant(-1.0);
    spec_.observation.high = Eigen::Vector2d::Constant(1.0);
    spec_.action.low = Eigen::VectorXd::Constant(1, -1.0);
    spec_.action.high = Eigen::VectorXd::Constant(1, 1.0);
  }
  const EnvSpec& spec() const override { return spec_; }
  Eigen::VectorXd reset(std::optional<std::uint64_t>) override {
    t_ = 0;
    return Eigen::Vector2d(0.5, -0.25);
  }
  StepResult step(const Eigen::VectorXd& a) override {
    received_->push_back(a(0));
    StepResult r;
    r.obs = Eigen::Vector2d(0.5, -0.25);
    r.reward = 1.0;
    if (++t_ == 3) (index_ == 0 ? r.truncated : r.terminated) = true;
    return r;
  }

 private:
  EnvSpec spec_;
  std::size_t index_;
  std::vector<double>* received_;
  int t_ = 0;
};

TrainerConfig toy_config() {
  TrainerConfig c;
  c.n_envs = 2;
  c.seed = 5;
  c.ppo.n_steps = 7;
  c.ppo.batch_size = 14;
  c.ppo.gamma = 0.9;
  c.ppo.actor_hidden = {4};
  c.ppo.critic_hidden = {4};
  c.ppo.log_std_init = 2.0;  // sigma = 7.4: most samples fall outside [-1, 1]
  c.total_timesteps = 14;
  return c;
}

TEST(Trainer, TimeoutBootstrapAddsDiscountedTerminalValue) {
  std::vector<double> received[2];
  EnvFactory f = [&](std::size_t i) { return std::make_unique<ThreeStepEnv>(i, &received[i]); };
  Trainer trainer(f, toy_config());
  // Make V(obs) = 5 for every observation: zero weights, output bias 5.
  MlpT<float>& critic = trainer.model().critic();
  critic.params().setZero();
  critic.bias(critic.num_layers())(0) = 5.0f;

  trainer.collect_rollouts();
  const RolloutBuffer& b = trainer.buffer();
  // Steps t = 0..6; both envs end an episode at t = 2 and t = 5.
  //   env 0 (truncated): reward at t = 2, 5 is 1 + gamma V(terminal) = 1 + 0.9 * 5 = 5.5
  //   env 1 (terminated): no bootstrap, reward 1 everywhere.
  for (int t = 0; t < 7; ++t) {
    const bool end = (t == 2 || t == 5);
    EXPECT_FLOAT_EQ(b.rewards()(t * 2 + 0), end ? 5.5f : 1.0f) << "t=" << t;
    EXPECT_FLOAT_EQ(b.rewards()(t * 2 + 1), 1.0f) << "t=" << t;
    // episode_starts: first step of the rollout, and the step after each episode end.
    const float start = (t == 0 || t == 3 || t == 6) ? 1.0f : 0.0f;
    EXPECT_EQ(b.episode_starts()(t * 2 + 0), start) << "t=" << t;
    EXPECT_EQ(b.episode_starts()(t * 2 + 1), start) << "t=" << t;
  }
  // GAE of the last step (t = 6, not done, next value 5, V = 5):
  //   delta = 1 + 0.9 * 5 - 5 = 0.5 = advantage; return = 5.5.
  EXPECT_NEAR(b.advantages()(12), 0.5f, 1e-6);
  EXPECT_NEAR(b.returns()(12), 5.5f, 1e-6);
  // Terminated env at t = 5 (next_non_terminal = 0): advantage = 1 - 5 = -4.
  EXPECT_NEAR(b.advantages()(11), -4.0f, 1e-6);

  // Episode statistics count raw rewards (no bootstrap): 4 episodes of return 3, length 3.
  ASSERT_EQ(trainer.num_episodes(), 4);
  for (const EpisodeRecord& e : trainer.recent_episodes()) {
    EXPECT_DOUBLE_EQ(e.episode_return, 3.0);
    EXPECT_EQ(e.length, 3);
  }
  EXPECT_EQ(trainer.num_timesteps(), 14);
}

TEST(Trainer, EnvGetsClippedActionsBufferKeepsUnclipped) {
  std::vector<double> received[2];
  EnvFactory f = [&](std::size_t i) { return std::make_unique<ThreeStepEnv>(i, &received[i]); };
  Trainer trainer(f, toy_config());
  trainer.collect_rollouts();
  const RolloutBuffer& b = trainer.buffer();
  int outside = 0;
  for (int t = 0; t < 7; ++t) {
    for (int e = 0; e < 2; ++e) {
      const double stored = b.actions()(0, t * 2 + e);
      if (std::abs(stored) > 1.0) ++outside;
      EXPECT_DOUBLE_EQ(received[e][static_cast<std::size_t>(t)], std::clamp(stored, -1.0, 1.0));
    }
  }
  // With sigma = e^2 = 7.39 a sample lands in [-1, 1] with probability < 0.11; 14 samples all
  // inside has probability < 1e-13.
  EXPECT_GT(outside, 0);
}

TrainerConfig small_pendulum_config(std::size_t threads) {
  TrainerConfig c;
  c.n_envs = 4;
  c.n_threads = threads;
  c.seed = 11;
  c.ppo.n_steps = 64;
  c.ppo.batch_size = 64;
  c.ppo.n_epochs = 2;
  c.ppo.gamma = 0.9;
  c.total_timesteps = 3 * 4 * 64;
  return c;
}

TEST(Trainer, BitIdenticalForOneAndFourThreads) {
  Trainer one(pendulum_factory(), small_pendulum_config(1));
  Trainer four(pendulum_factory(), small_pendulum_config(4));
  one.learn();
  four.learn();
  EXPECT_EQ(one.num_timesteps(), 3 * 256);
  EXPECT_EQ(one.model().actor().params(), four.model().actor().params());
  EXPECT_EQ(one.model().critic().params(), four.model().critic().params());
  EXPECT_EQ(one.model().log_std(), four.model().log_std());
  EXPECT_EQ(one.buffer().rewards(), four.buffer().rewards());
  // A different seed gives a different model.
  TrainerConfig other = small_pendulum_config(1);
  other.seed = 12;
  Trainer t3(pendulum_factory(), other);
  t3.learn();
  EXPECT_NE(one.model().actor().params(), t3.model().actor().params());
}

// ppo.policy = "gru" in the gym trainer: the same results for 1 and 4 threads; the hidden states
// carry across rollouts (Pendulum's 200-step episodes span the 64-step rollouts), so the second
// rollout starts from non-zero states; the trained policy evaluates as its policy file does.
TEST(Trainer, RecurrentPolicyIsThreadIndependentCarriesItsStateAndEvaluatesAsItsFile) {
  TrainerConfig c1 = small_pendulum_config(1), c4 = small_pendulum_config(4);
  for (TrainerConfig* c : {&c1, &c4}) {
    c->ppo.policy = PolicyKind::Gru;
    c->ppo.gru_hidden = 8;
  }
  Trainer one(pendulum_factory(), c1), four(pendulum_factory(), c4);
  one.collect_rollouts();
  one.update();
  ASSERT_NE(one.recurrent(), nullptr);
  const RecurrentActorCritic first = *one.recurrent();
  EXPECT_EQ(one.rollout_start_state()->actor.squaredNorm(), 0.0f);  // the first rollout starts from zero
  one.collect_rollouts();  // steps 64-127 of 200-step episodes: no episode starts in this rollout
  EXPECT_EQ(one.buffer().episode_starts().sum(), 0.0f);
  EXPECT_GT(one.rollout_start_state()->actor.squaredNorm(), 0.0f) << "the state must carry across rollouts";
  EXPECT_GT(one.rollout_start_state()->critic.squaredNorm(), 0.0f);
  one.update();
  one.learn();
  four.learn();
  EXPECT_EQ(one.recurrent()->actor_gru().params(), four.recurrent()->actor_gru().params());
  EXPECT_EQ(one.recurrent()->critic().params(), four.recurrent()->critic().params());
  EXPECT_NE(one.recurrent()->actor_gru().params(), first.actor_gru().params());
  const PolicyFileContents contents = one.policy_contents();
  ASSERT_TRUE(contents.recurrent.has_value());
  const std::filesystem::path file =
      std::filesystem::path(::testing::TempDir()) / ("trainer_gru_" + std::to_string(::getpid()) + ".cdspol");
  save_policy(file, contents);
  const Policy loaded = Policy::load(file);
  EXPECT_TRUE(loaded.recurrent());
  const EvalResult a = evaluate(Policy(contents), pendulum_factory(), 3, 4242);
  const EvalResult b = evaluate(loaded, pendulum_factory(), 3, 4242);
  EXPECT_EQ(a.returns, b.returns);
  std::filesystem::remove(file);
}

TEST(Trainer, LearnStopsAtFirstRolloutReachingTotal) {
  TrainerConfig c = small_pendulum_config(1);
  c.total_timesteps = 257;  // one rollout is 256 steps: SB3 runs a second one
  Trainer t(pendulum_factory(), c);
  int calls = 0;
  t.learn([&](const TrainProgress& p) {
    ++calls;
    EXPECT_EQ(p.iteration, calls);
    EXPECT_EQ(p.timesteps, 256 * calls);
    EXPECT_GT(p.steps_per_s, 0.0);
    EXPECT_FALSE(p.mean_return.has_value());  // no 200-step episode has ended yet
  });
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(t.num_timesteps(), 512);
  // 512 steps over 4 envs = 128 steps each: no 200-step episode has ended.
  EXPECT_EQ(t.num_episodes(), 0);
}

TEST(Evaluate, DeterministicEpisodesSeededPerEpisode) {
  // Zero torque: return of episode k equals a hand-rolled loop from Pendulum reset(seed + k).
  const DeterministicPolicy zero = [](const Eigen::VectorXd&) {
    return Eigen::VectorXd::Zero(1).eval();
  };
  const EvalResult r = evaluate(zero, pendulum_factory(), 3, 1000);
  ASSERT_EQ(r.returns.size(), 3u);
  double mean = 0;
  for (int k = 0; k < 3; ++k) {
    Pendulum p;
    p.reset(1000 + static_cast<std::uint64_t>(k));
    double ret = 0;
    for (int t = 0; t < 200; ++t) ret += p.step(Eigen::VectorXd::Zero(1)).reward;
    EXPECT_DOUBLE_EQ(r.returns[static_cast<std::size_t>(k)], ret);
    EXPECT_EQ(r.lengths[static_cast<std::size_t>(k)], 200);
    mean += ret / 3;
  }
  EXPECT_NEAR(r.mean_return, mean, 1e-9);
  double var = 0;
  for (double x : r.returns) var += (x - mean) * (x - mean) / 3;
  EXPECT_NEAR(r.std_return, std::sqrt(var), 1e-9);

  // Actions are clipped: a policy asking for 100 behaves as one asking for 2.
  const DeterministicPolicy big = [](const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, 100.0).eval();
  };
  const DeterministicPolicy two = [](const Eigen::VectorXd&) {
    return Eigen::VectorXd::Constant(1, 2.0).eval();
  };
  EXPECT_EQ(evaluate(big, pendulum_factory(), 2, 7).returns,
            evaluate(two, pendulum_factory(), 2, 7).returns);
}

}  // namespace
}  // namespace codesign::rl

namespace codesign::rl {
namespace {

// A short learning check (the full acceptance run is scripts/pendulum_seeds.sh). The issue's
// Pendulum settings for 12 rollouts (49152 steps, ~1 s in Release). The untrained policy scores
// about -1245 (mean action ~0: the pendulum is never swung up); after 12 rollouts seeds 0..6
// scored between -263 and -211 when this test was written. A learner that does not learn stays
// near -1200; -400 separates the two with a wide margin on both sides.
TEST(TrainerLearning, PendulumImprovesWithin12Rollouts) {
  TrainerConfig c;
  c.seed = 0;
  c.n_envs = 4;
  c.ppo.n_steps = 1024;
  c.ppo.batch_size = 64;
  c.ppo.n_epochs = 10;
  c.ppo.gamma = 0.9;
  c.ppo.gae_lambda = 0.95;
  c.ppo.learning_rate = 1e-3;
  c.ppo.clip_range = 0.2;
  c.ppo.ent_coef = 0.0;
  c.total_timesteps = 12 * 4096;
  Trainer t(pendulum_factory(), c);
  const double before =
      evaluate(t.model(), pendulum_factory(), 20, c.seed + kEvalSeedOffset).mean_return;
  t.learn();
  const double after =
      evaluate(t.model(), pendulum_factory(), 20, c.seed + kEvalSeedOffset).mean_return;
  EXPECT_LT(before, -1000.0);
  EXPECT_GT(after, -400.0) << "before " << before;
}

}  // namespace
}  // namespace codesign::rl
