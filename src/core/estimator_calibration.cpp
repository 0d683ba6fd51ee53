#include "core/estimator_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/evaluation.hpp"
#include "rl/thread_pool.hpp"

namespace codesign::core {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kProbeDeg = 2.0;       // second settle angle of the θ* line
constexpr double kCentreSpreadDeg = 3.0;  // θc spread over θ* ± 1.5°
constexpr double kSwingDeg = 1.0;       // sinusoid amplitude

double settled_force(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task, EpisodeSetup s,
                     double theta0) {
  WhiskerEnv env(sims, task);
  s.theta0_rad = theta0;
  env.set_episode(s);
  env.reset(std::nullopt);
  return env.simulator().sensors().contact_force_mN;
}

void keep(std::vector<ForceSample>& out, const fem::Sensors& s) {
  if (s.contact_force_mN > 0.0) out.push_back({s.axial_strain, s.contact_force_mN, s.theta_rad});
}

}  // namespace

EstimatorCalibration calibrate_force_estimator(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                               const EpisodeSetup& setup, int episodes, int tuning_phases,
                                               std::size_t threads) {
  if (episodes < 1 || tuning_phases < 1)
    throw std::invalid_argument("calibrate_force_estimator: episodes and tuning_phases must be >= 1");
  EstimatorCalibration out;
  out.episodes = episodes;
  // θ*: where the settled force meets F_t, on the line through two settle angles.
  EpisodeSetup first = setup;
  first.plate_phase_rad = evaluation_phase(0, tuning_phases, kTuningPhaseOffset);
  const double f0 = settled_force(sims, task, first, 0.0), f1 = settled_force(sims, task, first, kProbeDeg * kDeg);
  const double half_limit = 0.5 * sims->scene().theta_limit_deg * kDeg;
  out.theta_centre_rad =
      f1 > f0 ? std::clamp(kProbeDeg * kDeg * (task.target_force_mN - f0) / (f1 - f0), -half_limit, half_limit) : 0.0;

  std::vector<std::vector<ForceSample>> per_episode(static_cast<std::size_t>(episodes));
  rl::ThreadPool pool(threads);
  pool.parallel_for(per_episode.size(), [&](std::size_t i) {
    const int ii = static_cast<int>(i);
    WhiskerEnv env(sims, task);
    EpisodeSetup s = setup;
    s.plate_phase_rad = evaluation_phase(ii % tuning_phases, tuning_phases, kTuningPhaseOffset);
    const double centre = out.theta_centre_rad +
                          (episodes == 1 ? 0.0 : kCentreSpreadDeg * kDeg * (static_cast<double>(ii) / (episodes - 1) - 0.5));
    const double sign = ii % 2 == 0 ? 1.0 : -1.0;
    const int k_total = env.decisions_per_episode();
    auto planned = [&](int k) {
      return centre + sign * kSwingDeg * kDeg * std::sin(2.0 * std::numbers::pi * k / k_total);
    };
    s.theta0_rad = planned(0);
    env.set_episode(s);
    env.reset(std::nullopt);
    std::vector<ForceSample>& samples = per_episode[i];
    Eigen::VectorXd a(1);
    for (int k = 0;; ++k) {
      if (k > 0) keep(samples, env.simulator().sensors());  // after decision k − 1's hold
      a[0] = (planned(k + 1) - planned(k)) / task.theta_max_rad;
      const rl::StepResult r = env.step(a);
      if (r.done()) {
        if (r.reason.rfind("numerical", 0) != 0) keep(samples, env.simulator().sensors());
        break;
      }
    }
  });
  std::vector<ForceSample> all;
  for (const auto& v : per_episode) all.insert(all.end(), v.begin(), v.end());
  try {
    out.fit = fit_force_estimator(all);
  } catch (const std::invalid_argument& e) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    out.failure = e.what();
    out.fit.estimator = {nan, nan, nan};
    out.fit.r2 = out.fit.rms_mN = nan;
    out.fit.samples = static_cast<int>(all.size());
  }
  return out;
}

}  // namespace codesign::core
