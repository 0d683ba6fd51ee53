#pragma once
// The settings of the design distribution (Algorithm 2, design_distribution.hpp) as a value
// type, with the β schedule they choose. CodesignConfig holds one ([codesign] keys of the same
// names); DistributionConfig::validate() is the one check of its fields.
#include <cstdint>

#include "base/enum_names.hpp"

namespace codesign::core {

// How β(t) of q_disc = softmax(β R̂) is set from T1 on (docs/codesign.md, "Phases and β"):
//   Ramp     the paper's: linear from beta_start at T1 to beta_end at T2, beta_end after.
//   Entropy  ours, after Schaff et al.: at each t, the β ≥ 0 whose softmax has the entropy of a
//            line from ln n at T1 to entropy_end at T2 (entropy_end after), found by bisection.
enum class BetaSchedule { Ramp, Entropy };
inline constexpr EnumNames<BetaSchedule, 2> kBetaScheduleNames{{{BetaSchedule::Ramp, "ramp"},
                                                                {BetaSchedule::Entropy, "entropy"}}};
inline const char* to_string(BetaSchedule s) { return name_of(kBetaScheduleNames, s).data(); }

// Default target entropy of q_disc at T2 for the entropy schedule: ln 3 nats (perplexity 3, about
// three designs still drawn when the distribution collapses: the co-design should leave
// H(q_disc) ≤ ln 3 at T2; docs/codesign.md, "Phases and β"). The literal is std::log(3.0)
// rounded to double (a test checks it).
inline constexpr double kDefaultEntropyEnd = 1.0986122886681098;

struct DistributionConfig {
  std::int64_t exploration_end = 220'000;     // T1 (paper)
  std::int64_t exploitation_start = 800'000;  // T2 (ours: where the entropy decay ends)
  double alpha = 0.1;             // step of Eq. 7–8 (paper)
  double phi = 0.05;              // baseline tracking rate of Eq. 9 (paper)
  double beta_start = 0.0;        // β ramps linearly from beta_start at T1 to beta_end at T2;
  double beta_end = 0.5;          // β = 0 before T1 (paper), beta_end from T2 on (ours)
  // Ramp: β as above. Entropy: β solved so that H(q_disc) follows a line from ln n at T1 to
  // entropy_end at T2 (entropy_end from T2 on); beta_start and beta_end are then unused, as
  // entropy_end is under the ramp (above, and docs/codesign.md).
  BetaSchedule beta_schedule = BetaSchedule::Ramp;
  double entropy_end = kDefaultEntropyEnd;  // nats; ≤ ln n is checked by the constructor
  int reward_buffer = 100;        // per-design buffer of recent returns for the running stats (ours)
  double pressure_max_kPa = 20.0; // p_i ∈ (0, p_max) (paper: [0, 20] kPa)
  double latent_mu0 = 0.0;        // μ0 in latent space, both components (ours)
  double latent_sigma0 = 1.0;     // Σ0 = σ0² I in latent space (ours)
  double latent_sigma_min = 1e-3; // eigenvalue floor σ_min² of Σ after Eq. 8 (ours: keeps Σ PD)

  // Throws std::invalid_argument naming the first bad field and its allowed range:
  // 0 ≤ T1 < T2; alpha > 0; phi ∈ [0, 1]; beta_start, beta_end ≥ 0; entropy_end ≥ 0 (finite);
  // reward_buffer ≥ 2; pressure_max_kPa > 0; latent_mu0 finite; 0 < latent_sigma_min ≤
  // latent_sigma0. (entropy_end ≤ ln n needs the number of designs: the constructor checks it.)
  void validate() const;
};

}  // namespace codesign::core
