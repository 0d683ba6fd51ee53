#pragma once
// The outer co-design loop (Algorithm 1) and the design-distribution update (Algorithm 2),
// as a value type with the paper's defaults. "(ours)" marks choices the paper leaves open.
// The paper's no-feedback baseline is the observation set of [task] (observation =
// "no_feedback"); the single-design baseline is `baseline` here.
#include <cstdint>

#include "base/enum_names.hpp"

namespace codesign::coopt {

enum class Baseline { None, SingleDesign };
inline constexpr EnumNames<Baseline, 2> kBaselineNames{{{Baseline::None, "none"}, {Baseline::SingleDesign, "single_design"}}};
inline const char* to_string(Baseline b) { return name_of(kBaselineNames, b).data(); }

// How β(t) of q_disc = softmax(β R̂) is set from T1 on (docs/codesign.md, "Phases and β"):
//   Ramp     the paper's: linear from beta_start at T1 to beta_end at T2, beta_end after.
//   Entropy  ours, after Schaff et al.: at each t, the β ≥ 0 whose softmax has the entropy of a
//            line from ln n at T1 to entropy_end at T2 (entropy_end after), found by bisection.
enum class BetaSchedule { Ramp, Entropy };
inline constexpr EnumNames<BetaSchedule, 2> kBetaScheduleNames{{{BetaSchedule::Ramp, "ramp"},
                                                                {BetaSchedule::Entropy, "entropy"}}};
inline const char* to_string(BetaSchedule s) { return name_of(kBetaScheduleNames, s).data(); }

// Default target entropy of q_disc at T2 for the entropy schedule: ln 3 nats (perplexity 3, about
// three designs still drawn when the distribution collapses; issue 18 asks for H(q_disc) ≤ ln 3
// at T2). The literal is std::log(3.0) rounded to double (a test checks it).
inline constexpr double kDefaultEntropyEnd = 1.0986122886681098;

struct CodesignConfig {
  std::int64_t total_timesteps = 1'000'000;  // T: decisions over all environments (paper, Table I)
  int designs_per_update = 40;          // ψ: designs sampled (and environments) per iteration (paper)
  std::int64_t exploration_end = 220'000;    // T1 (paper: exploration 0 ≤ t ≤ 220K)
  std::int64_t exploitation_start = 800'000; // T2 (ours: where the entropy decay ends)
  double alpha = 0.1;                   // step of Eq. 7–8 (paper)
  double phi = 0.05;                    // baseline tracking rate of Eq. 9 (paper)
  double beta_start = 0.0;              // β(t) ramps linearly from beta_start at T1 ... (ours)
  double beta_end = 0.5;                // ... to beta_end at T2; β = 0 before T1 (paper)
  BetaSchedule beta_schedule = BetaSchedule::Ramp;  // ramp (paper) or entropy (ours); above
  double entropy_end = kDefaultEntropyEnd;          // entropy schedule: H(q_disc) at T2, nats
                                                    // (allowed [0, ln 110]; unused by the ramp)
  int reward_buffer = 100;              // per-design reward buffer for the running stats (ours)
  double latent_mu0 = 0.0;              // μ_0 in the latent space (ours): p = p_max·sigmoid(z)
  double latent_sigma0 = 1.0;           // Σ_0 = σ_0² I in the latent space (ours)
  double latent_sigma_min = 1e-3;       // eigenvalue floor of Σ after Eq. 8 (ours)
  Baseline baseline = Baseline::None;   // single_design: train on one fixed design (paper)
  int single_design_index = 21;         // design j for Baseline::SingleDesign (paper's d*)
  double single_design_p1_kPa = 0.069;  // paper's p* for j21 (Table III)
  double single_design_p2_kPa = 0.0;
  // Training episodes start at a random plate phase (ours: a policy without a clock must track
  // any phase); false: every episode starts at plate_phase_deg.
  bool random_plate_phase = true;
  double plate_phase_rad = 0.0;
  int eval_episodes = 100;              // final evaluation: episodes (plate phases) per design (ours)
  // The reference the final evaluation prints beside d*'s test return (ours): the best constant
  // base angle on d* at p*, tuned on this many plate phases (never test phases; design_sweep.hpp
  // tune_fixed_theta) and tested on the eval_episodes test phases. 0: not computed.
  int fixed_theta_phases = 10;
  std::int64_t checkpoint_every = 50'000;  // timesteps between checkpoints (ours)
  std::uint64_t seed = 1;
};

}  // namespace codesign::coopt
