#pragma once
// The paper's hybrid design distribution q_φ (§IV-C, Eq. 5–9) and its update (Algorithm 2), as a
// value type. A design d = (j, p): j is one of the discrete nominal structures, drawn from
// q_disc = softmax(β(t) R̂) (Eq. 5); p ∈ (0, p_max)² are the chamber pressures, drawn as
// p = p_max·sigmoid(z) with z ~ N(μ_j, Σ_j) in a latent space (Eq. 6; Σ_j = L_j L_jᵀ).
// Three phases by the timestep t: Exploration (t < T1), Transition (T1 ≤ t < T2),
// Exploitation (t ≥ T2, collapsed to d*). Semantics and every choice the paper leaves open:
// docs/codesign.md, "Design distribution (Algorithm 2)".
//
//   DesignDistribution q(config, chambers);          // chambers[j] ∈ {1, 2}
//   auto d = q.sample(t, rng);                        // one uniform + two normals, always
//   q.update(samples, returns, t);                    // Algorithm 2, samples in order
//   DesignDistribution resumed(config, chambers, q.state());  // exact restore
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "base/enum_names.hpp"
#include "core/distribution_config.hpp"
#include "rl/rng.hpp"

namespace codesign::core {

enum class Phase { Exploration, Transition, Exploitation };
inline constexpr EnumNames<Phase, 3> kPhaseNames{
    {{Phase::Exploration, "exploration"}, {Phase::Transition, "transition"}, {Phase::Exploitation, "exploitation"}}};
inline const char* to_string(Phase phase) { return name_of(kPhaseNames, phase).data(); }


struct DesignSample {
  int design = 0;                                          // j
  Eigen::Vector2d latent = Eigen::Vector2d::Zero();        // z (z2 carried even when n = 1)
  Eigen::Vector2d pressures_kPa = Eigen::Vector2d::Zero(); // p = p_max·sigmoid(z), p2 = 0 if n = 1
};

// Every number that defines the distribution (public, for checkpoints).
struct DistributionState {
  Eigen::VectorXd score;                    // R̂ per design (init 0)
  Eigen::VectorXd baseline;                 // b per design (init 0)
  std::vector<Eigen::Vector2d> mu;          // latent mean per design (init μ0)
  std::vector<Eigen::Matrix2d> sigma;       // latent covariance per design (init Σ0)
  std::vector<std::vector<double>> buffer;  // last reward_buffer returns per design, oldest first
  std::vector<std::int64_t> samples;        // how many returns each design has received
  bool collapsed = false;                   // d* fixed (Exploitation)
  int best_design = -1;                     // j* once collapsed, else -1
  Eigen::Vector2d best_latent = Eigen::Vector2d::Zero();  // μ_{j*} at the collapse
};

// H(softmax(β·score)) in nats, computed as entropy() computes it (the largest logit subtracted,
// std::exp element by element, zero probabilities contributing 0).
double softmax_entropy(const Eigen::VectorXd& score, double beta);

// The β ≥ 0 with softmax_entropy(score, β) = target, by bisection (H is non-increasing in β ≥ 0:
// dH/dβ = −β·Var_q(score)). Returns 0 when score has one entry, when all entries are equal, or
// when target ≥ ln n. Otherwise the bracket [0, β_cap] is halved until its width is at most
// kBetaRelTolerance times its upper end, which is returned: H(β) ≤ target and
// |β − β_exact| ≤ kBetaRelTolerance·β. β_cap = min(kBetaCapLogit/Δ, kBetaMax), Δ the gap between
// the largest score and the next lower one: from β_cap on every design below the top has a
// weight exp(−β·Δ) that underflows to 0, so q is uniform over the tied maxima and no larger β
// changes it. If even β_cap leaves H above target (the floor ln(number of tied maxima)), β_cap is
// returned; H(q) > target then says so in the logs.
inline constexpr double kBetaRelTolerance = 1e-12;
inline constexpr double kBetaCapLogit = 746.0;  // exp(−746) == 0 in doubles (below ~−745.13)
inline constexpr double kBetaMax = 1e300;       // keeps β·R̂ finite when Δ is denormal-small
double entropy_matching_beta(const Eigen::VectorXd& score, double target);

class DesignDistribution {
 public:
  // chambers[j] = number of chambers (1 or 2) of design j; its size is the number of designs.
  // Throws std::invalid_argument on a bad config, an empty / out-of-range chambers list, or,
  // with the entropy schedule, entropy_end above ln(number of designs).
  DesignDistribution(const DistributionConfig& config, std::vector<int> chambers);
  // Restore from a checkpointed state. Throws std::invalid_argument if the state does not fit
  // (sizes, a buffer longer than reward_buffer, a non-finite number, Σ not symmetric positive
  // definite, non-zero Σ12 for a 1-chamber design, best_design out of range when collapsed).
  DesignDistribution(const DistributionConfig& config, std::vector<int> chambers,
                     DistributionState state);

  Phase phase(std::int64_t t) const;
  // β(t): 0 before T1 under either schedule. Ramp: beta_start → beta_end over [T1, T2), beta_end
  // from T2 on. Entropy: entropy_matching_beta(R̂, target_entropy(t)), recomputed from the current
  // R̂ at every call (stateless: nothing to checkpoint; a restored distribution gives the same β).
  double beta(std::int64_t t) const;
  // The entropy schedule's target H*(t) in nats: ln n before T1, ln n + (t − T1)/(T2 − T1)·
  // (entropy_end − ln n) in the transition, entropy_end from T2 on. nullopt under the ramp.
  std::optional<double> target_entropy(std::int64_t t) const;
  // q_disc = softmax(β(t) R̂) (Eq. 5; the max is subtracted before exp). In Exploitation this is
  // still Eq. 5 at β(t) (beta_end, or the β of entropy_end); sample() ignores it there and
  // returns d*.
  Eigen::VectorXd probabilities(std::int64_t t) const;
  double entropy(std::int64_t t) const;  // of probabilities(t), in nats

  // j ~ q_disc by inverse CDF on one rng.uniform(); ξ = (rng.normal(), rng.normal());
  // z = μ_j + L_j ξ (L_j lower Cholesky factor of Σ_j); p = map(z).
  // Collapsed or t ≥ T2: returns d* = (j*, z*, map(z*)) exactly, after drawing (and ignoring) the
  // same three random values, so the RNG stream does not depend on the phase. If t ≥ T2 but
  // collapse() has not run yet, d* is what collapse() would pick (argmax R̂, its μ).
  DesignSample sample(std::int64_t t, rl::Rng& rng) const;

  // Algorithm 2 for samples[i] with return returns[i], in order. If t ≥ T2 and not yet
  // collapsed, collapse() runs first. Throws std::invalid_argument, leaving the state unchanged,
  // on mismatched sizes, a design index out of range, a non-finite return or latent, or an
  // Eq. 7–8 step that overflows to a non-finite μ or Σ.
  void update(const std::vector<DesignSample>& samples, const std::vector<double>& returns,
              std::int64_t t);

  // Fixes d*: best_design = argmax R̂ (ties: lowest index), best_latent = μ_{best}. Idempotent.
  void collapse();

  // The latent-to-pressure map: p_i = p_max·sigmoid(z_i); p2 = 0 for a 1-chamber design.
  Eigen::Vector2d pressures_kPa(const Eigen::Vector2d& latent, int design) const;
  // map(μ_j): the median of p under q_cont(·|j) (the map is monotone), not its mean.
  Eigen::Vector2d mean_pressures_kPa(int design) const;
  // Delta-method std in kPa: p_max·s(μ_i)(1 − s(μ_i))·sqrt(Σ_ii), s = sigmoid; 0 for p2 if n = 1.
  Eigen::Vector2d sigma_pressures_kPa(int design) const;

  std::vector<int> ranking() const;  // designs by R̂ descending, ties by lower index
  // The design the distribution currently favours: d* once collapsed, else argmax R̂ (ties:
  // lowest index, i.e. ranking().front()).
  int leading_design() const { return state_.collapsed ? state_.best_design : argmax_score(); }
  const DistributionState& state() const { return state_; }
  const DistributionConfig& config() const { return config_; }
  int design_count() const { return static_cast<int>(chambers_.size()); }
  int chambers(int design) const;

 private:
  int argmax_score() const;
  void check_design(int design) const;
  void condition_sigma(int design);  // zero Σ12 if n = 1, symmetrise, eigenvalue floor

  DistributionConfig config_;
  std::vector<int> chambers_;
  DistributionState state_;
};

}  // namespace codesign::core
