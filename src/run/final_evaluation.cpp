#include "run/final_evaluation.hpp"

#include "core/policy_controller.hpp"
#include "run/run_folder.hpp"
#include "run/stop_signals.hpp"

namespace codesign::run {

namespace {

using core::EpisodeSetup;

struct FinalDesigns {
  EpisodeSetup best;
  std::optional<EpisodeSetup> runner_up;
};

FinalDesigns final_designs(const core::DesignDistribution& dist, const core::CodesignConfig& c) {
  FinalDesigns f;
  if (c.baseline == core::Baseline::SingleDesign) {
    const core::DesignSample d = core::single_design(c);
    f.best = {d.design, d.pressures_kPa[0], d.pressures_kPa[1], 0.0, 0.0};
    return f;
  }
  const std::vector<int> rank = dist.ranking();
  const int jb = dist.leading_design();
  const Eigen::Vector2d pb = dist.state().collapsed ? dist.pressures_kPa(dist.state().best_latent, jb)
                                                    : dist.mean_pressures_kPa(jb);
  f.best = {jb, pb[0], pb[1], 0.0, 0.0};
  const int jr = rank[0] == jb ? rank[1] : rank[0];
  const Eigen::Vector2d pr = dist.mean_pressures_kPa(jr);
  f.runner_up = EpisodeSetup{jr, pr[0], pr[1], 0.0, 0.0};
  return f;
}

}  // namespace

FinalEvaluation evaluate_final(const core::DesignDistribution& dist, const core::LoopConfig& lc,
                               const std::shared_ptr<const rl::Policy>& policy,
                               const std::shared_ptr<core::SimulatorPool>& sims, std::size_t threads,
                               const std::filesystem::path& run_dir, RunTelemetry& telemetry, std::int64_t t) {
  const core::CodesignConfig& c = lc.codesign;
  const FinalDesigns designs = final_designs(dist, c);
  // One controller per episode: a recurrent policy's state starts at zero in each.
  const core::ControllerFactory controller = core::policy_factory(policy);
  core::EvaluationOptions options;
  options.episodes = c.eval_episodes;
  options.threads = threads;
  const std::filesystem::path eval_dir = run_dir / run_file::kEvalDir;

  FinalEvaluation result;
  result.best = core::evaluate_feedback(controller, sims, lc.task, designs.best, options);
  write_evaluation(eval_dir, "best", result.best);
  telemetry.publish_trace(result.best, t);
  if ((result.stop_signal = stop_signal()) != 0) return result;

  if (designs.runner_up) {
    result.runner_up = core::evaluate_feedback(controller, sims, lc.task, *designs.runner_up, options);
    write_evaluation(eval_dir, "runner_up", *result.runner_up);
    telemetry.publish_trace(*result.runner_up, t);
  }
  if ((result.stop_signal = stop_signal()) != 0) return result;

  if (c.fixed_theta_phases > 0) {
    result.fixed_theta = core::tune_fixed_theta(sims, lc.task, designs.best, core::FixedThetaConfig{},
                                                c.fixed_theta_phases, c.eval_episodes, threads);
    result.stop_signal = stop_signal();
  }
  return result;
}

}  // namespace codesign::run
