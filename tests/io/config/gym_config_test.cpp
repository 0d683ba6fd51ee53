// The train-gym config reader: the shipped pendulum config, defaults, and validation messages
// (every message names the file, the key and the allowed range).
#include <gtest/gtest.h>

#include <string>

#include "base/errors.hpp"
#include "io/config/gym_config.hpp"
#include "rl/gemm.hpp"

namespace codesign::io {
namespace {

GymTrainConfig parse(const std::string& text) {
  TableReader root = TableReader::from_string(text, "test.toml");
  return read_gym_config(root);
}

// Parses `text` expecting an InputError; returns its message.
std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return {};
}

TEST(GymConfig, ShippedPendulumConfigHasTheIssueSettings) {
  const GymTrainConfig c = load_gym_config(CODESIGN_SOURCE_DIR "/configs/pendulum.toml");
  EXPECT_EQ(c.env_name, "pendulum");
  EXPECT_EQ(c.trainer.n_envs, 4);
  EXPECT_EQ(c.trainer.ppo.n_steps, 1024);
  EXPECT_EQ(c.trainer.ppo.batch_size, 64);
  EXPECT_EQ(c.trainer.ppo.n_epochs, 10);
  EXPECT_DOUBLE_EQ(c.trainer.ppo.gamma, 0.9);
  EXPECT_DOUBLE_EQ(c.trainer.ppo.gae_lambda, 0.95);
  EXPECT_DOUBLE_EQ(c.trainer.ppo.learning_rate, 1e-3);
  EXPECT_DOUBLE_EQ(c.trainer.ppo.clip_range, 0.2);
  EXPECT_DOUBLE_EQ(c.trainer.ppo.ent_coef, 0.0);
  EXPECT_EQ(c.trainer.ppo.actor_hidden, (std::vector<int>{64, 64}));
  EXPECT_EQ(c.trainer.ppo.critic_hidden, (std::vector<int>{64, 64}));
  EXPECT_FALSE(c.trainer.ppo.target_kl.has_value());
  EXPECT_EQ(c.trainer.total_timesteps, 100'000);
  EXPECT_EQ(c.eval_episodes, 100);
  EXPECT_EQ(c.max_episode_steps, 200);
}

TEST(GymConfig, EmptyFileGivesDefaults) {
  const GymTrainConfig c = parse("");
  const GymTrainConfig d;
  const rl::PpoConfig p;
  EXPECT_EQ(c.env_name, "pendulum");
  EXPECT_EQ(c.trainer.n_envs, d.trainer.n_envs);
  EXPECT_EQ(c.trainer.ppo.n_steps, p.n_steps);
  EXPECT_DOUBLE_EQ(c.trainer.ppo.learning_rate, p.learning_rate);
  EXPECT_FALSE(c.trainer.ppo.ent_decay_start.has_value());
  EXPECT_EQ(c.output_dir, d.output_dir);
}

TEST(GymConfig, OptionalPpoFields) {
  const GymTrainConfig c =
      parse("[ppo]\ntarget_kl = 0.02\nent_decay_start = 220000\nent_decay_end = 800000\n");
  ASSERT_TRUE(c.trainer.ppo.target_kl.has_value());
  EXPECT_DOUBLE_EQ(*c.trainer.ppo.target_kl, 0.02);
  EXPECT_EQ(c.trainer.ppo.ent_decay_start.value_or(-1), 220000);
  EXPECT_EQ(c.trainer.ppo.ent_decay_end.value_or(-1), 800000);
}

TEST(GymConfig, ReadPpoConfigLeavesFinishToCaller) {
  TableReader root = TableReader::from_string("[ppo]\ngamma = 0.5\nextra = 3\n", "x.toml");
  TableReader ppo = root.table("ppo");
  rl::PpoConfig defaults;
  defaults.n_epochs = 7;
  const rl::PpoConfig c = read_ppo_config(ppo, defaults);
  EXPECT_DOUBLE_EQ(c.gamma, 0.5);
  EXPECT_EQ(c.n_epochs, 7);  // from the given defaults
  EXPECT_EQ(ppo.integer("extra", 0, 0, 10), 3);  // a caller's own key
  EXPECT_NO_THROW(ppo.finish());
}

TEST(GymConfig, OutOfRangeValueNamesFileKeyAndRange) {
  std::string m = error_of("[ppo]\ngamma = 1.5\n");
  EXPECT_NE(m.find("test.toml"), std::string::npos) << m;
  EXPECT_NE(m.find("ppo.gamma"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;

  m = error_of("[env]\nn_envs = 0\n");
  EXPECT_NE(m.find("test.toml: env.n_envs"), std::string::npos) << m;
  EXPECT_NE(m.find("[1, 4096]"), std::string::npos) << m;

  m = error_of("[ppo]\nactor_hidden = [64, 0]\n");
  EXPECT_NE(m.find("ppo.actor_hidden"), std::string::npos) << m;

  m = error_of("[train]\ntotal_timesteps = -5\n");
  EXPECT_NE(m.find("train.total_timesteps"), std::string::npos) << m;

  m = error_of("[ppo]\nlearning_rate = \"fast\"\n");
  EXPECT_NE(m.find("ppo.learning_rate"), std::string::npos) << m;
}

TEST(GymConfig, UnknownKeysAndTablesAreRejected) {
  std::string m = error_of("[ppo]\nlearnin_rate = 1e-3\n");
  EXPECT_NE(m.find("ppo.learnin_rate"), std::string::npos) << m;
  EXPECT_NE(m.find("learning_rate"), std::string::npos) << m;  // lists the allowed keys
  m = error_of("[trian]\ntotal_timesteps = 5\n");
  EXPECT_NE(m.find("trian"), std::string::npos) << m;
  m = error_of("[env]\nname = \"cartpole\"\n");
  EXPECT_NE(m.find("env.name"), std::string::npos) << m;
  EXPECT_NE(m.find("pendulum"), std::string::npos) << m;
}

TEST(GymConfig, CrossFieldRules) {
  // batch larger than a rollout (n_steps * n_envs = 8 * 2 = 16).
  std::string m = error_of("[env]\nn_envs = 2\n[ppo]\nn_steps = 8\nbatch_size = 17\n");
  EXPECT_NE(m.find("ppo.batch_size"), std::string::npos) << m;
  EXPECT_NE(m.find("16"), std::string::npos) << m;
  EXPECT_NO_THROW(parse("[env]\nn_envs = 2\n[ppo]\nn_steps = 8\nbatch_size = 16\n"));

  m = error_of("[ppo]\nent_decay_start = 100\n");
  EXPECT_NE(m.find("ppo.ent_decay_end"), std::string::npos) << m;
  m = error_of("[ppo]\nent_decay_start = 100\nent_decay_end = 100\n");
  EXPECT_NE(m.find("ppo.ent_decay_end"), std::string::npos) << m;

  m = error_of("[ppo]\nlr_decay_end = 100\n");
  EXPECT_NE(m.find("ppo.lr_decay_start: missing"), std::string::npos) << m;
  m = error_of("[ppo]\nlr_decay_start = 100\nlr_decay_end = 50\n");
  EXPECT_NE(m.find("ppo.lr_decay_end: must be greater than lr_decay_start (100)"), std::string::npos) << m;
  m = error_of("[ppo]\nlearning_rate_final = 0.0001\n");
  EXPECT_NE(m.find("ppo.learning_rate_final: applies only with lr_decay_start and lr_decay_end"), std::string::npos) << m;
  m = error_of("[ppo]\nlr_decay_start = 1\nlr_decay_end = 2\nlearning_rate_final = 2.0\n");
  EXPECT_NE(m.find("ppo.learning_rate_final: value 2 is out of range; allowed [0, 1]"), std::string::npos) << m;

  // The log-std floor must not be above the initial log-std.
  m = error_of("[ppo]\nlog_std_init = -3.0\nlog_std_min = -2.5\n");
  EXPECT_NE(m.find("test.toml"), std::string::npos) << m;
  EXPECT_NE(m.find("ppo.log_std_min: value -2.5 is above log_std_init = -3; allowed: [-20, log_std_init]"),
            std::string::npos) << m;
  m = error_of("[ppo]\nlog_std_min = -21.0\n");
  EXPECT_NE(m.find("ppo.log_std_min"), std::string::npos) << m;
  EXPECT_NO_THROW(parse("[ppo]\nlog_std_init = -3.0\nlog_std_min = -3.0\n"));

  // The gym tasks have no privileged features for a privileged critic.
  m = error_of("[ppo]\nprivileged_critic = true\n");
  EXPECT_NE(m.find("test.toml"), std::string::npos) << m;
  EXPECT_NE(m.find("ppo.privileged_critic"), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: false"), std::string::npos) << m;
  EXPECT_NO_THROW(parse("[ppo]\nprivileged_critic = false\n"));

  // The recurrent policy: train-gym runs it; gru_hidden needs it; unknown kinds are named.
  EXPECT_EQ(parse("[ppo]\npolicy = \"gru\"\ngru_hidden = 16\n").trainer.ppo.gru_hidden, 16);
  m = error_of("[ppo]\ngru_hidden = 32\n");
  EXPECT_NE(m.find("ppo.gru_hidden: applies only with policy = \"gru\""), std::string::npos) << m;
  m = error_of("[ppo]\npolicy = \"lstm\"\n");
  EXPECT_NE(m.find("ppo.policy"), std::string::npos) << m;
  EXPECT_NE(m.find("gru"), std::string::npos) << m;
  EXPECT_NO_THROW(parse("[ppo]\npolicy = \"mlp\"\n"));
}

// ppo.matmul_precision: "auto" (also when absent) resolves to bf16 where the build/CPU has
// AVX-512 BF16, else float32; "float32" and "bf16" are explicit; anything else is an error that
// names the key and the allowed values.
TEST(GymConfig, MatmulPrecisionAbsentOrAutoIsTheBuildDefault) {
  const rl::MatmulPrecision expected = rl::bf16_gemm_available()
                                           ? rl::MatmulPrecision::BFloat16
                                           : rl::MatmulPrecision::Float32;
  EXPECT_EQ(rl::resolve(rl::MatmulChoice::Auto), expected);
  EXPECT_EQ(parse("").trainer.ppo.matmul_precision, expected);
  EXPECT_EQ(parse("[ppo]\ngamma = 0.5\n").trainer.ppo.matmul_precision, expected);
  EXPECT_EQ(parse("[ppo]\nmatmul_precision = \"auto\"\n").trainer.ppo.matmul_precision, expected);
  // "auto" whatever the caller's defaults say (documented in gym_config.hpp).
  for (const auto d : {rl::MatmulPrecision::Float32, rl::MatmulPrecision::BFloat16}) {
    TableReader root = TableReader::from_string("[ppo]\n", "x.toml");
    TableReader ppo = root.table("ppo");
    rl::PpoConfig defaults;
    defaults.matmul_precision = d;
    EXPECT_EQ(read_ppo_config(ppo, defaults).matmul_precision, expected);
  }
}

TEST(GymConfig, MatmulPrecisionExplicitValues) {
  EXPECT_EQ(parse("[ppo]\nmatmul_precision = \"float32\"\n").trainer.ppo.matmul_precision,
            rl::MatmulPrecision::Float32);
  const std::string bf16 = "[ppo]\nmatmul_precision = \"bf16\"\n";
  if (rl::bf16_gemm_available()) {
    EXPECT_EQ(parse(bf16).trainer.ppo.matmul_precision, rl::MatmulPrecision::BFloat16);
  } else {
    const std::string m = error_of(bf16);
    EXPECT_NE(m.find("ppo.matmul_precision"), std::string::npos) << m;
    EXPECT_NE(m.find("float32"), std::string::npos) << m;  // says what is allowed instead
  }
}

TEST(GymConfig, MatmulPrecisionUnknownValueNamesKeyAndAllowedValues) {
  const std::string m = error_of("[ppo]\nmatmul_precision = \"half\"\n");
  EXPECT_NE(m.find("test.toml"), std::string::npos) << m;
  EXPECT_NE(m.find("ppo.matmul_precision"), std::string::npos) << m;
  EXPECT_NE(m.find("half"), std::string::npos) << m;
  for (const char* allowed : {"\"auto\"", "\"float32\"", "\"bf16\""})
    EXPECT_NE(m.find(allowed), std::string::npos) << allowed << " missing from: " << m;
  // A non-string is rejected too, not read as a default.
  const std::string n = error_of("[ppo]\nmatmul_precision = 16\n");
  EXPECT_NE(n.find("ppo.matmul_precision"), std::string::npos) << n;
}

}  // namespace
}  // namespace codesign::io
