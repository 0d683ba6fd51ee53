// A cheap end-to-end learning check (the Pendulum benchmark is the real proof, run by script).
//
// Task: a contextual bandit. Each episode is one step: observe s ~ U(-1, 1), act a, receive
// r = -(a - s)^2, episode terminates. The optimal deterministic policy a = s earns 0.
// The deterministic evaluation return is J = -mean over a grid of s of (mu(s) - s)^2.
//   * At initialisation mu(s) ~ 0 (head gain 0.01), so J0 ~ -mean(s^2) = -0.34 on the grid.
//   * ANY policy that ignores s has J <= -Var(s) = -0.34: it cannot pass a threshold above that.
// Passing J > -0.34 / 3 therefore proves the learner picked up the state dependence and removed
// at least two thirds of the error a blind policy must make. The threshold is not tuned: it is
// the "explains 2/3 of the variance" line.
#include <cmath>

#include <gtest/gtest.h>

#include "rl/ppo.hpp"

namespace codesign::rl {
namespace {

double deterministic_return(const ActorCritic& model) {
  double sum = 0;
  const int n = 101;
  for (int k = 0; k < n; ++k) {
    const float s = -1.0f + 2.0f * static_cast<float>(k) / (n - 1);
    const float a = model.deterministic_action(Eigen::VectorXf::Constant(1, s))(0);
    sum += -(double(a) - s) * (double(a) - s);
  }
  return sum / n;
}

double blind_policy_bound() {  // -mean(s^2) over the grid: the best any state-blind policy does
  double sum = 0;
  for (int k = 0; k < 101; ++k) {
    const double s = -1.0 + 2.0 * k / 100.0;
    sum += s * s;
  }
  return -sum / 101;
}

void learn_contextual_bandit(int hidden, MatmulPrecision precision) {
  PpoConfig cfg;
  cfg.n_steps = 32;
  cfg.batch_size = 64;
  cfg.n_epochs = 10;
  cfg.learning_rate = 1e-3;
  cfg.actor_hidden = {hidden, hidden};
  cfg.critic_hidden = {hidden, hidden};
  const int n_envs = 8;
  const int iterations = 30;  // 30 x 256 = 7680 environment steps

  Rng rng(12345);
  ActorCritic model(1, 1, cfg.actor_hidden, cfg.critic_hidden);
  model.init_orthogonal(rng);
  model.set_matmul_precision(precision);
  Adam adam = make_adam(cfg);
  RolloutBuffer buffer(cfg.n_steps, n_envs, 1, 1);
  const double j0 = deterministic_return(model);
  const double blind = blind_policy_bound();
  EXPECT_LT(j0, blind / 3);  // the untrained policy must not already pass

  std::int64_t timesteps = 0;
  const Eigen::RowVectorXf ones = Eigen::RowVectorXf::Ones(n_envs);
  for (int it = 0; it < iterations; ++it) {
    buffer.reset();
    for (int t = 0; t < cfg.n_steps; ++t) {
      Eigen::MatrixXf obs(1, n_envs);
      for (int e = 0; e < n_envs; ++e) obs(0, e) = static_cast<float>(2 * rng.uniform() - 1);
      const auto out = model.act(obs, rng);
      const Eigen::RowVectorXf rewards = -(out.actions - obs).array().square().matrix();
      buffer.add(obs, out.actions, rewards, ones, out.values, out.log_probs);
      timesteps += n_envs;
    }
    // Every step terminates: last values are irrelevant (dones = 1).
    buffer.compute_returns_and_advantage(Eigen::RowVectorXf::Zero(n_envs), ones, cfg.gamma,
                                         cfg.gae_lambda);
    ppo_update(model, adam, buffer, cfg, timesteps, rng);
  }
  const double j = deterministic_return(model);
  ::testing::Test::RecordProperty("initial_return", std::to_string(j0));
  ::testing::Test::RecordProperty("final_return", std::to_string(j));
  EXPECT_GT(j, blind / 3) << "initial " << j0 << ", blind-policy bound " << blind;
}

TEST(PpoLearning, ContextualBanditLearnsStateDependentAction) {
  learn_contextual_bandit(32, MatmulPrecision::Float32);
}

// The same with 64-unit layers, where the hidden-to-hidden products of the update (64 x 64,
// minibatch 64) run on the bf16 kernels: forward with the bias/tanh epilogue, weight gradient,
// and the input gradient through the W^T packed by the forward pass.
TEST(PpoLearning, ContextualBanditLearnsWithBf16Products) {
  if (!bf16_gemm_available()) GTEST_SKIP() << "built without AVX-512 BF16";
  learn_contextual_bandit(64, MatmulPrecision::BFloat16);
}

}  // namespace
}  // namespace codesign::rl
