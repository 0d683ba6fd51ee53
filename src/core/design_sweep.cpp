#include "core/design_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "base/errors.hpp"
#include "fem/design.hpp"

namespace codesign::core {

void FixedThetaConfig::validate() const {
  if (scan_points < 3) throw std::invalid_argument("sweep: fixed_theta_scan_points must be >= 3");
  if (max_evals < 1) throw std::invalid_argument("sweep: fixed_theta_max_evals must be >= 1");
}

FixedThetaTuning tune_fixed_theta(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                  const EpisodeSetup& setup, const FixedThetaConfig& config, int tuning_phases,
                                  int test_episodes, std::size_t threads) {
  config.validate();
  const double lim = sims->scene().theta_limit_deg * std::numbers::pi / 180.0;
  EvaluationOptions tuning;
  tuning.episodes = tuning_phases;
  tuning.phase_offset = kTuningPhaseOffset;
  tuning.threads = threads;
  tuning.trace_first = false;
  FixedThetaTuning out;
  auto value = [&](double th) {
    EpisodeSetup s = setup;
    s.theta0_rad = th;
    ++out.evaluations;
    return evaluate_design(nullptr, sims, task, s, tuning).mean_return;
  };
  const double lo = -0.95 * lim, hi = 0.95 * lim, step = (hi - lo) / (config.scan_points - 1);
  double best_th = 0.0, best_v = -HUGE_VAL;
  for (int i = 0; i < config.scan_points; ++i) {
    const double th = lo + i * step, v = value(th);
    if (v > best_v) best_v = v, best_th = th;
  }
  SearchOptions so;
  so.method = LocalMethod::Cobyla;
  so.starts = 1;
  so.max_evals = config.max_evals;
  so.xtol_rel = 1e-3;
  so.ftol_abs = 1e-4;
  const SearchBox box{{std::max(lo, best_th - step)}, {std::min(hi, best_th + step)}};
  const SearchResult r = maximise([&](const std::vector<double>& x) { return value(x[0]); }, box, so,
                                  std::vector<double>{best_th});
  if (r.value > best_v) best_v = r.value, best_th = r.x[0];
  out.theta0_rad = best_th;
  out.tuning_return = best_v;
  EvaluationOptions test;
  test.episodes = test_episodes;
  test.threads = threads;
  EpisodeSetup s = setup;
  s.theta0_rad = best_th;
  out.test = evaluate_design(nullptr, sims, task, s, test);
  return out;
}

namespace {

PidSignal signal_of(SweepController c) {
  return c == SweepController::PidForce ? PidSignal::Force
         : c == SweepController::PidStrain ? PidSignal::Strain
                                           : PidSignal::Estimate;
}

}  // namespace

SweepController sweep_controller_from_name(const std::string& name) {
  if (const std::optional<SweepController> c = value_of(kSweepControllerNames, name)) return *c;
  throw std::invalid_argument("unknown sweep controller '" + name + "'; allowed: " + names_list(kSweepControllerNames));
}

void SweepConfig::validate() const {
  if (pressures_kPa.empty()) throw std::invalid_argument("sweep: pressures_kPa must not be empty");
  for (double p : pressures_kPa)
    if (!(p >= 0.0 && std::isfinite(p))) throw std::invalid_argument("sweep: pressures must be finite and >= 0");
  if (controllers.empty()) throw std::invalid_argument("sweep: controllers must not be empty");
  fixed_theta.validate();
  if (first_design < 0 || last_design >= fem::kDesignCount || first_design > last_design)
    throw std::invalid_argument("sweep: designs must be a range within 0..109");
}

std::vector<SweepPoint> sweep_points(const SweepConfig& config) {
  std::vector<SweepPoint> out;
  for (int j = config.first_design; j <= config.last_design; ++j) {
    const int n = fem::design_from_index(j).n;
    for (double p1 : config.pressures_kPa) {
      if (n == 1) {
        out.push_back({j, p1, 0.0});
        continue;
      }
      for (double p2 : config.pressures_kPa) out.push_back({j, p1, p2});
    }
  }
  return out;
}

SweepRow sweep_one(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task, const SweepPoint& point,
                   SweepController controller, const SweepConfig& sweep, const PidTuningConfig& pid) {
  const auto t0 = std::chrono::steady_clock::now();
  const EpisodeSetup setup{point.design, point.p1_kPa, point.p2_kPa, 0.0, 0.0};
  SweepRow row;
  row.point = point;
  row.controller = controller;
  const DesignEvaluation* test = nullptr;
  FixedThetaTuning ft;
  PidTuningResult pt;
  if (controller == SweepController::FixedTheta) {
    ft = tune_fixed_theta(sims, task, setup, sweep.fixed_theta, pid.tuning_phases, pid.test_episodes);
    row.theta0_rad = ft.theta0_rad;
    row.tuning_return = ft.tuning_return;
    row.evaluations = ft.evaluations;
    test = &ft.test;
  } else {
    pt = tune_whisker_pid(sims, task, setup, signal_of(controller), pid);
    if (controller == SweepController::PidEstimate) {
      row.fit_r2 = pt.estimator.fit.r2;
      row.fit_rms_mN = pt.estimator.fit.rms_mN;
    }
    row.gains = pt.pid.gains;
    row.setpoint = pt.pid.setpoint;
    row.tuning_return = pt.tuning_return;
    row.evaluations = pt.evaluations;
    test = &pt.test;
  }
  row.test_return = test->mean_return;
  row.test_std = test->std_return;
  row.band_fraction = test->mean_band_fraction;
  row.test_episodes = static_cast<int>(test->returns.size());
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return row;
}

}  // namespace codesign::core
