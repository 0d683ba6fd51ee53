#include "run/final_result.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "base/duration_text.hpp"
#include "fem/design.hpp"

namespace codesign::run {

ResultFile final_result(const FinalEvaluation& evaluation, const core::LoopConfig& lc, std::int64_t timesteps,
                        std::int64_t iterations, std::int64_t numerical_failures, double wall_s) {
  const core::CodesignConfig& c = lc.codesign;
  ResultFile r;
  r.eval_episodes = c.eval_episodes;
  r.best = result_design(evaluation.best);
  if (evaluation.runner_up) r.runner_up = result_design(*evaluation.runner_up);
  if (const auto& fixed = evaluation.fixed_theta)
    r.fixed_theta = ResultFixedTheta{fixed->theta0_rad, c.fixed_theta_phases, fixed->test.mean_return,
                                     fixed->test.std_return, fixed->test.mean_band_fraction};
  r.run.timesteps = timesteps;
  r.run.iterations = iterations;
  r.run.seed = c.seed;
  r.run.observation = to_string(lc.task.observation);
  r.run.baseline = to_string(c.baseline);
  r.run.numerical_failures = numerical_failures;
  r.run.wall_s = wall_s;
  return r;
}

void print_result(const std::filesystem::path& run_dir, const ResultFile& result, const FinalEvaluation& evaluation) {
  const core::DesignEvaluation& eb = evaluation.best;
  const core::EpisodeSetup& best = eb.setup;
  std::printf("codesign: d* = %s, p* = [%.4g, %.4g] kPa: test return %.2f +- %.2f over %d episodes (band %.0f%%)\n",
              fem::design_label(best.design).c_str(), best.p1_kPa, best.p2_kPa, eb.mean_return, eb.std_return,
              result.eval_episodes, 100.0 * eb.mean_band_fraction);
  if (const auto& fixed = evaluation.fixed_theta)
    std::printf("codesign: d* with the base held at its best fixed angle %.2f deg (no controller): test return %.2f +- %.2f "
                "(band %.0f%%); the policy %s it by %.2f\n",
                fixed->theta0_rad * 180.0 / std::numbers::pi, fixed->test.mean_return, fixed->test.std_return,
                100.0 * fixed->test.mean_band_fraction, eb.mean_return > fixed->test.mean_return ? "beats" : "trails",
                std::abs(eb.mean_return - fixed->test.mean_return));
  if (const auto& er = evaluation.runner_up)
    std::printf("codesign: runner-up %s, p = [%.4g, %.4g] kPa: test return %.2f +- %.2f (band %.0f%%)\n",
                fem::design_label(er->setup.design).c_str(), er->setup.p1_kPa, er->setup.p2_kPa, er->mean_return,
                er->std_return, 100.0 * er->mean_band_fraction);
  if (result.run.numerical_failures > 0)
    std::printf("codesign: %lld training episodes ended by a numerical failure (episodes.csv reason \"numerical: ...\")\n",
                static_cast<long long>(result.run.numerical_failures));
  std::printf("codesign: %lld timesteps in %s -> %s\n", static_cast<long long>(result.run.timesteps),
              duration_text(result.run.wall_s).c_str(), (run_dir / run_file::kResult).string().c_str());
}

}  // namespace codesign::run
