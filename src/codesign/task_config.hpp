#pragma once
// The whisker force-tracking MDP of the paper (§IV-A, §V-A), as a value type with the paper's
// defaults. Where the paper is silent the choice is ours and is marked "(ours)".
#include <numbers>

namespace codesign::coopt {

struct TaskConfig {
  int episode_steps = 250;        // simulation steps per episode (paper)
  int action_hold_steps = 5;      // an action is held for 5 steps -> 50 decisions (paper)
  double theta_max_rad = std::numbers::pi / 18.0;  // Δθ = a·θ_max (paper)
  double target_force_mN = 20.0;  // F_t (ours; set from the default scene's force range)
  double tolerance_fraction = 0.2;  // band ±20 % of F_t (paper)
  double kappa = 1.5;             // raised-cosine exponent (paper)
  double smooth_penalty = 0.05;   // r_smooth = c·|Δθ|/θ_max (spec)
  double flip_penalty = 0.1;      // r_flip when sign(Δθ) flips (spec)
  // The episode ends early when fem::Sensors::theta_extreme is set, i.e. |θ| beyond the scene's
  // fem::SceneConfig::theta_limit_deg ([scene] theta_limit_deg): one limit, stated there.
};

// Which observation the policy sees: the paper's main framework, or its no-feedback baseline
// where strain and morphology are removed from the state.
enum class ObservationSet { Full, NoFeedback };

}  // namespace codesign::coopt
