#include "core/outer_loop.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "base/seconds_since.hpp"
#include "fem/design.hpp"
#include "core/run_ahead.hpp"
#include "rl/gaussian.hpp"
#include "rl/gru_policy.hpp"
#include "rl/recurrent_ppo.hpp"
#include "rl/rollout.hpp"

namespace codesign::core {

namespace {


const LoopConfig& checked(const LoopConfig& c, const EnvPool* envs) {
  rl::validate(c.ppo);
  if (!envs) throw std::invalid_argument("OuterLoop: no environments");
  const int decisions = c.task.episode_steps / c.task.action_hold_steps;
  if (c.ppo.n_steps != decisions)
    throw std::invalid_argument("OuterLoop: ppo.n_steps (" + std::to_string(c.ppo.n_steps) +
                                ") must equal the decisions per episode (" + std::to_string(decisions) + ")");
  if (static_cast<int>(envs->size()) != c.codesign.designs_per_update)
    throw std::invalid_argument("OuterLoop: one environment per sampled design expected");
  const int extra = static_cast<int>(envs->spec().observation.dim()) - observation_dim(c.task);
  if (extra != (c.ppo.privileged_critic ? kPrivilegedDim : 0))
    throw std::invalid_argument("OuterLoop: the environments' observations have " + std::to_string(extra) +
                                " privileged features; ppo.privileged_critic asks for " +
                                std::to_string(c.ppo.privileged_critic ? kPrivilegedDim : 0));
  return c;
}

}  // namespace

rl::ActorCritic feed_forward_model(const LoopConfig& c, const EnvPool& envs) {
  if (c.ppo.policy != rl::PolicyKind::Mlp) return {};
  rl::ActorCritic m(observation_dim(c.task), static_cast<int>(envs.spec().action.dim()), c.ppo.actor_hidden,
                    c.ppo.critic_hidden, static_cast<float>(c.ppo.log_std_init),
                    c.ppo.privileged_critic ? kPrivilegedDim : 0);
  m.set_matmul_precision(c.ppo.matmul_precision);
  return m;
}

bool whole_rollouts_allowed(const LoopConfig& c) {
  return c.ppo.policy == rl::PolicyKind::Mlp && !c.ppo.normalize_observations;
}

DistributionConfig distribution_config(const CodesignConfig& c, const TaskConfig& task) {
  DistributionConfig d = c.distribution;
  d.pressure_max_kPa = task.pressure_max_kPa;
  return d;
}

DesignSample single_design(const CodesignConfig& c) {
  DesignSample d;
  d.design = c.single_design_index;
  d.pressures_kPa = {c.single_design_p1_kPa, fem::design_from_index(d.design).n >= 2 ? c.single_design_p2_kPa : 0.0};
  return d;
}

std::vector<int> design_chambers() {
  std::vector<int> n(fem::kDesignCount);
  for (int j = 0; j < fem::kDesignCount; ++j) n[j] = fem::design_from_index(j).n;
  return n;
}

OuterLoop::OuterLoop(const LoopConfig& config, std::unique_ptr<EnvPool> envs)
    : config_(checked(config, envs.get())),
      envs_(std::move(envs)),
      model_(feed_forward_model(config_, *envs_)),
      optimizer_(rl::make_adam(config_.ppo)),
      buffer_(config_.ppo.n_steps, static_cast<int>(envs_->size()), static_cast<int>(envs_->spec().observation.dim()),
              static_cast<int>(envs_->spec().action.dim())),
      distribution_(distribution_config(config_.codesign, config_.task), design_chambers()) {
  rl::Rng master(config_.codesign.seed);
  rl::Rng init_rng = master.split();
  act_rng_ = master.split();
  update_rng_ = master.split();
  design_rng_ = master.split();
  if (config_.ppo.policy == rl::PolicyKind::Gru) {
    recurrent_.emplace(observation_dim(config_.task), static_cast<int>(envs_->spec().action.dim()),
                       config_.ppo.gru_hidden, config_.ppo.actor_hidden, config_.ppo.critic_hidden,
                       static_cast<float>(config_.ppo.log_std_init), config_.ppo.privileged_critic ? kPrivilegedDim : 0);
    recurrent_->init(init_rng);
    recurrent_->set_matmul_precision(config_.ppo.matmul_precision);
  } else {
    model_.init_orthogonal(init_rng);
    model_.set_matmul_precision(config_.ppo.matmul_precision);
  }
  if (config_.ppo.normalize_observations)
    obs_stats_.emplace(static_cast<int>(envs_->spec().observation.dim()));
}

std::optional<rl::ObsNormalization> OuterLoop::obs_normalization() const {
  if (!obs_stats_) return std::nullopt;
  rl::ObsNormalization n = obs_stats_->frozen();
  // The policy acts on the actor's rows; privileged features come after them.
  const Eigen::Index actor = recurrent_ ? recurrent_->obs_dim() : model_.obs_dim();
  n.mean = n.mean.head(actor).eval();
  n.var = n.var.head(actor).eval();
  return n;
}

rl::PolicyFileContents OuterLoop::policy_contents() const {
  rl::PolicyFileContents c{model_, obs_normalization()};
  c.recurrent = recurrent_;
  return c;
}

std::vector<DesignSample> OuterLoop::sample_designs(int k, std::vector<EpisodeSetup>& setups) {
  const CodesignConfig& c = config_.codesign;
  std::vector<DesignSample> samples;
  setups.clear();
  for (std::size_t i = 0; i < envs_->size(); ++i) {
    DesignSample d = distribution_.sample(t_, design_rng_);  // always drawn: one RNG stream
    if (c.baseline == Baseline::SingleDesign) d = single_design(c);
    const double u = design_rng_.uniform();
    const double phase = c.random_plate_phase ? 2.0 * std::numbers::pi * u : c.plate_phase_rad;
    setups.push_back({d.design, d.pressures_kPa[0], d.pressures_kPa[1], phase, 0.0,
                      config_.task.faults.fault_for(k, i, envs_->size()),
                      draw_physics(config_.task.randomize, c.seed, k, i)});
    samples.push_back(d);
  }
  return samples;
}

IterationReport OuterLoop::iterate() {
  IterationReport rep;
  rep.k = k_;
  rep.phase = distribution_.phase(t_);
  const auto t_collect = std::chrono::steady_clock::now();
  std::vector<EpisodeSetup> setups;
  if (next_) {
    rep.samples = std::move(next_->samples);
    setups = std::move(next_->setups);
    next_.reset();
  } else {
    rep.samples = sample_designs(k_, setups);
  }
  const auto n = static_cast<Eigen::Index>(envs_->size());
  std::vector<double> running(n, 0.0);
  std::vector<int> length(n, 0);
  std::vector<char> first_done(n, 0);
  const int n_steps = config_.ppo.n_steps;
  // Every rollout starts each column from reset (episode_starts is 1 at step 0), so the recurrent
  // policy's sequences start from a zero state; an episode that ends early (e.g. lost contact)
  // restarts in its column, from a zero state again. Emplaced below, read by `observe`.
  std::optional<rl::GruPolicy> gru;
  // One decision of environment i: its raw reward, whether its episode ended (with the episode's
  // in-band decisions and end reason), in the order of the one-process rollout.
  const auto record = [&](int k, std::size_t i, double reward, bool done, int in_band, const std::string& reason) {
    running[i] += reward;
    length[i] += 1;
    if (!done && k + 1 < n_steps) return;
    EpisodeRecord e;
    e.env = static_cast<int>(i);
    e.setup = setups[i];
    e.episode_return = running[i];
    e.decisions = length[i];
    e.in_band = done ? in_band : -1;
    e.reason = done ? reason : "rollout_end";
    e.first = !first_done[i];
    first_done[i] = 1;
    rep.episodes.push_back(std::move(e));
    running[i] = 0.0;
    length[i] = 0;
  };
  RunAhead* const run_ahead = envs_->run_ahead();
  if (run_ahead && whole_rollouts_allowed(config_)) {
    // The ranks run their environments' whole rollouts (run_ahead.hpp): the policy's draws are
    // taken here first, in the order the step-by-step rollout below takes them.
    std::vector<Eigen::MatrixXd> normals;
    for (int k = 0; k < n_steps; ++k)
      normals.push_back(rl::standard_normals(static_cast<Eigen::Index>(envs_->spec().action.dim()), n, act_rng_));
    const ShareRollout rollout = run_ahead->rollout(setups, model_, normals, config_.ppo.gamma);
    for (int k = 0; k < n_steps; ++k) {
      const RolloutStepColumns& s = rollout.steps[static_cast<std::size_t>(k)];
      for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i)
        record(k, i, s.raw_rewards(static_cast<Eigen::Index>(i)), s.done[i] != 0, s.in_band[i], s.reasons[i]);
    }
    fill_buffer(rollout, config_.ppo.gamma, config_.ppo.gae_lambda, buffer_);
    rep.policy_s = rollout.policy_s;
  } else {
    const rl::RolloutStep step = [this](const Eigen::MatrixXd& actions, bool last) -> const rl::VecStepResult& {
      return envs_->step(actions, !last);
    };
    Eigen::MatrixXd obs = envs_->start(setups);
    Eigen::RowVectorXf episode_starts = Eigen::RowVectorXf::Ones(n);
    const rl::RolloutObserver observe = [&](int k, std::size_t i, const rl::VecStepResult& r) {
      if (i == 0 && gru && memory_observer_)
        memory_observer_(length[0], setups[0].design, gru->state().actor.col(0), gru->state().critic.col(0));
      const bool done = r.done(i);
      record(k, i, r.rewards(static_cast<Eigen::Index>(i)), done, done ? envs_->last_in_band(i) : -1, r.reasons[i]);
    };
    const rl::RolloutOptions options{n_steps, config_.ppo.gamma, config_.ppo.gae_lambda,
                                     obs_stats_ ? &*obs_stats_ : nullptr};
    std::optional<rl::MlpPolicy> mlp;
    rl::RolloutPolicy& policy = recurrent_ ? static_cast<rl::RolloutPolicy&>(gru.emplace(*recurrent_, n))
                                           : static_cast<rl::RolloutPolicy&>(mlp.emplace(model_));
    rep.policy_s = rl::collect_rollout(policy, step, envs_->spec().action, options, obs, episode_starts, buffer_,
                                       act_rng_, observe).policy_s;
  }
  t_ += static_cast<std::int64_t>(n) * config_.ppo.n_steps;
  rep.collect_s = seconds_since(t_collect);

  // Algorithm 2 before the PPO update: it reads the returns alone, and the update does not read
  // the distribution, so the order changes no number.
  const auto t_dist = std::chrono::steady_clock::now();
  rep.returns.assign(static_cast<std::size_t>(n), 0.0);
  for (const EpisodeRecord& e : rep.episodes)
    if (e.first) rep.returns[static_cast<std::size_t>(e.env)] = e.episode_return;
  if (config_.codesign.baseline != Baseline::SingleDesign) distribution_.update(rep.samples, rep.returns, t_);
  rep.distribution_s = seconds_since(t_dist);
  if (run_ahead && whole_rollouts_allowed(config_) && !finished()) {
    // The next iteration's designs, drawn as its iterate() would draw them, started on the ranks
    // during the update below (counted as collection).
    const auto t_next = std::chrono::steady_clock::now();
    NextDesigns next;
    next.rng_before = design_rng_.save();
    next.samples = sample_designs(k_ + 1, next.setups);
    run_ahead->prestart(next.setups);
    next_ = std::move(next);
    rep.collect_s += seconds_since(t_next);
  }

  const auto t_update = std::chrono::steady_clock::now();
  // The rollout's threads are idle now: the update runs the actor and the critic side by side on
  // them (bit-identical to one thread).
  rl::ThreadPool* const pool = envs_->thread_pool();
  rep.ppo = recurrent_ ? rl::recurrent_ppo_update(*recurrent_, optimizer_, buffer_, gru->rollout_start_state(),
                                                  config_.ppo, t_, update_rng_, pool)
                       : rl::ppo_update(model_, optimizer_, buffer_, config_.ppo, t_, update_rng_,
                                        /*defer_optimizer_step=*/true, pool);
  rep.learning_rate = rl::learning_rate_at(config_.ppo, t_);
  rep.update_s = seconds_since(t_update);
  rep.beta = distribution_.beta(t_);
  rep.t = t_;
  ++k_;
  return rep;
}

LoopState OuterLoop::state() const {
  LoopState s;
  s.k = k_;
  s.t = t_;
  if (recurrent_) {
    s.actor = recurrent_->actor().params();
    s.critic = recurrent_->critic().params();
    s.log_std = recurrent_->log_std();
    s.actor_gru = recurrent_->actor_gru().params();
    s.critic_gru = recurrent_->critic_gru().params();
  } else {
    s.actor = model_.actor().params();
    s.critic = model_.critic().params();
    s.log_std = model_.log_std();
  }
  s.adam_steps = optimizer_.step_count();
  for (std::size_t i = 0; i < optimizer_.block_count(); ++i) {
    s.adam_m.push_back(optimizer_.first_moment(i));
    s.adam_v.push_back(optimizer_.second_moment(i));
  }
  s.rng_act = act_rng_.save();
  s.rng_update = update_rng_.save();
  s.rng_design = next_ ? next_->rng_before : design_rng_.save();
  s.distribution = distribution_.state();
  if (obs_stats_) {
    s.obs_mean = obs_stats_->mean;
    s.obs_var = obs_stats_->var;
    s.obs_count = obs_stats_->count;
  }
  return s;
}

void OuterLoop::restore(const LoopState& s) {
  const rl::MlpT<float>& actor = recurrent_ ? recurrent_->actor() : model_.actor();
  const rl::MlpT<float>& critic = recurrent_ ? recurrent_->critic() : model_.critic();
  const Eigen::Index log_std = recurrent_ ? recurrent_->log_std().size() : model_.log_std().size();
  if (s.actor.size() != actor.num_params() || s.critic.size() != critic.num_params() || s.log_std.size() != log_std)
    throw std::invalid_argument("network sizes differ from this config's (" + std::to_string(actor.num_params()) +
                                " actor, " + std::to_string(critic.num_params()) + " critic parameters)");
  const Eigen::Index actor_gru = recurrent_ ? recurrent_->actor_gru().num_params() : 0;
  const Eigen::Index critic_gru = recurrent_ ? recurrent_->critic_gru().num_params() : 0;
  if (s.actor_gru.size() != actor_gru || s.critic_gru.size() != critic_gru)
    throw std::invalid_argument("recurrent layer sizes differ from this config's (" + std::to_string(actor_gru) +
                                " actor and " + std::to_string(critic_gru) + " critic GRU parameters)");
  if (s.k < 0 || s.t < 0) throw std::invalid_argument("negative iteration or timestep count");
  rl::Rng a, u, d;
  if (!a.restore(s.rng_act) || !u.restore(s.rng_update) || !d.restore(s.rng_design))
    throw std::invalid_argument("random generator state unreadable");
  const auto obs_dim = static_cast<Eigen::Index>(envs_->spec().observation.dim());
  if (obs_stats_ && (s.obs_mean.size() != obs_dim || s.obs_var.size() != obs_dim || !(s.obs_count > 0.0) ||
                     !s.obs_mean.allFinite() || !s.obs_var.allFinite() || (s.obs_var.array() < 0.0).any()))
    throw std::invalid_argument("observation statistics missing or unusable (ppo.normalize_observations is on, " +
                                std::to_string(obs_dim) + " components expected)");
  if (!obs_stats_ && s.obs_mean.size() != 0)
    throw std::invalid_argument("observation statistics present but ppo.normalize_observations is off");
  DesignDistribution dist(distribution_config(config_.codesign, config_.task), design_chambers(), s.distribution);
  rl::Adam opt = rl::make_adam(config_.ppo);
  opt.restore(s.adam_steps, s.adam_m, s.adam_v);
  if (!s.adam_m.empty()) {
    const std::vector<rl::AdamBlock<float>> blocks =
        recurrent_ ? recurrent_->adam_blocks(recurrent_->zero_grad()) : model_.adam_blocks(model_.zero_grad());
    bool same = blocks.size() == s.adam_m.size();
    for (std::size_t i = 0; same && i < blocks.size(); ++i) same = blocks[i].size == s.adam_m[i].size();
    if (!same) throw std::invalid_argument("optimiser state does not match the networks");
  }
  if (recurrent_) {
    recurrent_->actor().params() = s.actor;
    recurrent_->critic().params() = s.critic;
    recurrent_->log_std() = s.log_std;
    recurrent_->actor_gru().params() = s.actor_gru;
    recurrent_->critic_gru().params() = s.critic_gru;
  } else {
    model_.actor().params() = s.actor;
    model_.critic().params() = s.critic;
    model_.log_std() = s.log_std;
  }
  optimizer_ = std::move(opt);
  act_rng_ = a;
  update_rng_ = u;
  design_rng_ = d;
  next_.reset();
  distribution_ = std::move(dist);
  if (obs_stats_) {
    obs_stats_->mean = s.obs_mean;
    obs_stats_->var = s.obs_var;
    obs_stats_->count = s.obs_count;
  }
  k_ = s.k;
  t_ = s.t;
}

}  // namespace codesign::core
