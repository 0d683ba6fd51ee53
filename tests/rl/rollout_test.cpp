// The policy seam of the one rollout loop (rl/rollout.hpp): what a policy kind is told and asked
// for, with a scripted policy and scripted environments whose answers are known in advance.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rl/rollout.hpp"

namespace codesign::rl {
namespace {

// Action = +2 (clipped to 1 for the env); V = 10·(first observation component) of the column it
// is asked for; records every episode_starts row and every value_of() environment index.
class ScriptedPolicy final : public RolloutPolicy {
 public:
  void begin_rollout() override { ++rollouts; }
  ActResult act(const Eigen::MatrixXf& obs, const Eigen::RowVectorXf& starts, Rng& /*rng*/) override {
    starts_seen.push_back(starts);
    obs_seen.push_back(obs);
    ActResult r;
    r.actions = Eigen::MatrixXf::Constant(1, obs.cols(), 2.0f);
    r.values = 10.0f * obs.row(0);
    r.log_probs = Eigen::RowVectorXf::Constant(obs.cols(), -1.0f);
    return r;
  }
  float value_of(const Eigen::VectorXf& obs, std::size_t env) override {
    value_envs.push_back(env);
    return 10.0f * obs(0);
  }
  Eigen::RowVectorXf values(const Eigen::MatrixXf& obs) override { return 10.0f * obs.row(0); }

  int rollouts = 0;
  std::vector<Eigen::RowVectorXf> starts_seen;
  std::vector<Eigen::MatrixXf> obs_seen;
  std::vector<std::size_t> value_envs;
};

// Two environments, observation (decision count within the episode); env 0 is truncated after
// 2 decisions, env 1 terminated after 3; each finished episode restarts at once (obs 0) and its
// last observation is the terminal one. Reward 1 per step.
struct ScriptedEnvs {
  std::vector<int> t{0, 0};
  std::vector<double> actions_seen;
  VecStepResult result;
  const VecStepResult& step(const Eigen::MatrixXd& a) {
    result.obs.resize(1, 2);
    result.rewards = Eigen::VectorXd::Ones(2);
    result.terminated.assign(2, 0);
    result.truncated.assign(2, 0);
    result.terminal_obs.assign(2, std::nullopt);
    result.reasons.assign(2, "");
    for (int i = 0; i < 2; ++i) {
      actions_seen.push_back(a(0, i));
      ++t[i];
      const bool end = i == 0 ? t[i] == 2 : t[i] == 3;
      if (end) {
        (i == 0 ? result.truncated : result.terminated)[i] = 1;
        result.terminal_obs[i] = Eigen::VectorXd::Constant(1, t[i]);
        t[i] = 0;
      }
      result.obs(0, i) = t[i];
    }
    return result;
  }
};

TEST(Rollout, PolicyIsToldWhereEpisodesStartAndAskedForTerminalValues) {
  ScriptedPolicy policy;
  ScriptedEnvs envs;
  BoxSpec bounds;
  bounds.low = Eigen::VectorXd::Constant(1, -1.0);
  bounds.high = Eigen::VectorXd::Constant(1, 1.0);
  const RolloutOptions options{6, 0.5, 1.0};
  RolloutBuffer buffer(options.n_steps, 2, 1, 1);
  Eigen::MatrixXd obs = Eigen::MatrixXd::Zero(1, 2);
  Eigen::RowVectorXf starts = Eigen::RowVectorXf::Ones(2);
  Rng rng(1);
  std::vector<int> observed_steps;
  collect_rollout(
      policy, [&](const Eigen::MatrixXd& a, bool) -> const VecStepResult& { return envs.step(a); }, bounds, options, obs,
      starts, buffer, rng, [&](int k, std::size_t, const VecStepResult&) { observed_steps.push_back(k); });

  EXPECT_EQ(policy.rollouts, 1);
  ASSERT_EQ(policy.starts_seen.size(), 6u);
  // Env 0 restarts before decisions 2 and 4 (after 2 steps each), env 1 before decision 3.
  const float want0[6] = {1, 0, 1, 0, 1, 0}, want1[6] = {1, 0, 0, 1, 0, 0};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(policy.starts_seen[k](0), want0[k]) << "decision " << k;
    EXPECT_EQ(policy.starts_seen[k](1), want1[k]) << "decision " << k;
  }
  // Terminal values only for the truncations (env 0 at steps 1, 3, 5), never for termination.
  EXPECT_EQ(policy.value_envs, (std::vector<std::size_t>{0, 0, 0}));
  // The environments got clipped actions; the buffer keeps the unclipped sample.
  for (double a : envs.actions_seen) EXPECT_EQ(a, 1.0);
  EXPECT_EQ(buffer.actions()(0, 0), 2.0f);
  // Rewards: 1, and on a truncation 1 + γ·V(terminal) = 1 + 0.5·10·2 = 11.
  // (The buffer's columns run environment-fastest: column = step·n_envs + env.)
  EXPECT_EQ(buffer.rewards()(1 * 2 + 0), 11.0f);
  EXPECT_EQ(buffer.rewards()(2 * 2 + 1), 1.0f);  // env 1's termination at step 2: no bootstrap
  EXPECT_EQ(buffer.rewards()(0), 1.0f);
  // The observer saw every (step, env) pair, in order.
  EXPECT_EQ(observed_steps, (std::vector<int>{0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5}));
  // On return, the state to continue from: both episodes ended at the last step (env 0 after
  // 2 + 2 + 2 decisions, env 1 after 3 + 3), so both columns start a new episode at obs 0.
  EXPECT_EQ(starts(0), 1.0f);
  EXPECT_EQ(starts(1), 1.0f);
  EXPECT_EQ(obs(0, 0), 0.0);
  EXPECT_EQ(obs(0, 1), 0.0);
}

// With observation statistics, the policy and the buffer see each step's observations after the
// statistics took them in; the environments' own observations (handed back) stay raw.
TEST(Rollout, NormalisedObservationsReachPolicyAndBuffer) {
  ScriptedPolicy policy;
  ScriptedEnvs envs;
  envs.t = {1, 0};  // env 0 starts one decision in, so the first batch is (1, 0)
  BoxSpec bounds;
  bounds.low = Eigen::VectorXd::Constant(1, -1.0);
  bounds.high = Eigen::VectorXd::Constant(1, 1.0);
  RunningObsStats stats(1);
  RolloutOptions options{3, 0.5, 1.0, &stats};
  RolloutBuffer buffer(options.n_steps, 2, 1, 1);
  Eigen::MatrixXd obs(1, 2);
  obs << 1.0, 0.0;
  Eigen::RowVectorXf starts = Eigen::RowVectorXf::Ones(2);
  Rng rng(1);
  collect_rollout(
      policy, [&](const Eigen::MatrixXd& a, bool) -> const VecStepResult& { return envs.step(a); }, bounds, options, obs,
      starts, buffer, rng);
  // After the first batch {1, 0}: count 2 + 1e-4, mean 1/count, var from the pooled moments.
  const double n = 2.0 + 1e-4, m = 1.0 / n;
  const double var = (1e-4 * (1.0 + m * m) + (1.0 - m) * (1.0 - m) + m * m) / n;
  const float z0 = static_cast<float>((1.0 - m) / std::sqrt(var + 1e-8));
  const float z1 = static_cast<float>((0.0 - m) / std::sqrt(var + 1e-8));
  ASSERT_EQ(policy.obs_seen.size(), 3u);
  EXPECT_FLOAT_EQ(policy.obs_seen[0](0, 0), z0);
  EXPECT_FLOAT_EQ(policy.obs_seen[0](0, 1), z1);
  EXPECT_EQ(buffer.observations()(0, 0), policy.obs_seen[0](0, 0));
  EXPECT_EQ(buffer.observations()(0, 1), policy.obs_seen[0](0, 1));
  EXPECT_DOUBLE_EQ(stats.count, 6.0 + 1e-4);  // 3 steps × 2 environments
  // Handed back raw: env 0 was truncated at steps 0 and 2, env 1 terminated at step 2; both
  // restarted at observation 0.
  EXPECT_EQ(obs(0, 0), 0.0);
  EXPECT_EQ(obs(0, 1), 0.0);
  EXPECT_EQ(starts(0), 1.0f);
}

}  // namespace
}  // namespace codesign::rl
