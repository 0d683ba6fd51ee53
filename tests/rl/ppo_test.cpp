#include "rl/ppo.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include <limits>
#include <utility>

#include "fd_check.hpp"
#include "rl/gaussian.hpp"

namespace codesign::rl {
namespace {

using ModelD = ActorCriticT<double>;
using BatchD = PpoMinibatchT<double>;

void randomise(ModelD& m, Rng& rng, double scale) {
  for (auto* v : {&m.actor().params(), &m.critic().params()})
    for (Eigen::Index i = 0; i < v->size(); ++i) (*v)(i) = scale * rng.normal();
  for (Eigen::Index i = 0; i < m.log_std().size(); ++i) m.log_std()(i) = 0.3 * rng.normal();
}

BatchD random_batch(const ModelD& m, int n, double log_ratio_spread, Rng& rng) {
  BatchD b;
  b.obs.resize(m.critic_input_dim(), n);
  for (Eigen::Index i = 0; i < b.obs.size(); ++i) b.obs(i) = rng.normal();
  const auto act = m.act(b.obs, rng);
  b.actions = act.actions;
  b.old_log_prob = act.log_probs;
  b.advantages.resize(n);
  b.returns.resize(n);
  for (int j = 0; j < n; ++j) {
    b.old_log_prob(j) += log_ratio_spread * rng.normal();
    b.advantages(j) = rng.normal();
    b.returns(j) = rng.normal();
  }
  return b;
}

const PpoLossCoefficients kFdCoefs{0.2, 0.05, 0.6, true};

// The full loss's analytic gradient of every block against finite differences; the loss at the
// unperturbed parameters goes to *loss_out if given. Call under ASSERT_NO_FATAL_FAILURE.
void expect_full_loss_gradient_matches(ModelD& model, const BatchD& batch, PpoLossT<double>* loss_out = nullptr) {
  PpoWorkspaceT<double> ws;
  auto grad = model.zero_grad();
  const auto l = ppo_minibatch_loss<double>(model, batch, kFdCoefs, &grad, ws);
  if (loss_out) *loss_out = l;
  // Both branches of the clipped surrogate must be exercised for the check to mean anything.
  ASSERT_GT(l.clip_fraction, 0.0);
  ASSERT_LT(l.clip_fraction, 1.0);
  auto loss = [&] { return ppo_minibatch_loss<double>(model, batch, kFdCoefs, nullptr, ws).loss; };
  test::expect_gradient_matches(model.actor().params(), loss, grad.actor, "actor");
  test::expect_gradient_matches(model.critic().params(), loss, grad.critic, "critic");
  test::expect_gradient_matches(model.log_std(), loss, grad.log_std, "log_std");
}

TEST(PpoLoss, FullLossGradientMatchesFiniteDifferences) {
  Rng rng(21);
  ModelD model(3, 2, {5, 4}, {6}, 0.0);
  randomise(model, rng, 0.5);
  ASSERT_NO_FATAL_FAILURE(expect_full_loss_gradient_matches(model, random_batch(model, 9, 0.3, rng)));
}

// A privileged critic (asymmetric actor-critic) reads 2 more rows than the actor: the gradient
// of every block still matches finite differences, and the extra rows reach the critic only.
TEST(PpoLoss, PrivilegedCriticGradientMatchesFiniteDifferencesAndTheActorIgnoresTheExtraRows) {
  Rng rng(22);
  ModelD model(3, 2, {5, 4}, {6}, 0.0, 2);
  ASSERT_EQ(model.obs_dim(), 3);
  ASSERT_EQ(model.critic_input_dim(), 5);
  ASSERT_EQ(model.privileged_dim(), 2);
  randomise(model, rng, 0.5);
  const BatchD batch = random_batch(model, 9, 0.3, rng);
  PpoLossT<double> l;
  ASSERT_NO_FATAL_FAILURE(expect_full_loss_gradient_matches(model, batch, &l));
  const PpoLossCoefficients& coefs = kFdCoefs;
  PpoWorkspaceT<double> ws;

  // Changing only the privileged rows: the policy terms are unchanged to the last bit (the actor
  // never reads them), the value loss moves.
  BatchD moved = batch;
  moved.obs.bottomRows(2).array() += 1.0;
  const auto lm = ppo_minibatch_loss<double>(model, moved, coefs, nullptr, ws);
  EXPECT_EQ(lm.pg_loss, l.pg_loss);
  EXPECT_EQ(lm.approx_kl, l.approx_kl);
  EXPECT_NE(lm.value_loss, l.value_loss);
  const ModelD::Mat actor_obs = batch.obs.topRows(3);
  EXPECT_TRUE(model.deterministic_actions(actor_obs) == model.deterministic_actions(ModelD::Mat(moved.obs.topRows(3))));
  // A batch with the actor's rows only is refused (it would silently feed the critic too few).
  BatchD short_batch = batch;
  short_batch.obs = actor_obs;
  EXPECT_THROW(ppo_minibatch_loss<double>(model, short_batch, coefs, nullptr, ws), std::invalid_argument);
}

// One sample whose ratio is set to r; pg loss only.
ActorCriticGradT<double> pg_gradient(double r, double advantage) {
  Rng rng(4);
  ModelD model(2, 1, {4}, {4}, 0.0);
  randomise(model, rng, 0.7);
  BatchD b = random_batch(model, 1, 0.0, rng);
  b.old_log_prob(0) -= std::log(r);  // log_prob - old = log r
  b.advantages(0) = advantage;
  const PpoLossCoefficients coefs{0.2, 0.0, 0.0, false};
  PpoWorkspaceT<double> ws;
  auto grad = model.zero_grad();
  const auto l = ppo_minibatch_loss<double>(model, b, coefs, &grad, ws);
  EXPECT_NEAR(l.pg_loss, -std::min(advantage * r, advantage * std::clamp(r, 0.8, 1.2)), 1e-12);
  return grad;
}

double pg_grad_norm(double r, double a) {
  const auto g = pg_gradient(r, a);
  return std::sqrt(g.actor.squaredNorm() + g.log_std.squaredNorm());
}

TEST(PpoLoss, ClippedSurrogateHasZeroGradientOnlyWhereTheClipBinds) {
  // ratio above 1 + eps: no gradient for A > 0 (no incentive to push further), gradient for A < 0.
  EXPECT_EQ(pg_grad_norm(1.5, +1.0), 0.0);
  EXPECT_GT(pg_grad_norm(1.5, -1.0), 1e-3);
  // ratio below 1 - eps: no gradient for A < 0, gradient for A > 0.
  EXPECT_EQ(pg_grad_norm(0.5, -1.0), 0.0);
  EXPECT_GT(pg_grad_norm(0.5, +1.0), 1e-3);
  // inside the trust region: gradient for both signs.
  EXPECT_GT(pg_grad_norm(1.1, +1.0), 1e-3);
  EXPECT_GT(pg_grad_norm(0.9, -1.0), 1e-3);
}

TEST(PpoLoss, AdvantagesAreNormalisedWithUnbiasedStd) {
  // Two samples, A = (1, 3): mean 2, unbiased std sqrt(2) -> A_hat = (-1/sqrt2, +1/sqrt2)
  // (population std would give -1, +1). Ratios 1.1 and 1.0, both inside the clip range:
  // pg = -mean(A_hat r) = -(-1.1 + 1.0) / (2 sqrt2) = 0.1 / (2 sqrt2) = 0.0353553...
  Rng rng(9);
  ModelD model(2, 1, {3}, {3}, 0.0);
  randomise(model, rng, 0.5);
  BatchD b = random_batch(model, 2, 0.0, rng);
  b.old_log_prob(0) -= std::log(1.1);
  b.advantages << 1.0, 3.0;
  PpoWorkspaceT<double> ws;
  const auto l = ppo_minibatch_loss<double>(model, b, {0.2, 0.0, 0.5, true}, nullptr, ws);
  EXPECT_NEAR(l.pg_loss, 0.1 / (2 * std::sqrt(2.0)) / (1 + 1e-8 / std::sqrt(2.0)), 1e-12);
}

TEST(PpoLoss, ValueLossEntropyAndKlMatchDefinitions) {
  Rng rng(13);
  ModelD model(2, 2, {3}, {3}, 0.0);
  randomise(model, rng, 0.5);
  const BatchD b = random_batch(model, 5, 0.2, rng);
  PpoWorkspaceT<double> ws;
  const PpoLossCoefficients coefs{0.2, 0.03, 0.7, true};
  const auto l = ppo_minibatch_loss<double>(model, b, coefs, nullptr, ws);
  const Eigen::RowVectorXd v = model.value(b.obs);
  const Eigen::RowVectorXd lp =
      gaussian_log_prob<double>(model.deterministic_actions(b.obs), model.log_std(), b.actions);
  const Eigen::RowVectorXd lr = lp - b.old_log_prob;
  EXPECT_NEAR(l.value_loss, (b.returns - v).squaredNorm() / 5, 1e-12);
  EXPECT_NEAR(l.entropy_loss, -gaussian_entropy<double>(model.log_std()), 1e-12);
  EXPECT_NEAR(l.approx_kl, (lr.array().exp() - 1 - lr.array()).mean(), 1e-12);
  EXPECT_NEAR(l.loss, l.pg_loss + 0.03 * l.entropy_loss + 0.7 * l.value_loss, 1e-12);
}

// A full buffer of 5 steps x 2 envs (10 samples) from a small float model with 2 inputs.
RolloutBuffer make_buffer(const ActorCritic& model, float log_prob_shift, Rng& rng) {
  RolloutBuffer buf(5, 2, 2, model.act_dim());
  for (int t = 0; t < 5; ++t) {
    Eigen::MatrixXf obs(2, 2);
    for (Eigen::Index i = 0; i < obs.size(); ++i) obs(i) = static_cast<float>(rng.normal());
    const auto a = model.act(obs, rng);
    Eigen::RowVectorXf r(2);
    r << static_cast<float>(rng.normal()), static_cast<float>(rng.normal());
    buf.add(obs, a.actions, r, Eigen::RowVectorXf::Constant(2, t == 0 ? 1.f : 0.f), a.values,
            (a.log_probs.array() + log_prob_shift).matrix());
  }
  buf.compute_returns_and_advantage(Eigen::RowVectorXf::Zero(2), Eigen::RowVectorXf::Zero(2),
                                    0.99, 0.95);
  return buf;
}

TEST(PpoUpdate, KlEarlyStopSkipsTheOffendingMinibatchAndAllLaterEpochs) {
  Rng rng(1);
  ActorCritic model(2, 1, {8}, {8});
  model.init_orthogonal(rng);
  // Old log-probs 2 nats below the current ones: ratio e^2, approx_kl = e^2 - 3 = 4.39 > 0.03.
  const RolloutBuffer buf = make_buffer(model, -2.0f, rng);
  PpoConfig cfg;
  cfg.batch_size = 4;
  cfg.n_epochs = 10;
  cfg.target_kl = 0.02;
  Adam adam = make_adam(cfg);
  const ActorCritic before = model;
  const PpoStats s = ppo_update(model, adam, buf, cfg, 0, rng);
  EXPECT_TRUE(s.early_stopped);
  EXPECT_EQ(s.epochs_done, 1);
  EXPECT_EQ(s.minibatches_applied, 0);
  EXPECT_NEAR(s.approx_kl, std::exp(2.0) - 3.0, 1e-4);
  EXPECT_EQ(model.actor().params(), before.actor().params());
  EXPECT_EQ(model.critic().params(), before.critic().params());
  EXPECT_EQ(adam.step_count(), 0);
}

TEST(PpoUpdate, WithoutTargetKlRunsAllEpochsIncludingThePartialMinibatch) {
  Rng rng(1);
  ActorCritic model(2, 1, {8}, {8});
  model.init_orthogonal(rng);
  const RolloutBuffer buf = make_buffer(model, -2.0f, rng);
  PpoConfig cfg;
  cfg.batch_size = 4;  // 10 samples -> minibatches of 4, 4, 2
  cfg.n_epochs = 10;
  Adam adam = make_adam(cfg);
  const PpoStats s = ppo_update(model, adam, buf, cfg, 0, rng);
  EXPECT_FALSE(s.early_stopped);
  EXPECT_EQ(s.epochs_done, 10);
  EXPECT_EQ(s.minibatches_applied, 30);
  EXPECT_EQ(adam.step_count(), 30);
}

TEST(PpoUpdate, GradientNormIsGlobalAndClipped) {
  Rng rng(5);
  ActorCritic model(2, 1, {8}, {8});
  model.init_orthogonal(rng);
  const RolloutBuffer buf = make_buffer(model, -0.1f, rng);
  PpoConfig cfg;
  cfg.batch_size = 10;  // one minibatch = the whole buffer, one epoch, one Adam step
  cfg.n_epochs = 1;
  cfg.learning_rate = 1e-3;
  cfg.ent_coef = 0.01;

  // The reported pre-clip norm is the norm over actor, critic AND log_std together. The loss is a
  // mean over samples, so the shuffled order only changes float rounding (relative 1e-5 is
  // ~100 float ulps).
  PpoMinibatchT<float> all{buf.observations(), buf.actions(), buf.log_probs(), buf.advantages(),
                           buf.returns()};
  PpoWorkspaceT<float> ws;
  ActorCriticGrad g = model.zero_grad();
  ppo_minibatch_loss<float>(model, all, {cfg.clip_range, cfg.ent_coef, cfg.vf_coef, true}, &g, ws);
  const double actor2 = g.actor.cast<double>().squaredNorm();
  const double critic2 = g.critic.cast<double>().squaredNorm();
  const double log_std2 = g.log_std.cast<double>().squaredNorm();
  const double full_norm = std::sqrt(actor2 + critic2 + log_std2);
  // log_std must matter at the tolerance used below, or leaving it out would go unnoticed.
  ASSERT_GT(log_std2, 1e-3 * full_norm * full_norm);

  auto max_change = [&](double max_grad_norm, double* reported_norm) {
    ActorCritic m = model;
    PpoConfig c = cfg;
    c.max_grad_norm = max_grad_norm;
    Adam adam = make_adam(c);
    Rng r(1);
    const PpoStats s = ppo_update(m, adam, buf, c, 0, r);
    *reported_norm = s.grad_norm;
    return std::max({(m.actor().params() - model.actor().params()).cwiseAbs().maxCoeff(),
                     (m.critic().params() - model.critic().params()).cwiseAbs().maxCoeff(),
                     (m.log_std() - model.log_std()).cwiseAbs().maxCoeff()});
  };
  double n1 = 0, n2 = 0;
  const double free_step = max_change(1e9, &n1);
  // Clipped to norm 1e-9, every gradient entry is <= 1e-9 << eps = 1e-5, so Adam's first step
  // lr * g / (|g| + eps) is <= lr * 1e-4; unclipped, the largest entry moves by ~lr.
  const double clipped_step = max_change(1e-9, &n2);
  EXPECT_NEAR(n1, full_norm, 1e-5 * full_norm);
  EXPECT_NEAR(n2, full_norm, 1e-5 * full_norm);
  EXPECT_GT(free_step, 0.5 * cfg.learning_rate);
  EXPECT_LT(clipped_step, 1e-4 * cfg.learning_rate * 1.01);
}

// Deferring each Adam step into the next forward pass (the default) must not change a single
// bit: the same arithmetic on the same values, only later. Hidden sizes 64 and 96 put the
// 96 x 64 layer on the fused path (bf16 products, W packed column block by column block right
// after its update); 16 envs x 8 steps = 128 samples in minibatches of 64 (>= 32 columns).
// A full buffer of 8 steps x 16 envs of random observations (`rows` per column) from the model.
RolloutBuffer random_rollout(const ActorCritic& model, int rows, Rng& rng) {
  RolloutBuffer buf(8, 16, rows, 1);
  for (int t = 0; t < 8; ++t) {
    Eigen::MatrixXf obs(rows, 16);
    for (Eigen::Index i = 0; i < obs.size(); ++i) obs(i) = static_cast<float>(rng.normal());
    const auto a = model.act(obs, rng);
    Eigen::RowVectorXf r(16);
    for (Eigen::Index e = 0; e < 16; ++e) r(e) = static_cast<float>(rng.normal());
    buf.add(obs, a.actions, r, Eigen::RowVectorXf::Constant(16, t == 0 ? 1.f : 0.f), a.values, a.log_probs);
  }
  buf.compute_returns_and_advantage(Eigen::RowVectorXf::Zero(16), Eigen::RowVectorXf::Zero(16), 0.99, 0.95);
  return buf;
}

// Two trainings that must have ended in the same state: parameters and Adam moments to the bit.
void expect_same_state(const ActorCritic& a, const Adam& adam_a, const ActorCritic& b, const Adam& adam_b) {
  EXPECT_EQ(a.actor().params(), b.actor().params());
  EXPECT_EQ(a.critic().params(), b.critic().params());
  EXPECT_EQ(a.log_std(), b.log_std());
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(adam_a.first_moment(i), adam_b.first_moment(i));
    EXPECT_EQ(adam_a.second_moment(i), adam_b.second_moment(i));
  }
}

TEST(PpoUpdate, DeferredOptimizerStepIsBitIdenticalToStepping) {
  for (MatmulPrecision p : {MatmulPrecision::Float32, MatmulPrecision::BFloat16}) {
    if (p == MatmulPrecision::BFloat16 && !bf16_gemm_available()) continue;
    Rng rng(21);
    ActorCritic model(6, 1, {64, 96}, {96, 64});
    model.init_orthogonal(rng);
    model.set_matmul_precision(p);
    const RolloutBuffer buf = random_rollout(model, 6, rng);
    PpoConfig cfg;
    cfg.batch_size = 64;
    cfg.n_epochs = 3;
    cfg.learning_rate = 1e-3;
    ActorCritic deferred = model, stepped = model;
    Adam adam_d = make_adam(cfg), adam_s = make_adam(cfg);
    for (int update = 0; update < 2; ++update) {  // two updates: Adam state carries over
      Rng r1(7 + update), r2(7 + update);
      const PpoStats sd = ppo_update(deferred, adam_d, buf, cfg, 0, r1, true);
      const PpoStats ss = ppo_update(stepped, adam_s, buf, cfg, 0, r2, false);
      EXPECT_EQ(sd.minibatches_applied, 6);
      EXPECT_EQ(sd.loss, ss.loss);
      EXPECT_FALSE(adam_d.pending());
    }
    expect_same_state(deferred, adam_d, stepped, adam_s);
    EXPECT_NE(deferred.actor().params(), model.actor().params());  // it did learn something
  }
}

// With a pool of two threads the actor's and the critic's passes run side by side: the same
// operations per network, so the same parameters, Adam moments and statistics to the bit, in
// both product precisions, with the deferred Adam step (whose layer-by-layer application the two
// forward passes then do concurrently) and the privileged critic's wider input.
TEST(PpoUpdate, ActorAndCriticSideBySideAreBitIdenticalToOneThread) {
  for (MatmulPrecision p : {MatmulPrecision::Float32, MatmulPrecision::BFloat16}) {
    if (p == MatmulPrecision::BFloat16 && !bf16_gemm_available()) continue;
    for (int privileged : {0, 3}) {
      SCOPED_TRACE(std::string(p == MatmulPrecision::BFloat16 ? "bf16" : "float32") + ", privileged " +
                   std::to_string(privileged));
      Rng rng(23);
      ActorCritic model(6, 1, {64, 96}, {96, 64}, 0.0f, privileged);
      model.init_orthogonal(rng);
      model.set_matmul_precision(p);
      const RolloutBuffer buf = random_rollout(model, 6 + privileged, rng);
      PpoConfig cfg;
      cfg.batch_size = 64;
      cfg.n_epochs = 3;
      cfg.learning_rate = 1e-3;
      ActorCritic one = model, two = model;
      Adam adam_1 = make_adam(cfg), adam_2 = make_adam(cfg);
      ThreadPool pool(2);
      for (int update = 0; update < 2; ++update) {
        Rng r1(11 + update), r2(11 + update);
        const PpoStats s1 = ppo_update(one, adam_1, buf, cfg, 0, r1, true, nullptr);
        const PpoStats s2 = ppo_update(two, adam_2, buf, cfg, 0, r2, true, &pool);
        EXPECT_EQ(s1.loss, s2.loss);
        EXPECT_EQ(s1.approx_kl, s2.approx_kl);
        EXPECT_EQ(s1.grad_norm, s2.grad_norm);
        EXPECT_EQ(s1.minibatches_applied, s2.minibatches_applied);
      }
      expect_same_state(one, adam_1, two, adam_2);
      EXPECT_NE(two.actor().params(), model.actor().params());  // it did learn something
    }
  }
}

TEST(PpoConfig, EntropyCoefficientDecaysLinearly) {
  const PpoConfig c = paper_ppo_config();
  EXPECT_DOUBLE_EQ(entropy_coef_at(c, 0), 0.01);
  EXPECT_DOUBLE_EQ(entropy_coef_at(c, 220'000), 0.01);
  EXPECT_NEAR(entropy_coef_at(c, 510'000), 0.005, 1e-15);
  EXPECT_DOUBLE_EQ(entropy_coef_at(c, 800'000), 0.0);
  EXPECT_DOUBLE_EQ(entropy_coef_at(c, 1'000'000), 0.0);
  PpoConfig constant;
  constant.ent_coef = 0.02;
  EXPECT_DOUBLE_EQ(entropy_coef_at(constant, 5'000'000), 0.02);
}

TEST(PpoConfig, LearningRateDecaysLinearlyToItsFinalValue) {
  PpoConfig c;
  c.learning_rate = 1e-3;
  EXPECT_DOUBLE_EQ(learning_rate_at(c, 5'000'000), 1e-3);  // no schedule: constant
  c.lr_decay_start = 100;
  c.lr_decay_end = 200;
  c.learning_rate_final = 1e-4;
  EXPECT_DOUBLE_EQ(learning_rate_at(c, 0), 1e-3);
  EXPECT_DOUBLE_EQ(learning_rate_at(c, 100), 1e-3);
  EXPECT_NEAR(learning_rate_at(c, 150), 5.5e-4, 1e-18);
  EXPECT_NEAR(learning_rate_at(c, 175), 3.25e-4, 1e-18);
  EXPECT_DOUBLE_EQ(learning_rate_at(c, 200), 1e-4);
  EXPECT_DOUBLE_EQ(learning_rate_at(c, 10'000), 1e-4);
}

// The update takes its step with the scheduled rate. Adam's first step moves each parameter by
// lr * g / (|g| + eps) (bias-corrected m = g, v = g^2), so one update at half the rate moves every
// parameter by exactly half as much, and a final rate of 0 moves nothing. The moves are measured
// as float differences after - before, each off by up to half an ulp of the parameter, so half
// and full/2 may differ by 0.75 ulp: the bound below is one float epsilon times |parameter|.
TEST(PpoUpdate, StepsWithTheScheduledLearningRate) {
  PpoConfig cfg;
  cfg.batch_size = 10;  // the whole buffer: one minibatch, one Adam step
  cfg.n_epochs = 1;
  cfg.learning_rate = 1e-3;
  cfg.lr_decay_start = 100;
  cfg.lr_decay_end = 200;
  cfg.learning_rate_final = 0.0;
  const auto update_at = [&](std::int64_t t) {
    Rng rng(1);
    ActorCritic model(2, 1, {8}, {8});
    model.init_orthogonal(rng);
    const ActorCritic before = model;
    const RolloutBuffer buf = make_buffer(model, -0.1f, rng);
    Adam adam = make_adam(cfg);
    ppo_update(model, adam, buf, cfg, t, rng);
    return std::pair{Eigen::VectorXd((model.actor().params() - before.actor().params()).cast<double>()),
                     Eigen::VectorXd(before.actor().params().cast<double>())};
  };
  const auto [full, p0] = update_at(50);
  const Eigen::VectorXd half = update_at(150).first, none = update_at(250).first;
  ASSERT_GT(full.cwiseAbs().maxCoeff(), 1e-4);  // the first step moves the largest-gradient weights by ~lr
  const double ulp = std::numeric_limits<float>::epsilon();
  EXPECT_LE(full.cwiseAbs().maxCoeff(), 1e-3 + ulp * p0.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < full.size(); ++i)
    EXPECT_NEAR(half[i], 0.5 * full[i], ulp * std::abs(p0[i]) + 1e-12) << i;
  EXPECT_EQ(none.cwiseAbs().maxCoeff(), 0.0);
}

// The log-std floor (PpoConfig::log_std_min) is a projection after each optimiser step: with a
// large learning rate and no entropy bonus the unfloored update drives some log-std component
// below the floor (checked first, so the test can fail), the floored one leaves every component
// at or above it, in both the deferred and the immediate step; a floor far below changes no bit.
TEST(PpoUpdate, LogStdFloorIsKeptAfterEveryStep) {
  Rng rng(3);
  ActorCritic model(2, 4, {8}, {8});
  model.init_orthogonal(rng);
  const RolloutBuffer buf = make_buffer(model, 0.0f, rng);
  PpoConfig cfg;
  cfg.batch_size = 4;
  cfg.n_epochs = 5;
  cfg.learning_rate = 0.05;
  cfg.ent_coef = 0.0;
  auto run = [&](std::optional<double> floor, bool defer) {
    ActorCritic m = model;
    PpoConfig c = cfg;
    c.log_std_min = floor;
    Adam adam = make_adam(c);
    Rng r(9);
    ppo_update(m, adam, buf, c, 0, r, defer);
    return m;
  };
  const ActorCritic free = run(std::nullopt, true);
  const float floor = 0.0f;  // log_std_init of PpoConfig{}
  ASSERT_LT(free.log_std().minCoeff(), floor - 0.01f) << "the update must push below the floor";
  for (bool defer : {true, false}) {
    const ActorCritic floored = run(0.0, defer);
    EXPECT_GE(floored.log_std().minCoeff(), floor);
    EXPECT_EQ(floored.log_std().minCoeff(), floor);  // the projected component sits at the floor
  }
  const ActorCritic low = run(-20.0, true);  // never reached: the same bits as no floor
  EXPECT_EQ(low.log_std(), free.log_std());
  EXPECT_EQ(low.actor().params(), free.actor().params());
}

TEST(PpoConfig, ValidateRejectsBadValues) {
  PpoConfig c;
  c.batch_size = 0;
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = PpoConfig{};
  c.ent_decay_start = 10;
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = PpoConfig{};
  c.lr_decay_end = 10;  // without its start
  EXPECT_THROW(validate(c), std::invalid_argument);
  c.lr_decay_start = 10;  // start = end
  EXPECT_THROW(validate(c), std::invalid_argument);
  c.lr_decay_start = 5;
  c.learning_rate_final = -1e-4;
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = PpoConfig{};
  c.log_std_init = -3.0;
  c.log_std_min = -2.0;  // above the initial value
  EXPECT_THROW(validate(c), std::invalid_argument);
  c.log_std_min = -3.0;
  EXPECT_NO_THROW(validate(c));
  EXPECT_NO_THROW(validate(paper_ppo_config()));
}

}  // namespace
}  // namespace codesign::rl
