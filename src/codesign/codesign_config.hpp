#pragma once
// The outer co-design loop (Algorithm 1) and the design-distribution update (Algorithm 2),
// as a value type with the paper's defaults. "(ours)" marks choices the paper leaves open.
#include <cstdint>
#include <string>

namespace codesign::coopt {

enum class Baseline { None, NoFeedback, SingleDesign };

struct CodesignConfig {
  std::int64_t total_timesteps = 1'000'000;  // paper, Table I
  int designs_per_update = 40;          // ψ: designs sampled per iteration (paper, Table I)
  int design_batch = 40;                // designs used per distribution update (paper, Table I)
  std::int64_t exploration_end = 220'000;    // T1 (paper: exploration 0 ≤ t ≤ 220K)
  std::int64_t exploitation_start = 800'000; // T2 (ours: where the entropy decay ends)
  double alpha = 0.1;                   // step of Eq. 7–8 (paper)
  double phi = 0.05;                    // baseline tracking rate of Eq. 9 (paper)
  double beta_start = 0.0;              // β(t) ramps linearly from beta_start at T1 ... (ours)
  double beta_end = 0.5;                // ... to beta_end at T2; β = 0 before T1 (paper)
  int reward_buffer = 100;              // per-design reward buffer for the running stats (ours)
  double pressure_max_kPa = 20.0;       // p_i ∈ [0, 20] kPa (paper)
  double latent_mu0 = 0.0;              // μ_0 in the latent space (ours): p = p_max·sigmoid(z)
  double latent_sigma0 = 1.0;           // Σ_0 = σ_0² I in the latent space (ours)
  Baseline baseline = Baseline::None;   // paper's baselines as switches
  int single_design_index = 21;         // design j for Baseline::SingleDesign (paper's d*)
  double single_design_p1_kPa = 0.069;  // paper's p* for j21 (Table III)
  double single_design_p2_kPa = 0.0;
  int eval_decisions = 50;              // final evaluation over 50 test decisions (paper)
  std::int64_t checkpoint_every = 50'000;  // timesteps between checkpoints (ours)
  std::uint64_t seed = 1;
};

}  // namespace codesign::coopt
