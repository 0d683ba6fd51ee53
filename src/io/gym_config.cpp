#include "io/gym_config.hpp"

#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace codesign::io {

namespace {

constexpr std::int64_t kMaxSteps = 1'000'000'000'000;  // 1e12 timesteps

namespace ppo_range = rl::ppo_range;

// actor_hidden / critic_hidden: layer sizes, layer count in ppo_range::hidden_layers.
std::vector<int> hidden(TableReader& t, std::string_view key, const std::vector<int>& def) {
  const auto v = t.integers(key, std::vector<std::int64_t>(def.begin(), def.end()),
                            ppo_range::hidden_size.lo, ppo_range::hidden_size.hi,
                            static_cast<std::size_t>(ppo_range::hidden_layers.lo),
                            static_cast<std::size_t>(ppo_range::hidden_layers.hi));
  return std::vector<int>(v.begin(), v.end());
}

// A schedule window PREFIX_start < PREFIX_end in timesteps, both or neither: absent keeps the
// caller's values (the defaults), present replaces them.
void read_decay_window(TableReader& t, const std::string& prefix, Range<std::int64_t> range,
                       std::optional<std::int64_t>& start, std::optional<std::int64_t>& end) {
  const std::string ks = prefix + "_start", ke = prefix + "_end";
  if (!t.has(ks) && !t.has(ke)) {
    t.integer(ks, 0, range);  // marks both as read so finish() accepts neither being present
    t.integer(ke, 0, range);
    return;
  }
  if (!t.has(ks) || !t.has(ke))
    t.fail(t.has(ks) ? ke : ks, "missing; " + ks + " and " + ke + " must be given together");
  start = t.integer(ks, 0, range);
  end = t.integer(ke, 0, range);
  if (*end <= *start) t.fail(ke, "must be greater than " + ks + " (" + std::to_string(*start) + ")");
}

}  // namespace

rl::MatmulPrecision default_matmul_precision() {
  return rl::bf16_gemm_available() ? rl::MatmulPrecision::BFloat16
                                   : rl::MatmulPrecision::Float32;
}

rl::MatmulPrecision matmul_precision_from_name(std::string_view name) {
  if (name == "float32") return rl::MatmulPrecision::Float32;
  if (name == "bf16") return rl::MatmulPrecision::BFloat16;
  return default_matmul_precision();
}

rl::PpoConfig read_ppo_config(TableReader& t, const rl::PpoConfig& d) {
  rl::PpoConfig c;
  c.learning_rate = t.number("learning_rate", d.learning_rate, ppo_range::learning_rate);
  c.n_steps = static_cast<int>(t.integer("n_steps", d.n_steps, ppo_range::n_steps));
  c.batch_size = static_cast<int>(t.integer("batch_size", d.batch_size, ppo_range::batch_size));
  c.n_epochs = static_cast<int>(t.integer("n_epochs", d.n_epochs, ppo_range::n_epochs));
  c.gamma = t.number("gamma", d.gamma, ppo_range::gamma);
  c.gae_lambda = t.number("gae_lambda", d.gae_lambda, ppo_range::gae_lambda);
  c.clip_range = t.number("clip_range", d.clip_range, ppo_range::clip_range);
  c.ent_coef = t.number("ent_coef", d.ent_coef, ppo_range::ent_coef);
  c.ent_decay_start = d.ent_decay_start;
  c.ent_decay_end = d.ent_decay_end;
  c.lr_decay_start = d.lr_decay_start;
  c.lr_decay_end = d.lr_decay_end;
  c.learning_rate_final = d.learning_rate_final;
  read_decay_window(t, "ent_decay", ppo_range::ent_decay_timesteps, c.ent_decay_start, c.ent_decay_end);
  read_decay_window(t, "lr_decay", ppo_range::lr_decay_timesteps, c.lr_decay_start, c.lr_decay_end);
  if (c.lr_decay_start) {
    c.learning_rate_final = t.number("learning_rate_final", d.learning_rate_final, ppo_range::learning_rate_final);
  } else {
    if (t.has("learning_rate_final"))
      t.fail("learning_rate_final", "applies only with lr_decay_start and lr_decay_end; give both or drop it");
    t.number("learning_rate_final", 0.0, ppo_range::learning_rate_final);  // marks it read
  }
  c.vf_coef = t.number("vf_coef", d.vf_coef, ppo_range::vf_coef);
  c.max_grad_norm = t.number("max_grad_norm", d.max_grad_norm, ppo_range::max_grad_norm);
  c.target_kl = d.target_kl;
  if (t.has("target_kl")) c.target_kl = t.number("target_kl", 0.0, ppo_range::target_kl);
  else t.number("target_kl", 0.0, ppo_range::target_kl);
  c.normalize_advantage = t.boolean("normalize_advantage", d.normalize_advantage);
  c.normalize_observations = t.boolean("normalize_observations", d.normalize_observations);
  c.privileged_critic = t.boolean("privileged_critic", d.privileged_critic);
  c.policy = t.choice("policy", d.policy, rl::kPolicyKindNames);
  c.gru_hidden = d.gru_hidden;
  if (c.policy == rl::PolicyKind::Gru) {
    c.gru_hidden = static_cast<int>(t.integer("gru_hidden", d.gru_hidden, ppo_range::gru_hidden));
  } else {
    if (t.has("gru_hidden"))
      t.fail("gru_hidden", "applies only with policy = \"gru\"; set policy = \"gru\" or drop it");
    t.integer("gru_hidden", d.gru_hidden, ppo_range::gru_hidden);  // marks it read
  }
  c.actor_hidden = hidden(t, "actor_hidden", d.actor_hidden);
  c.critic_hidden =
      hidden(t, "critic_hidden", d.critic_hidden);
  c.log_std_init = t.number("log_std_init", d.log_std_init, ppo_range::log_std_init);
  c.log_std_min = d.log_std_min;
  if (t.has("log_std_min")) {
    c.log_std_min = t.number("log_std_min", 0.0, ppo_range::log_std_init);
    if (!(c.log_std_init >= *c.log_std_min)) {
      std::ostringstream m;
      m << "value " << *c.log_std_min << " is above log_std_init = " << c.log_std_init << "; allowed: ["
        << ppo_range::log_std_init.lo << ", log_std_init]";
      t.fail("log_std_min", m.str());
    }
  }
  c.adam_eps = t.number("adam_eps", d.adam_eps, ppo_range::adam_eps);
  const std::string precision =
      t.string("matmul_precision", "auto", {"auto", "float32", "bf16"});
  if (precision == "bf16" && !rl::bf16_gemm_available())
    t.fail("matmul_precision", "value \"bf16\" needs AVX-512 BF16, which this build/CPU does "
                               "not have; allowed here: \"auto\", \"float32\"");
  c.matmul_precision = matmul_precision_from_name(precision);
  return c;
}

GymTrainConfig read_gym_config(TableReader& root) {
  GymTrainConfig g;
  const GymTrainConfig d;

  TableReader env = root.table("env");
  g.env_name = env.string("name", d.env_name, {"pendulum"});
  g.trainer.n_envs = static_cast<int>(env.integer("n_envs", d.trainer.n_envs, 1, 4096));
  g.trainer.n_threads = static_cast<std::size_t>(
      env.integer("n_threads", static_cast<std::int64_t>(d.trainer.n_threads), 0, 1024));
  // Seeds up to 2^53 so every seed prints and parses exactly as a double too.
  g.trainer.seed = static_cast<std::uint64_t>(env.integer("seed", 0, 0, 9'007'199'254'740'992));
  g.max_episode_steps =
      static_cast<int>(env.integer("max_episode_steps", d.max_episode_steps, 1, 100'000'000));
  env.finish();

  TableReader ppo = root.table("ppo");
  g.trainer.ppo = read_ppo_config(ppo);
  ppo.finish();
  if (g.trainer.ppo.privileged_critic)
    ppo.fail("privileged_critic", "value true is not allowed here: the gym tasks supply no privileged "
                                  "features (only the whisker co-design does); allowed: false");
  const std::int64_t rollout = static_cast<std::int64_t>(g.trainer.ppo.n_steps) * g.trainer.n_envs;
  if (g.trainer.ppo.batch_size > rollout)
    ppo.fail("batch_size", "value " + std::to_string(g.trainer.ppo.batch_size) +
                               " is out of range; allowed [1, n_steps * env.n_envs = " +
                               std::to_string(rollout) + "]");

  TableReader train = root.table("train");
  g.trainer.total_timesteps =
      train.integer("total_timesteps", d.trainer.total_timesteps, 1, kMaxSteps);
  g.eval_episodes = static_cast<int>(train.integer("eval_episodes", d.eval_episodes, 1, 100'000));
  g.trainer.stats_window = static_cast<std::size_t>(
      train.integer("stats_window", static_cast<std::int64_t>(d.trainer.stats_window), 1,
                    1'000'000));
  g.log_every_iterations =
      static_cast<int>(train.integer("log_every_iterations", d.log_every_iterations, 1, 1'000'000));
  g.checkpoint_every_iterations = static_cast<int>(train.integer(
      "checkpoint_every_iterations", d.checkpoint_every_iterations, 0, 1'000'000));
  g.save_policy = train.boolean("save_policy", d.save_policy);
  g.output_dir = train.string("output_dir", d.output_dir);
  if (g.output_dir.empty()) train.fail("output_dir", "must not be empty");
  train.finish();

  root.finish();
  return g;
}

GymTrainConfig load_gym_config(const std::string& path) {
  TableReader root = TableReader::from_file(path);
  return read_gym_config(root);
}

}  // namespace codesign::io
