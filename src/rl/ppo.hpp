#pragma once
// One PPO update (the optimisation phase of an iteration), following Stable-Baselines3's
// PPO.train(). Each SB3 semantic followed is listed in docs/rl.md; in short:
//   * n_epochs passes over the buffer; each pass draws a fresh random permutation and cuts it
//     into minibatches of batch_size; the last, partial minibatch is used too.
//   * advantages are normalised PER MINIBATCH: (A - mean) / (std + 1e-8), std unbiased (N-1);
//     skipped for a minibatch of one sample (SB3: `len(advantages) > 1`).
//   * ratio = exp(log_pi - log_pi_old); pg_loss = -mean(min(A r, A clip(r, 1-eps, 1+eps))).
//   * value_loss = mean((returns - V)^2) (no value clipping, clip_range_vf = None).
//   * entropy_loss = -mean(entropy);  loss = pg + ent_coef * entropy_loss + vf_coef * value.
//   * approx_kl = mean((r - 1) - log r), computed before the step of that minibatch; if
//     target_kl is set and approx_kl > 1.5 target_kl, the minibatch is NOT applied and training
//     stops (all remaining epochs skipped).
//   * gradients of actor, critic and log_std are clipped together to global L2 norm
//     max_grad_norm (torch.nn.utils.clip_grad_norm_: factor max / (norm + 1e-6) when < 1),
//     then one Adam step with the current learning rate.
// The entropy coefficient may decay linearly (paper: 0.01 from 220k to 800k steps, then 0).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <sstream>
#include <vector>

#include <Eigen/Core>

#include "base/enum_names.hpp"
#include "base/config_keys.hpp"
#include "base/range.hpp"
#include "rl/ppo_stats.hpp"
#include "rl/actor_critic.hpp"
#include "rl/adam.hpp"
#include "rl/gemm.hpp"
#include "rl/rng.hpp"
#include "rl/rollout_buffer.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::rl {

// The policy network: the feed-forward actor-critic (actor_critic.hpp), or a GRU before each of
// its MLPs (recurrent_actor_critic.hpp, updated by recurrent_ppo.hpp).
enum class PolicyKind { Mlp, Gru };
inline constexpr EnumNames<PolicyKind, 2> kPolicyKindNames{{{PolicyKind::Mlp, "mlp"}, {PolicyKind::Gru, "gru"}}};

// Defaults are SB3's PPO defaults (MlpPolicy net_arch [64, 64]).
struct PpoConfig {
  double learning_rate = 3e-4;
  int n_steps = 2048;  // per environment, per rollout
  int batch_size = 64;
  int n_epochs = 10;
  double gamma = 0.99;
  double gae_lambda = 0.95;
  double clip_range = 0.2;
  // clip_range_vf: None in SB3 by default; not implemented (value loss is never clipped).
  double ent_coef = 0.0;
  // Linear entropy decay: ent_coef until ent_decay_start timesteps, then linearly to 0 at
  // ent_decay_end, 0 afterwards. Disabled (constant ent_coef) unless both are set.
  std::optional<std::int64_t> ent_decay_start;
  std::optional<std::int64_t> ent_decay_end;
  // Linear learning-rate decay (ours; SB3 takes a schedule function): learning_rate until
  // lr_decay_start timesteps, then linearly to learning_rate_final at lr_decay_end, and
  // learning_rate_final afterwards. Disabled (constant learning_rate) unless both are set.
  std::optional<std::int64_t> lr_decay_start;
  std::optional<std::int64_t> lr_decay_end;
  double learning_rate_final = 0.0;
  double vf_coef = 0.5;
  double max_grad_norm = 0.5;
  std::optional<double> target_kl;  // None: no early stop
  bool normalize_advantage = true;
  // Observation normalisation with running statistics (SB3's VecNormalize(norm_obs=True),
  // obs_normalizer.hpp); off by default (the paper's runs do not use it).
  bool normalize_observations = false;
  // Privileged critic (asymmetric actor-critic, ours; off by default): the critic also reads
  // features of the true state that the task's environment supplies during training (the
  // whisker: force error, base angle, plate phase, time in the episode; whisker_env.hpp), the
  // actor never does. Only tasks that supply such features accept it.
  bool privileged_critic = false;
  // Mlp (the default) or Gru: obs -> GRU(gru_hidden) -> the MLPs below, in actor and critic.
  PolicyKind policy = PolicyKind::Mlp;
  int gru_hidden = 64;  // used by PolicyKind::Gru only
  std::vector<int> actor_hidden = {64, 64};
  std::vector<int> critic_hidden = {64, 64};
  double log_std_init = 0.0;
  // Floor of the learned log-std (ours; SB3's DiagGaussian has none): after every optimiser step
  // each component is projected back to at least log_std_min, so the exploration noise cannot
  // shrink below exp(log_std_min). Why: the KL between two Gaussians of equal sigma grows as
  // (change of mean / sigma)^2, and a paper-size co-design whose sigma shrank from 0.018 to 0.006
  // ran into updates with approx_kl 0.5-20 and collapsed (docs/journal/results.md, "Paper-size
  // co-design with our settings"). Unset: no floor.
  // Needs log_std_init >= log_std_min.
  std::optional<double> log_std_min;
  double adam_eps = 1e-5;
  // Arithmetic of the large matrix products of actor and critic (gemm.hpp). BFloat16 rounds the
  // operands of those products to bf16 and keeps float32 sums, parameters, optimiser state and
  // everything else (PyTorch's bf16 autocast does the same); it needs AVX-512 BF16.
  MatmulPrecision matmul_precision = MatmulPrecision::Float32;
};

// The paper's settings (its Table I): lr 0.003, n_steps 50, batch 256, 10 epochs, gamma
// 0.99, lambda 0.95, clip 0.2, ent 0.01 decaying to 0 between 220k and 800k steps, vf 0.6, grad
// clip 0.5, target_kl 0.02, [512, 512, 512] actor and critic.
PpoConfig paper_ppo_config();

// The [ppo] config table, each key described once (base/config_keys.hpp says how the readers,
// the writer, the checks and the reference page use this list). The defaults are PpoConfig's
// (SB3's, for `train-gym`); the co-design reads the table over paper_ppo_config().
// matmul_precision as a file states it: "auto" resolves to bf16 where the CPU and build have
// AVX-512 BF16, else float32.
enum class MatmulChoice { Auto, Float32, BFloat16 };
inline constexpr EnumNames<MatmulChoice, 3> kMatmulChoiceNames{
    {{MatmulChoice::Auto, "auto"}, {MatmulChoice::Float32, "float32"}, {MatmulChoice::BFloat16, "bf16"}}};

inline MatmulPrecision resolve(MatmulChoice c) {
  if (c == MatmulChoice::BFloat16) return MatmulPrecision::BFloat16;
  if (c == MatmulChoice::Float32) return MatmulPrecision::Float32;
  return bf16_gemm_available() ? MatmulPrecision::BFloat16 : MatmulPrecision::Float32;
}

template <class V>
void describe_ppo_table(V& v, PpoConfig& c) {
  constexpr Range<std::int64_t> kTimesteps{0, 1'000'000'000'000};  // 1e12
  constexpr Range<std::int64_t> kHiddenSize{1, 8192};
  constexpr Range<std::size_t> kHiddenLayers{1, 16};
  constexpr Range<double> kLogStd{-20.0, 5.0};
  v.number({"learning_rate", "", "Adam step size (constant, or the start of the lr_decay window)"}, c.learning_rate,
           {1e-9, 1.0});
  v.integer({"n_steps", "", "decisions per environment per rollout (co-design: the decisions per episode)"},
            c.n_steps, {1, 1'000'000});
  v.integer({"batch_size", "", "minibatch size"}, c.batch_size, {1, 100'000'000});
  v.integer({"n_epochs", "", "passes over each rollout"}, c.n_epochs, {1, 10'000});
  v.number({"gamma", "", "discount factor"}, c.gamma, {0.0, 1.0});
  v.number({"gae_lambda", "", "λ of generalised advantage estimation"}, c.gae_lambda, {0.0, 1.0});
  v.number({"clip_range", "", "ε of the clipped surrogate objective"}, c.clip_range, {1e-6, 10.0});
  v.number({"ent_coef", "", "entropy coefficient (constant, or the start of the ent_decay window)"}, c.ent_coef,
           {0.0, 10.0});
  v.window({.name = "ent_decay_start", .unit = "decisions", .meaning = "ent_coef decays linearly to 0 from here",
            .written = config::Written::WhenSet},
           {.name = "ent_decay_end", .unit = "decisions", .meaning = "… reaching 0 here (give both or neither)",
            .written = config::Written::WhenSet},
           c.ent_decay_start, c.ent_decay_end, kTimesteps);
  v.window({.name = "lr_decay_start", .unit = "decisions", .meaning = "learning_rate decays linearly from here",
            .written = config::Written::WhenSet},
           {.name = "lr_decay_end", .unit = "decisions",
            .meaning = "… reaching learning_rate_final here (give both or neither)", .written = config::Written::WhenSet},
           c.lr_decay_start, c.lr_decay_end, kTimesteps);
  v.number({.name = "learning_rate_final", .unit = "", .meaning = "learning rate at the end of the lr_decay window",
            .applies = c.lr_decay_start.has_value(), .applies_with = "lr_decay_start and lr_decay_end",
            .fix = "give both or drop it"},
           c.learning_rate_final, {0.0, 1.0});
  v.number({"vf_coef", "", "weight of the value loss"}, c.vf_coef, {0.0, 1000.0});
  v.number({"max_grad_norm", "", "gradients clipped to this global norm"}, c.max_grad_norm, {1e-9, 1e9});
  v.optional_number({.name = "target_kl", .unit = "",
                     .meaning = "an update's epochs stop once approx_kl exceeds 1.5 × this (unset: never)",
                     .written = config::Written::WhenSet},
                    c.target_kl, {1e-9, 100.0});
  v.boolean({"normalize_advantage", "", "advantages normalised per minibatch"}, c.normalize_advantage);
  v.boolean({.name = "normalize_observations", .unit = "",
             .meaning = "observations normalised by running statistics (SB3's VecNormalize)",
             .written = config::Written::UnlessDefault, .at_default = !c.normalize_observations},
            c.normalize_observations);
  v.boolean({.name = "privileged_critic", .unit = "",
             .meaning = "the critic also reads true-state features in training (co-design only)",
             .written = config::Written::UnlessDefault, .at_default = !c.privileged_critic},
            c.privileged_critic);
  v.choice({.name = "policy", .unit = "", .meaning = "\"mlp\", or \"gru\": a GRU before the actor's and critic's MLPs",
            .written = config::Written::UnlessDefault, .at_default = c.policy == PpoConfig{}.policy},
           c.policy, kPolicyKindNames);
  v.integer({.name = "gru_hidden", .unit = "", .meaning = "units of the GRU", .applies = c.policy == PolicyKind::Gru,
             .applies_with = "policy = \"gru\"", .fix = "set policy = \"gru\" or drop it"},
            c.gru_hidden, {1, 4096});
  v.integers({"actor_hidden", "", "hidden layer sizes of the actor's MLP"}, c.actor_hidden, kHiddenSize,
             kHiddenLayers);
  v.integers({"critic_hidden", "", "hidden layer sizes of the critic's MLP"}, c.critic_hidden, kHiddenSize,
             kHiddenLayers);
  v.number({"log_std_init", "", "initial log standard deviation of the Gaussian policy"}, c.log_std_init, kLogStd);
  v.optional_number({.name = "log_std_min", .unit = "",
                     .meaning = "floor of the learned log standard deviation (unset: none)",
                     .written = config::Written::WhenSet, .range_note = "[-20, log_std_init]"},
                    c.log_std_min, kLogStd);
  v.require(!c.log_std_min || c.log_std_init >= *c.log_std_min, "log_std_min", [&] {
    std::ostringstream m;
    m << "value " << *c.log_std_min << " is above log_std_init = " << c.log_std_init << "; allowed: [" << kLogStd.lo
      << ", log_std_init]";
    return m.str();
  });
  v.number({"adam_eps", "", "ε of Adam"}, c.adam_eps, {1e-20, 1.0});
  // A file states "auto", "float32" or "bf16"; the resolved config the precision used.
  MatmulChoice precision = !V::kStructValues                                  ? MatmulChoice::Auto
                           : c.matmul_precision == MatmulPrecision::BFloat16 ? MatmulChoice::BFloat16
                                                                              : MatmulChoice::Float32;
  v.choice({"matmul_precision", "",
            "arithmetic of the networks' large products: \"float32\", \"bf16\" (AVX-512 BF16) or \"auto\""},
           precision, kMatmulChoiceNames);
  v.require(precision != MatmulChoice::BFloat16 || bf16_gemm_available(), "matmul_precision", [] {
    return std::string("value \"bf16\" needs AVX-512 BF16, which this build/CPU does not have; allowed here: "
                       "\"auto\", \"float32\"");
  });
  c.matmul_precision = resolve(precision);
}

// Entropy coefficient at a given number of collected timesteps.
double entropy_coef_at(const PpoConfig& config, std::int64_t num_timesteps);
// The learning rate of the update after num_timesteps (the lr_decay schedule above).
double learning_rate_at(const PpoConfig& config, std::int64_t num_timesteps);

// Throws std::invalid_argument naming the field if a value is outside its range or breaks a
// rule of the [ppo] description (describe_ppo_table above).
void validate(const PpoConfig& config);

// Projects log_std onto [log_std_min, inf) component by component when the config sets a floor
// (PpoConfig::log_std_min); does nothing otherwise. Called after each optimiser step.
template <class Vec>
void apply_log_std_floor(const PpoConfig& config, Vec& log_std) {
  if (config.log_std_min)
    log_std = log_std.cwiseMax(static_cast<typename Vec::Scalar>(*config.log_std_min));
}

// 1 - Var(y_true - y_pred) / Var(y_true) (population variances, in double); NaN if Var(y_true) = 0.
double explained_variance(const Eigen::RowVectorXf& y_pred, const Eigen::RowVectorXf& y_true);

// The optimiser PPO expects: Adam with eps = config.adam_eps (betas 0.9, 0.999).
inline Adam make_adam(const PpoConfig& config) {
  return Adam(AdamConfig{.beta1 = 0.9, .beta2 = 0.999, .eps = config.adam_eps});
}

// Runs the whole optimisation phase on a full buffer whose advantages/returns are computed.
// With defer_optimizer_step (the default) each Adam step is begun after the gradient and
// applied layer by layer as the next minibatch's forward pass reads the parameters (and after
// the last minibatch); the result is bit-identical to stepping at once (tested), with one pass
// less over the weights in memory.
// With a pool of two or more threads, the actor's and the critic's forward and backward passes of
// each minibatch run side by side (they share no data until the loss, which runs on the caller):
// the same operations in the same order per network, so the result is bit-identical to pool =
// null (tested), in about half the wall time of the networks' passes.
PpoStats ppo_update(ActorCritic& model, Adam& optimizer, const RolloutBuffer& buffer,
                    const PpoConfig& config, std::int64_t num_timesteps, Rng& rng,
                    bool defer_optimizer_step = true, ThreadPool* pool = nullptr);

// ---- The minibatch loss, exposed for gradient checks (templated so tests run in double) ----

template <class S>
struct PpoMinibatchT {
  using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using RowVec = Eigen::Matrix<S, 1, Eigen::Dynamic>;
  Mat obs;              // obs_dim x B
  Mat actions;          // act_dim x B (unclipped, as stored)
  RowVec old_log_prob;  // 1 x B
  RowVec advantages;    // 1 x B (raw; normalised inside if requested)
  RowVec returns;       // 1 x B
};

struct PpoLossCoefficients {
  double clip_range = 0.2;
  double ent_coef = 0.0;
  double vf_coef = 0.5;
  bool normalize_advantage = true;
  // Observation normalisation with running statistics (SB3's VecNormalize(norm_obs=True),
  // obs_normalizer.hpp); off by default (the paper's runs do not use it).
  bool normalize_observations = false;
  // Privileged critic (asymmetric actor-critic, ours; off by default): the critic also reads
  // features of the true state that the task's environment supplies during training (the
  // whisker: force error, base angle, plate phase, time in the episode; whisker_env.hpp), the
  // actor never does. Only tasks that supply such features accept it.
  bool privileged_critic = false;
};

template <class S>
struct PpoLossT {
  S loss = 0, pg_loss = 0, value_loss = 0, entropy_loss = 0;
  S approx_kl = 0;      // mean((r - 1) - log r), no gradient
  S clip_fraction = 0;  // mean(|r - 1| > clip_range)
  double grad_squared_norm = 0;  // squared global L2 norm of the gradient (if one was asked for)
};

// Gradient of the loss w.r.t. what the networks put out: the action means (act_dim x B), the
// values (1 x B) and log_std (act_dim).
template <class S>
struct PpoOutputGradT {
  typename PpoMinibatchT<S>::Mat d_mean, d_value;
  typename PpoMinibatchT<S>::Vec d_log_std;
};

// Scratch reused across minibatches (no allocation in steady state).
template <class S>
struct PpoWorkspaceT {
  typename MlpT<S>::Cache actor_cache, critic_cache;
  PpoOutputGradT<S> outputs;
  // Set by ppo_update between a deferred optimiser step and the next loss evaluation: they apply
  // the step to parameter ranges just before the forward passes read them (MlpT::forward's
  // before_use). Empty: nothing pending.
  typename MlpT<S>::ParamHook actor_pending, critic_pending;
  std::function<void()> log_std_pending;
  // Threads for the actor's and the critic's passes side by side (run_pair); null: one after the
  // other. Not owned.
  ThreadPool* pool = nullptr;
};

// The clipped PPO loss of a minibatch from the policy's outputs on it: action means
// (act_dim x B), values (a 1 x B matrix) and log_std; batch.obs is not read. Every policy kind shares it
// (the feed-forward one below, the recurrent one in recurrent_ppo.hpp). If grad is non-null it
// receives the loss's gradient w.r.t. those outputs.
template <class S>
PpoLossT<S> ppo_loss_from_outputs(const Eigen::Ref<const typename PpoMinibatchT<S>::Mat>& mean_action,
                                  const Eigen::Ref<const typename PpoMinibatchT<S>::Mat>& values,
                                  const Eigen::Ref<const typename PpoMinibatchT<S>::Vec>& log_std,
                                  const PpoMinibatchT<S>& batch, const PpoLossCoefficients& coefs,
                                  PpoOutputGradT<S>* grad);

extern template PpoLossT<float> ppo_loss_from_outputs<float>(
    const Eigen::Ref<const PpoMinibatchT<float>::Mat>&, const Eigen::Ref<const PpoMinibatchT<float>::Mat>&,
    const Eigen::Ref<const PpoMinibatchT<float>::Vec>&, const PpoMinibatchT<float>&, const PpoLossCoefficients&,
    PpoOutputGradT<float>*);
extern template PpoLossT<double> ppo_loss_from_outputs<double>(
    const Eigen::Ref<const PpoMinibatchT<double>::Mat>&, const Eigen::Ref<const PpoMinibatchT<double>::Mat>&,
    const Eigen::Ref<const PpoMinibatchT<double>::Vec>&, const PpoMinibatchT<double>&, const PpoLossCoefficients&,
    PpoOutputGradT<double>*);

// Loss of one minibatch and, if grad is non-null, its gradient w.r.t. all parameters (overwrites
// *grad, which must have the sizes of model.zero_grad()).
template <class S>
PpoLossT<S> ppo_minibatch_loss(const ActorCriticT<S>& model, const PpoMinibatchT<S>& batch,
                               const PpoLossCoefficients& coefs, ActorCriticGradT<S>* grad,
                               PpoWorkspaceT<S>& workspace);

extern template PpoLossT<float> ppo_minibatch_loss<float>(const ActorCriticT<float>&,
                                                          const PpoMinibatchT<float>&,
                                                          const PpoLossCoefficients&,
                                                          ActorCriticGradT<float>*,
                                                          PpoWorkspaceT<float>&);
extern template PpoLossT<double> ppo_minibatch_loss<double>(const ActorCriticT<double>&,
                                                            const PpoMinibatchT<double>&,
                                                            const PpoLossCoefficients&,
                                                            ActorCriticGradT<double>*,
                                                            PpoWorkspaceT<double>&);

}  // namespace codesign::rl
