#include "rl/trainer.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

#include "base/seconds_since.hpp"
#include "rl/policy_file.hpp"
#include "rl/recurrent_ppo.hpp"

namespace codesign::rl {

namespace {


AdamConfig adam_config(const PpoConfig& ppo) {
  AdamConfig a;
  a.eps = ppo.adam_eps;
  return a;
}

// Validates before any member is built from the config.
const TrainerConfig& checked(const TrainerConfig& c) {
  validate(c.ppo);
  if (c.n_envs < 1) throw std::invalid_argument("TrainerConfig: n_envs must be >= 1");
  if (c.total_timesteps < 1) throw std::invalid_argument("TrainerConfig: total_timesteps must be >= 1");
  if (c.stats_window < 1) throw std::invalid_argument("TrainerConfig: stats_window must be >= 1");
  return c;
}

}  // namespace

Trainer::Trainer(const EnvFactory& factory, const TrainerConfig& config)
    : config_(checked(config)),
      venv_(factory, static_cast<std::size_t>(config.n_envs), config.seed, config.n_threads),
      model_(static_cast<int>(venv_.spec().observation.dim()),
             static_cast<int>(venv_.spec().action.dim()), config.ppo.actor_hidden,
             config.ppo.critic_hidden, static_cast<float>(config.ppo.log_std_init)),
      optimizer_(adam_config(config.ppo)),
      buffer_(config.ppo.n_steps, config.n_envs, static_cast<int>(venv_.spec().observation.dim()),
              static_cast<int>(venv_.spec().action.dim())),
      start_(std::chrono::steady_clock::now()) {
  Rng master(config_.seed);
  Rng init_rng = master.split();
  act_rng_ = master.split();
  update_rng_ = master.split();
  const int obs_dim = static_cast<int>(venv_.spec().observation.dim());
  if (config_.ppo.policy == PolicyKind::Gru) {
    recurrent_.emplace(obs_dim, static_cast<int>(venv_.spec().action.dim()), config_.ppo.gru_hidden,
                       config_.ppo.actor_hidden, config_.ppo.critic_hidden,
                       static_cast<float>(config_.ppo.log_std_init));
    recurrent_->init(init_rng);
    recurrent_->set_matmul_precision(config_.ppo.matmul_precision);
    gru_.emplace(*recurrent_, config_.n_envs);
  } else {
    model_.init_orthogonal(init_rng);
    model_.set_matmul_precision(config_.ppo.matmul_precision);
  }
  if (config_.ppo.normalize_observations) obs_stats_.emplace(static_cast<int>(venv_.spec().observation.dim()));

  last_obs_ = venv_.reset();
  last_episode_starts_ = Eigen::RowVectorXf::Ones(config_.n_envs);  // SB3: all ones at start
  last_dones_ = Eigen::RowVectorXf::Zero(config_.n_envs);
  running_return_.assign(static_cast<std::size_t>(config_.n_envs), 0.0);
  running_length_.assign(static_cast<std::size_t>(config_.n_envs), 0);
}

void Trainer::collect_rollouts() {
  const auto t0 = std::chrono::steady_clock::now();
  const auto n = static_cast<std::int64_t>(config_.n_envs);
  std::optional<MlpPolicy> mlp;
  RolloutPolicy& policy = gru_ ? static_cast<RolloutPolicy&>(*gru_) : static_cast<RolloutPolicy&>(mlp.emplace(model_));
  const RolloutStep step = [this, n](const Eigen::MatrixXd& actions, bool /*last*/) -> const VecStepResult& {
    num_timesteps_ += n;  // VecEnv restarts finished episodes at once, the last step too
    return venv_.step(actions);
  };
  const RolloutObserver observe = [this](int /*step*/, std::size_t i, const VecStepResult& r) {
    running_return_[i] += r.rewards(static_cast<Eigen::Index>(i));
    running_length_[i] += 1;
    if (!r.done(i)) return;
    recent_.push_back({running_return_[i], running_length_[i], num_timesteps_});
    if (recent_.size() > config_.stats_window) recent_.pop_front();
    ++num_episodes_;
    running_return_[i] = 0.0;
    running_length_[i] = 0;
  };
  const RolloutOptions options{config_.ppo.n_steps, config_.ppo.gamma, config_.ppo.gae_lambda,
                               obs_stats_ ? &*obs_stats_ : nullptr};
  collect_rollout(policy, step, venv_.spec().action, options, last_obs_, last_episode_starts_, buffer_, act_rng_,
                  observe);
  last_dones_ = last_episode_starts_;
  last_collect_s_ = seconds_since(t0);
}

PpoStats Trainer::update() {
  if (recurrent_)
    return recurrent_ppo_update(*recurrent_, optimizer_, buffer_, gru_->rollout_start_state(), config_.ppo,
                                num_timesteps_, update_rng_);
  return ppo_update(model_, optimizer_, buffer_, config_.ppo, num_timesteps_, update_rng_);
}

PolicyFileContents Trainer::policy_contents() const {
  PolicyFileContents c{model_, obs_normalization()};
  c.recurrent = recurrent_;
  return c;
}

TrainProgress Trainer::iterate() {
  collect_rollouts();
  const auto t0 = std::chrono::steady_clock::now();
  TrainProgress p;
  p.stats = update();
  p.update_s = seconds_since(t0);
  p.collect_s = last_collect_s_;
  p.iteration = ++iteration_;
  p.timesteps = num_timesteps_;
  p.total_timesteps = config_.total_timesteps;
  p.elapsed_s = seconds_since(start_);
  p.steps_per_s = p.elapsed_s > 0.0 ? static_cast<double>(num_timesteps_) / p.elapsed_s : 0.0;
  p.episodes = num_episodes_;
  p.mean_return = mean_recent_return();
  if (!recent_.empty()) {
    double len = 0.0;
    for (const EpisodeRecord& e : recent_) len += e.length;
    p.mean_length = len / static_cast<double>(recent_.size());
  }
  return p;
}

void Trainer::learn(const std::function<void(const TrainProgress&)>& on_progress) {
  while (!finished()) {
    const TrainProgress p = iterate();
    if (on_progress) on_progress(p);
  }
}

std::optional<double> Trainer::mean_recent_return() const {
  if (recent_.empty()) return std::nullopt;
  double sum = 0.0;
  for (const EpisodeRecord& e : recent_) sum += e.episode_return;
  return sum / static_cast<double>(recent_.size());
}

std::optional<ObsNormalization> Trainer::obs_normalization() const {
  if (!obs_stats_) return std::nullopt;
  return obs_stats_->frozen();
}

std::uint64_t eval_seed_first(std::uint64_t train_seed, int episodes) {
  if (train_seed > kMaxEvalTrainSeed)
    throw std::invalid_argument("eval_seed_first: training seed " + std::to_string(train_seed) +
                                " is above " + std::to_string(kMaxEvalTrainSeed) +
                                " (2^43 - 1), the largest with disjoint evaluation seeds");
  if (episodes < 1 || static_cast<std::uint64_t>(episodes) > kEvalSeedStride)
    throw std::invalid_argument("eval_seed_first: episodes " + std::to_string(episodes) +
                                " is out of range; allowed [1, 2^20 = " +
                                std::to_string(kEvalSeedStride) + "]");
  return kEvalSeedOffset + train_seed * kEvalSeedStride;
}

namespace {

// The evaluation loop: make_episode() gives the policy of one episode (a fresh one per episode).
EvalResult evaluate_episodes(const std::function<DeterministicPolicy()>& make_episode, const EnvFactory& factory,
                             int episodes, std::uint64_t seed, int max_steps) {
  if (episodes < 1) throw std::invalid_argument("evaluate: episodes must be >= 1");
  std::unique_ptr<Env> env = factory(0);
  const BoxSpec& bounds = env->spec().action;
  EvalResult out;
  for (int k = 0; k < episodes; ++k) {
    const DeterministicPolicy policy = make_episode();
    Eigen::VectorXd obs = env->reset(seed + static_cast<std::uint64_t>(k));
    double ret = 0.0;
    int len = 0;
    for (;;) {
      const Eigen::MatrixXd a = clip_actions(policy(obs), bounds);
      StepResult r = env->step(a.col(0));
      ret += r.reward;
      ++len;
      if (r.done()) break;
      if (len >= max_steps)
        throw std::runtime_error("evaluate: episode exceeded max_steps without ending");
      obs = std::move(r.obs);
    }
    out.returns.push_back(ret);
    out.lengths.push_back(len);
  }
  const double n = static_cast<double>(episodes);
  out.mean_return = std::accumulate(out.returns.begin(), out.returns.end(), 0.0) / n;
  double ss = 0.0;
  for (double r : out.returns) ss += (r - out.mean_return) * (r - out.mean_return);
  out.std_return = std::sqrt(ss / n);
  return out;
}

}  // namespace

EvalResult evaluate(const DeterministicPolicy& policy, const EnvFactory& factory, int episodes,
                    std::uint64_t seed, int max_steps) {
  return evaluate_episodes([&policy] { return policy; }, factory, episodes, seed, max_steps);
}

EvalResult evaluate(const Policy& policy, const EnvFactory& factory, int episodes, std::uint64_t seed,
                    int max_steps) {
  return evaluate_episodes(
      [&policy]() -> DeterministicPolicy {
        auto episode = std::make_shared<Policy::Episode>(policy.begin_episode());
        return [episode](const Eigen::VectorXd& obs) { return episode->act(obs); };
      },
      factory, episodes, seed, max_steps);
}

EvalResult evaluate(const ActorCritic& model, const EnvFactory& factory, int episodes,
                    std::uint64_t seed, int max_steps, const std::optional<ObsNormalization>& obs_norm) {
  // As a policy file's reader acts: the normalised observation, the Gaussian mean.
  const Policy policy(PolicyFileContents{model, obs_norm});
  return evaluate([&policy](const Eigen::VectorXd& obs) { return policy.act_deterministic(obs); }, factory,
                  episodes, seed, max_steps);
}

}  // namespace codesign::rl
