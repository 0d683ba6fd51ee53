#include "rl/recurrent_ppo.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "fd_check.hpp"
#include "rl/gru_policy.hpp"
#include "rl/rollout.hpp"

namespace codesign::rl {
namespace {

using ModelD = RecurrentActorCriticT<double>;
using BatchD = RecurrentMinibatchT<double>;

void randomise(ModelD& m, Rng& rng, double scale) {
  for (auto* v : {&m.actor_gru().params(), &m.actor().params(), &m.critic_gru().params(), &m.critic().params()})
    for (Eigen::Index i = 0; i < v->size(); ++i) (*v)(i) = scale * rng.normal();
  for (Eigen::Index i = 0; i < m.log_std().size(); ++i) m.log_std()(i) = 0.3 * rng.normal();
}

// `b` sequences of `steps` steps, acted by the model itself from random initial states, with an
// episode start at step 2 of sequence 1; old log-probs shifted so that some ratios leave the clip
// range.
BatchD random_sequences(const ModelD& m, int steps, int b, double log_ratio_spread, Rng& rng) {
  BatchD batch;
  batch.steps = steps;
  const Eigen::Index n = Eigen::Index{steps} * b;
  auto& s = batch.samples;
  s.obs.resize(m.critic_input_dim(), n);
  for (Eigen::Index i = 0; i < s.obs.size(); ++i) s.obs(i) = rng.normal();
  batch.starts = Eigen::RowVectorXd::Zero(n);
  batch.starts(2 * b + 1) = 1;
  ModelD::State state = m.zero_state(b);
  for (auto* h : {&state.actor, &state.critic})
    for (Eigen::Index i = 0; i < h->size(); ++i) (*h)(i) = 0.5 * rng.normal();
  batch.h0_actor = state.actor;
  batch.h0_critic = state.critic;
  s.actions.resize(m.act_dim(), n);
  s.old_log_prob.resize(n);
  for (int t = 0; t < steps; ++t) {
    const auto a = m.act(s.obs.middleCols(Eigen::Index{t} * b, b), batch.starts.segment(Eigen::Index{t} * b, b),
                         state, rng);
    s.actions.middleCols(Eigen::Index{t} * b, b) = a.actions;
    s.old_log_prob.segment(Eigen::Index{t} * b, b) = a.log_probs;
  }
  s.advantages.resize(n);
  s.returns.resize(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    s.old_log_prob(j) += log_ratio_spread * rng.normal();
    s.advantages(j) = rng.normal();
    s.returns(j) = rng.normal();
  }
  return batch;
}

// The whole PPO loss (clipped surrogate, value loss, entropy) of a minibatch of 3 sequences of 4
// steps, with a reset inside one and non-zero initial states, against central differences of
// every parameter of both GRUs, both MLPs and log_std. Tolerance as fd_check.hpp: the loss is of
// order 1 (|L| < 100) and its third derivatives along one parameter stay below ~100 (bounded
// derivatives of σ, tanh and the Gaussian log-density, chained through 4 steps and two layers of
// weights of scale 0.5), so truncation + rounding < 5e-9, far inside 1e-6·(1 + |g|). The clipped
// surrogate is not differentiable where a ratio sits exactly on 1 ± ε; with random ratios no
// sample is within h·|d ratio/dθ| ~ 1e-5 of it, as the matching gradients show.
TEST(RecurrentPpoLoss, FullLossGradientMatchesFiniteDifferences) {
  Rng rng(41);
  ModelD model(3, 2, 4, {5}, {4}, 0.0, 1);
  randomise(model, rng, 0.5);
  const BatchD batch = random_sequences(model, 4, 3, 0.3, rng);
  const PpoLossCoefficients coefs{0.2, 0.05, 0.6, true};
  RecurrentWorkspaceT<double> ws;
  auto grad = model.zero_grad();
  const auto l = recurrent_minibatch_loss<double>(model, batch, coefs, &grad, ws);
  ASSERT_GT(l.clip_fraction, 0.0);
  ASSERT_LT(l.clip_fraction, 1.0);
  EXPECT_NEAR(l.grad_squared_norm,
              grad.actor_gru.squaredNorm() + grad.actor.squaredNorm() + grad.critic_gru.squaredNorm() +
                  grad.critic.squaredNorm() + grad.log_std.squaredNorm(),
              1e-12 * (1 + l.grad_squared_norm));
  auto loss = [&] { return recurrent_minibatch_loss<double>(model, batch, coefs, nullptr, ws).loss; };
  test::expect_gradient_matches(model.actor_gru().params(), loss, grad.actor_gru, "actor GRU");
  test::expect_gradient_matches(model.actor().params(), loss, grad.actor, "actor MLP");
  test::expect_gradient_matches(model.critic_gru().params(), loss, grad.critic_gru, "critic GRU");
  test::expect_gradient_matches(model.critic().params(), loss, grad.critic, "critic MLP");
  test::expect_gradient_matches(model.log_std(), loss, grad.log_std, "log_std");
  // The privileged row reaches the critic's GRU only.
  BatchD moved = batch;
  moved.samples.obs.bottomRows(1).array() += 1.0;
  const auto lm = recurrent_minibatch_loss<double>(model, moved, coefs, nullptr, ws);
  EXPECT_EQ(lm.pg_loss, l.pg_loss);
  EXPECT_NE(lm.value_loss, l.value_loss);
}

// The policy's state: zeroed where an episode starts, carried elsewhere; value_of reads the
// state of the environment asked about.
TEST(GruPolicy, ResetsWhereEpisodesStartAndAsksTheRightColumn) {
  Rng rng(5);
  RecurrentActorCritic model(2, 1, 6, {8}, {8});
  model.init(rng);
  GruPolicy policy(model, 3);
  Eigen::MatrixXf obs(2, 3);
  obs << 0.3f, -1.0f, 0.7f, 0.2f, 0.5f, -0.4f;
  policy.begin_rollout();
  policy.act(obs, Eigen::RowVectorXf::Ones(3), rng);
  const RecurrentState after_one = policy.state();
  EXPECT_GT(after_one.actor.norm(), 0.0f);
  // Step 2: column 1 starts a new episode, the others continue.
  Eigen::RowVectorXf starts(3);
  starts << 0.f, 1.f, 0.f;
  policy.act(obs, starts, rng);
  // Column 1 now holds one step from zero, which is what column 1 held after the first step.
  EXPECT_TRUE(policy.state().actor.col(1).isApprox(after_one.actor.col(1), 1e-6f));
  EXPECT_FALSE(policy.state().actor.col(0).isApprox(after_one.actor.col(0), 1e-3f));
  // value_of(obs, 2) is one critic step from column 2's state, and changes nothing.
  const RecurrentState before = policy.state();
  const float v = policy.value_of(obs.col(0), 2);
  EXPECT_FLOAT_EQ(v, model.value_step(obs.col(0), before.critic.col(2))(0));
  EXPECT_NE(v, model.value_step(obs.col(0), before.critic.col(0))(0));
  EXPECT_EQ(policy.state().critic, before.critic);
  // begin_rollout() records the state the next rollout starts from.
  policy.begin_rollout();
  EXPECT_EQ(policy.rollout_start_state().actor, before.actor);
}

// A memory task: the cue c = ±1 is shown at the first of 4 steps only; the reward, at the last
// step, is −(a − c)². Any policy without memory earns −E[c²] = −1 there; the deterministic
// recurrent policy must get above −1/3 (two thirds of that error removed). Episodes of 4 in
// rollouts of 6 steps, so columns hold episode starts in the middle and rollouts start inside an
// episode: the sequences' stored initial states and reset masks are both needed.
class CueTask {
 public:
  explicit CueTask(int n) : n_(n), t_(n, 0), cue_(n, 1.0), rng_(77) {
    result_.obs = Eigen::MatrixXd::Zero(2, n);
    result_.rewards = Eigen::VectorXd::Zero(n);
    result_.terminated.assign(n, 0);
    result_.truncated.assign(n, 0);
    result_.terminal_obs.assign(n, std::nullopt);
    result_.reasons.assign(n, "");
  }
  Eigen::MatrixXd reset() {
    Eigen::MatrixXd obs(2, n_);
    for (int i = 0; i < n_; ++i) start(i, obs);
    return obs;
  }
  const VecStepResult& step(const Eigen::MatrixXd& actions) {
    for (int i = 0; i < n_; ++i) {
      const bool last = t_[i] == 3;
      result_.rewards(i) = last ? -(actions(0, i) - cue_[i]) * (actions(0, i) - cue_[i]) : 0.0;
      result_.terminated[i] = last;
      ++t_[i];
      if (last) {
        start(i, result_.obs);
      } else {
        result_.obs(0, i) = 0.0;
        result_.obs(1, i) = t_[i] == 3 ? 1.0 : 0.0;
      }
    }
    return result_;
  }

 private:
  // A new episode in environment i: its first observation goes to column i of obs.
  void start(int i, Eigen::MatrixXd& obs) {
    t_[i] = 0;
    cue_[i] = rng_.uniform() < 0.5 ? -1.0 : 1.0;
    obs(0, i) = cue_[i];
    obs(1, i) = 0.0;
  }
  int n_;
  std::vector<int> t_;
  std::vector<double> cue_;
  Rng rng_;
  VecStepResult result_;
};

double deterministic_cue_return(const RecurrentActorCritic& model) {
  double sum = 0;
  for (const float cue : {-1.0f, 1.0f}) {
    Eigen::MatrixXf h = Eigen::MatrixXf::Zero(model.gru_hidden(), 1);
    Eigen::MatrixXf a;
    for (int t = 0; t < 4; ++t) {
      Eigen::MatrixXf obs(2, 1);
      obs << (t == 0 ? cue : 0.0f), (t == 3 ? 1.0f : 0.0f);
      a = model.deterministic_step(obs, Eigen::RowVectorXf::Constant(1, t == 0 ? 1.0f : 0.0f), h);
    }
    sum += -(double(a(0, 0)) - cue) * (double(a(0, 0)) - cue);
  }
  return sum / 2;
}

TEST(RecurrentPpoLearning, RemembersACueShownThreeStepsEarlier) {
  PpoConfig cfg;
  cfg.n_steps = 6;
  cfg.batch_size = 60;  // 10 sequences per minibatch
  cfg.n_epochs = 10;
  cfg.learning_rate = 3e-3;
  cfg.gamma = 0.99;
  const int n_envs = 40, iterations = 60;  // 60 x 240 = 14 400 steps
  ASSERT_EQ(sequences_per_minibatch(cfg, n_envs), 10);
  Rng rng(2024);
  RecurrentActorCritic model(2, 1, 16, {32}, {32});
  model.init(rng);
  Adam adam = make_adam(cfg);
  RolloutBuffer buffer(cfg.n_steps, n_envs, 2, 1);
  CueTask task(n_envs);
  Eigen::MatrixXd obs = task.reset();
  Eigen::RowVectorXf starts = Eigen::RowVectorXf::Ones(n_envs);
  GruPolicy policy(model, n_envs);
  const BoxSpec bounds{Eigen::VectorXd::Constant(1, -5.0), Eigen::VectorXd::Constant(1, 5.0)};
  const RolloutOptions options{cfg.n_steps, cfg.gamma, cfg.gae_lambda, nullptr};
  const RolloutStep step = [&](const Eigen::MatrixXd& a, bool) -> const VecStepResult& { return task.step(a); };
  const double j0 = deterministic_cue_return(model);
  EXPECT_LT(j0, -1.0 / 3);
  PpoStats last;
  for (int k = 0; k < iterations; ++k) {
    collect_rollout(policy, step, bounds, options, obs, starts, buffer, rng);
    // The update's sequences replay the rollout exactly: at the rollout's parameters every ratio
    // is 1 (up to float rounding), which needs the right initial states and reset masks.
    if (k == 1) {
      RecurrentMinibatchT<float> mb;
      mb.steps = cfg.n_steps;
      mb.samples = {buffer.observations(), buffer.actions(), buffer.log_probs(), buffer.advantages(),
                    buffer.returns()};
      mb.starts = buffer.episode_starts();
      mb.h0_actor = policy.rollout_start_state().actor;
      mb.h0_critic = policy.rollout_start_state().critic;
      ASSERT_GT(mb.h0_actor.norm(), 0.0f);  // this rollout starts inside episodes
      RecurrentWorkspaceT<float> ws;
      const auto l = recurrent_minibatch_loss<float>(model, mb, {0.2, 0.0, 0.5, true}, nullptr, ws);
      EXPECT_LT(l.approx_kl, 1e-6f);
      EXPECT_EQ(l.clip_fraction, 0.0f);
    }
    last = recurrent_ppo_update(model, adam, buffer, policy.rollout_start_state(), cfg, 0, rng);
  }
  EXPECT_EQ(last.minibatches_applied, cfg.n_epochs * 4);  // 40 sequences in minibatches of 10
  const double j = deterministic_cue_return(model);
  EXPECT_GT(j, -1.0 / 3) << "initial " << j0;  // reaches about -1e-4
}

// A full buffer of 4 steps x 5 envs from the recurrent model itself, old log-probs shifted by
// `log_prob_shift`.
RolloutBuffer recurrent_buffer(const RecurrentActorCritic& model, float log_prob_shift, Rng& rng) {
  RolloutBuffer buf(4, 5, 2, 1);
  RecurrentState state = model.zero_state(5);
  for (int t = 0; t < 4; ++t) {
    Eigen::MatrixXf obs(2, 5);
    for (Eigen::Index i = 0; i < obs.size(); ++i) obs(i) = static_cast<float>(rng.normal());
    const Eigen::RowVectorXf starts = Eigen::RowVectorXf::Constant(5, t == 0 ? 1.f : 0.f);
    const auto a = model.act(obs, starts, state, rng);
    Eigen::RowVectorXf r(5);
    for (int e = 0; e < 5; ++e) r(e) = static_cast<float>(rng.normal());
    buf.add(obs, a.actions, r, starts, a.values, (a.log_probs.array() + log_prob_shift).matrix());
  }
  buf.compute_returns_and_advantage(Eigen::RowVectorXf::Zero(5), Eigen::RowVectorXf::Ones(5), 0.99, 0.95);
  return buf;
}

// As ppo_update: the minibatch whose approx_kl exceeds 1.5 target_kl is not applied and no later
// one runs; without target_kl every epoch runs every minibatch, the last one partial.
TEST(RecurrentPpoUpdate, KlEarlyStopAndMinibatchesOfWholeSequences) {
  Rng rng(3);
  RecurrentActorCritic model(2, 1, 4, {8}, {8});
  model.init(rng);
  PpoConfig cfg;
  cfg.n_steps = 4;
  cfg.batch_size = 8;  // 2 sequences per minibatch: (2, 2, 1) over 5 envs
  cfg.n_epochs = 3;
  ASSERT_EQ(sequences_per_minibatch(cfg, 5), 2);
  cfg.target_kl = 0.02;
  // Old log-probs 2 nats below: ratio e^2, approx_kl = e^2 - 3 = 4.39 > 0.03.
  const RolloutBuffer shifted = recurrent_buffer(model, -2.0f, rng);
  Adam adam = make_adam(cfg);
  const RecurrentActorCritic before = model;
  const RecurrentState zero = model.zero_state(5);
  PpoStats s = recurrent_ppo_update(model, adam, shifted, zero, cfg, 0, rng);
  EXPECT_TRUE(s.early_stopped);
  EXPECT_EQ(s.epochs_done, 1);
  EXPECT_EQ(s.minibatches_applied, 0);
  EXPECT_NEAR(s.approx_kl, std::exp(2.0) - 3.0, 1e-4);
  EXPECT_EQ(model.actor_gru().params(), before.actor_gru().params());
  EXPECT_EQ(model.critic().params(), before.critic().params());
  EXPECT_EQ(adam.step_count(), 0);

  cfg.target_kl.reset();
  const RolloutBuffer fresh = recurrent_buffer(model, 0.0f, rng);
  s = recurrent_ppo_update(model, adam, fresh, zero, cfg, 0, rng);
  EXPECT_FALSE(s.early_stopped);
  EXPECT_EQ(s.epochs_done, 3);
  EXPECT_EQ(s.minibatches_applied, 9);
  EXPECT_EQ(adam.step_count(), 9);
  EXPECT_FALSE(model.actor_gru().params() == before.actor_gru().params());
  // A wrong number of initial states is refused.
  EXPECT_THROW(recurrent_ppo_update(model, adam, fresh, model.zero_state(4), cfg, 0, rng), std::invalid_argument);
}

// As ppo_update's: actor (GRU + MLP) and critic (GRU + MLP) side by side on a pool of two
// threads give the same parameters and statistics to the bit as one thread.
TEST(RecurrentPpoUpdate, ActorAndCriticSideBySideAreBitIdenticalToOneThread) {
  Rng rng(13);
  RecurrentActorCritic model(2, 1, 6, {16, 12}, {12, 16});
  model.init(rng);
  PpoConfig cfg;
  cfg.n_steps = 4;
  cfg.batch_size = 8;
  cfg.n_epochs = 3;
  cfg.learning_rate = 1e-2;
  const RolloutBuffer buf = recurrent_buffer(model, 0.0f, rng);
  RecurrentActorCritic one = model, two = model;
  Adam adam_1 = make_adam(cfg), adam_2 = make_adam(cfg);
  ThreadPool pool(2);
  for (int update = 0; update < 2; ++update) {
    Rng r1(3 + update), r2(3 + update);
    const PpoStats s1 = recurrent_ppo_update(one, adam_1, buf, one.zero_state(5), cfg, 0, r1, nullptr);
    const PpoStats s2 = recurrent_ppo_update(two, adam_2, buf, two.zero_state(5), cfg, 0, r2, &pool);
    EXPECT_EQ(s1.loss, s2.loss);
    EXPECT_EQ(s1.grad_norm, s2.grad_norm);
    EXPECT_EQ(s1.minibatches_applied, s2.minibatches_applied);
  }
  EXPECT_EQ(one.actor_gru().params(), two.actor_gru().params());
  EXPECT_EQ(one.critic_gru().params(), two.critic_gru().params());
  EXPECT_EQ(one.actor().params(), two.actor().params());
  EXPECT_EQ(one.critic().params(), two.critic().params());
  EXPECT_EQ(one.log_std(), two.log_std());
  EXPECT_NE(two.actor_gru().params(), model.actor_gru().params());
}

// The log-std floor (PpoConfig::log_std_min) holds after every recurrent update step too. One
// step (one epoch, one minibatch of all 5 sequences): the unfloored step takes log_std below 0
// (checked first, so the test can fail), the floored one leaves it at 0 exactly. Five epochs of
// minibatches: never below the floor, and the floor changed the trajectory.
TEST(RecurrentPpoUpdate, LogStdFloorIsKept) {
  Rng rng(5);
  RecurrentActorCritic model(2, 1, 4, {8}, {8});
  model.init(rng);
  const RolloutBuffer buf = recurrent_buffer(model, 0.0f, rng);
  PpoConfig cfg;
  cfg.n_steps = 4;
  cfg.learning_rate = 0.05;
  cfg.ent_coef = 0.0;
  auto run = [&](std::optional<double> floor, int epochs, int batch) {
    RecurrentActorCritic m = model;
    PpoConfig c = cfg;
    c.log_std_min = floor;
    c.n_epochs = epochs;
    c.batch_size = batch;
    Adam adam = make_adam(c);
    Rng r(9);
    recurrent_ppo_update(m, adam, buf, m.zero_state(5), c, 0, r);
    return m;
  };
  ASSERT_LT(run(std::nullopt, 1, 20).log_std().minCoeff(), -0.01f) << "the step must push below the floor";
  EXPECT_EQ(run(0.0, 1, 20).log_std().minCoeff(), 0.0f);
  const RecurrentActorCritic free = run(std::nullopt, 5, 8), floored = run(0.0, 5, 8);
  ASSERT_LT(free.log_std().minCoeff(), -0.01f);
  EXPECT_GE(floored.log_std().minCoeff(), 0.0f);
  EXPECT_NE(floored.actor_gru().params(), free.actor_gru().params());
}

}  // namespace
}  // namespace codesign::rl
