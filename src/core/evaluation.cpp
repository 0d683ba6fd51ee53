#include "core/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "rl/rng.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::core {

double evaluation_phase(int k, int n, double offset) { return 2.0 * std::numbers::pi * (k + offset) / n; }

DesignEvaluation evaluate_design(const Controller& controller, const std::shared_ptr<SimulatorPool>& sims,
                                 const TaskConfig& task, EpisodeSetup setup, const EvaluationOptions& options) {
  ControllerFactory make;
  if (controller)
    make = [&controller] {
      return FeedbackController([&controller](const Eigen::VectorXd& obs, const fem::Sensors&) { return controller(obs); });
    };
  return evaluate_feedback(make, sims, task, setup, options);
}

DesignEvaluation evaluate_feedback(const ControllerFactory& make, const std::shared_ptr<SimulatorPool>& sims,
                                   const TaskConfig& task, EpisodeSetup setup, const EvaluationOptions& options) {
  if (options.episodes < 1) throw std::invalid_argument("evaluate_design: episodes must be >= 1");
  const auto n = static_cast<std::size_t>(options.episodes);
  DesignEvaluation out;
  out.returns.assign(n, 0.0);
  out.band_fraction.assign(n, 0.0);
  out.decisions.assign(n, 0);
  out.reasons.assign(n, {});
  rl::ThreadPool pool(options.threads);
  pool.parallel_for(n, [&](std::size_t k) {
    WhiskerEnv env(sims, task);
    EpisodeSetup s = setup;
    s.plate_phase_rad = evaluation_phase(static_cast<int>(k), options.episodes, options.phase_offset);
    // Sensor noise: a stream of its own per episode (the given seed's k-th), so that episodes
    // differ in their noise as well as their phase. No noise, no change.
    if (s.physics.strain_noise > 0.0 || s.physics.encoder_noise_rad > 0.0)
      s.physics.noise_seed = rl::Rng(s.physics.noise_seed + k).split().next_u64();
    env.set_episode(s);
    const FeedbackController controller = make ? make() : FeedbackController();
    env.set_recording(k == 0 && options.trace_first);
    Eigen::VectorXd obs = env.reset(std::nullopt);
    Eigen::VectorXd a(1);
    double ret = 0.0;
    for (;;) {
      a[0] = controller ? controller(obs, env.readings()) : 0.0;
      rl::StepResult r = env.step(a);
      ret += r.reward;
      if (r.done()) {
        out.reasons[k] = r.reason;
        break;
      }
      obs = std::move(r.obs);
    }
    out.returns[k] = ret;
    out.decisions[k] = env.decisions_taken();
    out.band_fraction[k] = static_cast<double>(env.decisions_in_band()) / env.decisions_per_episode();
    if (k == 0 && options.trace_first) out.trace = env.trace();
  });
  out.setup = setup;
  out.setup.plate_phase_rad = evaluation_phase(0, options.episodes, options.phase_offset);
  double sum = 0.0, band = 0.0;
  for (std::size_t k = 0; k < n; ++k) sum += out.returns[k], band += out.band_fraction[k];
  out.mean_return = sum / static_cast<double>(n);
  out.mean_band_fraction = band / static_cast<double>(n);
  double ss = 0.0;
  for (double r : out.returns) ss += (r - out.mean_return) * (r - out.mean_return);
  out.std_return = std::sqrt(ss / static_cast<double>(n));
  return out;
}

FixedThetaResult best_fixed_theta(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                  EpisodeSetup setup, int phases, std::size_t threads, int scan_points,
                                  double tolerance_rad, double phase_offset) {
  if (scan_points < 3) throw std::invalid_argument("best_fixed_theta: scan_points must be >= 3");
  const double lim = sims->scene().theta_limit_deg * std::numbers::pi / 180.0;
  FixedThetaResult best;
  best.evaluation.mean_return = -1e300;
  EvaluationOptions opt;
  opt.episodes = phases;
  opt.threads = threads;
  opt.trace_first = false;
  opt.phase_offset = phase_offset;
  auto value = [&](double th) {
    EpisodeSetup s = setup;
    s.theta0_rad = th;
    DesignEvaluation e = evaluate_design(nullptr, sims, task, s, opt);
    best.evaluations += phases;
    if (e.mean_return > best.evaluation.mean_return) {
      best.evaluation = e;
      best.theta0_rad = th;
    }
    return e.mean_return;
  };
  // Coarse scan (strictly inside the limit, where an episode would end at once).
  const double lo = -0.95 * lim, hi = 0.95 * lim, step = (hi - lo) / (scan_points - 1);
  std::vector<double> v(static_cast<std::size_t>(scan_points));
  for (int i = 0; i < scan_points; ++i) v[static_cast<std::size_t>(i)] = value(lo + i * step);
  const auto im = static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin());
  if (v[static_cast<std::size_t>(im)] <= 0.0) return best;  // nowhere in band: nothing to refine
  // Golden-section search on the bracket around the best scan point.
  double a = lo + std::max(0, im - 1) * step, b = lo + std::min(scan_points - 1, im + 1) * step;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = value(c), fd = value(d);
  while (b - a > tolerance_rad) {
    if (fc >= fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a), fc = value(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a), fd = value(d);
    }
  }
  return best;
}

}  // namespace codesign::core
