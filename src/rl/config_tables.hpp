#pragma once
// The [ppo] config table, each key described once (base/config_keys.hpp says how the readers,
// the writer, the checks and the reference page use this list). The defaults are
// rl::PpoConfig's (SB3's, for `train-gym`); the co-design reads the table over
// rl::paper_ppo_config() (the paper's Table I).
#include <cstdint>
#include <sstream>
#include <string>

#include "base/config_keys.hpp"
#include "base/enum_names.hpp"
#include "rl/gemm.hpp"
#include "rl/ppo.hpp"

namespace codesign::rl {

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

}  // namespace codesign::rl
