#include "core/pid_tuning.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace codesign::core {

namespace {

void check_range(const char* name, const std::array<double, 2>& r, bool non_negative) {
  const std::string where = std::string("PID bounds: ") + name + " range [" + std::to_string(r[0]) + ", " +
                            std::to_string(r[1]) + "]";
  if (!std::isfinite(r[0]) || !std::isfinite(r[1])) throw std::invalid_argument(where + " is not finite");
  if (r[0] > r[1]) throw std::invalid_argument(where + " has its lower bound above its upper bound");
  if (non_negative && r[0] < 0.0) throw std::invalid_argument(where + " allows negative gains; gains must be >= 0");
}

}  // namespace

void PidBox::validate() const {
  check_range("kp", kp, true);
  check_range("ki", ki, true);
  check_range("kd", kd, true);
  check_range("offset", offset, false);
}

PidSearch tune_pid(const PidObjective& objective, const PidBox& box, const SearchOptions& search,
                   const PidGains& start, double offset_start) {
  box.validate();
  start.validate();
  if (!std::isfinite(offset_start)) throw std::invalid_argument("tune_pid: start offset is not finite");
  const SearchBox b{{box.kp[0], box.ki[0], box.kd[0], box.offset[0]}, {box.kp[1], box.ki[1], box.kd[1], box.offset[1]}};
  const SearchResult r = maximise(
      [&](const std::vector<double>& x) { return objective(PidGains{x[0], x[1], x[2]}, x[3]); }, b, search,
      std::vector<double>{start.kp, start.ki, start.kd, offset_start});
  return {PidGains{r.x[0], r.x[1], r.x[2]}, r.x[3], r.value, r.evaluations};
}

void PidTuningConfig::validate() const {
  box.validate();
  start.validate();
  search.validate();
  if (!(strain_scale > 0.0 && std::isfinite(strain_scale)))
    throw std::invalid_argument("pid: strain_scale must be > 0");
  if (tuning_phases < 1) throw std::invalid_argument("pid: tuning_phases must be >= 1");
  if (test_episodes < 1) throw std::invalid_argument("pid: test_episodes must be >= 1");
  if (estimator_fit_episodes < 1) throw std::invalid_argument("pid: estimator_fit_episodes must be >= 1");
}

double pid_error(const WhiskerPid& pid, const fem::Sensors& s, const TaskConfig& task) {
  const double band = task.tolerance_fraction * task.target_force_mN;
  switch (pid.signal) {
    case PidSignal::Force: return (pid.setpoint - s.contact_force_mN) / band;
    case PidSignal::Estimate: return (pid.setpoint - pid.estimator.force_mN(s.axial_strain, s.theta_rad)) / band;
    case PidSignal::Strain: break;
  }
  return -(pid.setpoint - s.axial_strain) / pid.strain_scale;
}

ControllerFactory pid_factory(const WhiskerPid& pid, const TaskConfig& task) {
  pid.gains.validate();
  return [pid, task] {
    auto c = std::make_shared<PidController>(pid.gains);
    return FeedbackController([c, pid, task](const Eigen::VectorXd&, const fem::Sensors& s) {
      return c->act(pid_error(pid, s, task));
    });
  };
}

double calibrate_strain_setpoint(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                 EpisodeSetup setup, double phase_rad) {
  // One episode with the base still: ε against F over the plate's swing.
  EvaluationOptions eo;
  eo.episodes = 1;
  eo.trace_first = true;
  eo.phase_offset = phase_rad / (2.0 * std::numbers::pi);
  setup.theta0_rad = 0.0;
  const DesignEvaluation e = evaluate_design(nullptr, sims, task, setup, eo);
  double n = 0, sf = 0, se = 0, sff = 0, sfe = 0, se_all = 0;
  for (const TraceRow& r : e.trace) {
    se_all += r.strain;
    if (!(r.force_mN > 0.0)) continue;
    n += 1, sf += r.force_mN, se += r.strain, sff += r.force_mN * r.force_mN, sfe += r.force_mN * r.strain;
  }
  if (e.trace.empty()) return 0.0;
  const double var = n * sff - sf * sf;
  // Too few contact points or no spread of F: the mean strain is the best guess.
  if (n < 3 || !(var > 1e-12 * n * n)) return se_all / static_cast<double>(e.trace.size());
  const double slope = (n * sfe - sf * se) / var;
  const double icpt = (se - slope * sf) / n;
  return icpt + slope * task.target_force_mN;
}

PidTuningResult tune_whisker_pid(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                 const EpisodeSetup& setup, PidSignal signal, const PidTuningConfig& config,
                                 std::size_t threads) {
  config.validate();
  PidTuningResult out;
  WhiskerPid pid;
  pid.signal = signal;
  pid.strain_scale = config.strain_scale;
  PidBox box = config.box;
  if (signal == PidSignal::Force || signal == PidSignal::Estimate) {
    pid.setpoint = task.target_force_mN;
    box.offset = {0.0, 0.0};
    if (signal == PidSignal::Estimate) {
      out.estimator = calibrate_force_estimator(sims, task, setup, config.estimator_fit_episodes,
                                                config.tuning_phases, threads);
      pid.estimator = out.estimator.fit.estimator;
    }
  } else {
    out.strain_calibrated = calibrate_strain_setpoint(sims, task, setup, evaluation_phase(0, config.tuning_phases,
                                                                                           kTuningPhaseOffset));
  }
  EvaluationOptions tuning;
  tuning.episodes = config.tuning_phases;
  tuning.phase_offset = kTuningPhaseOffset;
  tuning.threads = threads;
  tuning.trace_first = false;
  auto with = [&](const PidGains& g, double offset) {
    WhiskerPid p = pid;
    p.gains = g;
    if (signal == PidSignal::Strain) p.setpoint = out.strain_calibrated + offset * config.strain_scale;
    return p;
  };
  const PidSearch s = tune_pid(
      [&](const PidGains& g, double offset) {
        return evaluate_feedback(pid_factory(with(g, offset), task), sims, task, setup, tuning).mean_return;
      },
      box, config.search, config.start, 0.0);
  out.pid = with(s.gains, s.offset);
  out.offset = s.offset;
  out.tuning_return = s.value;
  out.evaluations = s.evaluations;
  EvaluationOptions test;
  test.episodes = config.test_episodes;
  test.threads = threads;
  out.test = evaluate_feedback(pid_factory(out.pid, task), sims, task, setup, test);
  return out;
}

}  // namespace codesign::core
