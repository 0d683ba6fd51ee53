#include "core/refine.hpp"

#include <sstream>
#include <stdexcept>

#include "base/errors.hpp"
#include "fem/design.hpp"

namespace codesign::core {

void RefineConfig::validate() const {
  if (tuning_phases < 1) throw std::invalid_argument("refine: tuning_phases must be >= 1");
  if (test_episodes < 1) throw std::invalid_argument("refine: test_episodes must be >= 1");
  search.validate();
}

RefineResult refine_pressures(const Controller& policy, const std::shared_ptr<SimulatorPool>& sims,
                              const TaskConfig& task, int design, std::array<double, 2> p_before,
                              const RefineConfig& config, std::size_t threads) {
  if (!policy) throw std::invalid_argument("refine: no policy");
  const ControllerFactory make = [&policy] {
    return FeedbackController([&policy](const Eigen::VectorXd& obs, const fem::Sensors&) { return policy(obs); });
  };
  return refine_pressures(make, sims, task, design, p_before, config, threads);
}

RefineResult refine_pressures(const ControllerFactory& policy, const std::shared_ptr<SimulatorPool>& sims,
                              const TaskConfig& task, int design, std::array<double, 2> p_before,
                              const RefineConfig& config, std::size_t threads) {
  config.validate();
  if (!policy) throw std::invalid_argument("refine: no policy");
  const int n = fem::design_from_index(design).n;
  const double pmax = task.pressure_max_kPa;
  for (double p : p_before)
    if (!(p >= 0.0 && p <= pmax))
      throw std::invalid_argument("refine: pressure " + std::to_string(p) + " kPa outside [0, " + std::to_string(pmax) +
                                  "]");
  if (n == 1) p_before[1] = 0.0;
  RefineResult out;
  out.design = design;
  out.p_before = p_before;
  out.config = config;
  EvaluationOptions tuning;
  tuning.episodes = config.tuning_phases;
  tuning.phase_offset = kTuningPhaseOffset;
  tuning.threads = threads;
  tuning.trace_first = false;
  auto tuning_return = [&](double p1, double p2) {
    return evaluate_feedback(policy, sims, task, {design, p1, p2, 0.0, 0.0}, tuning).mean_return;
  };
  out.tuning_before = tuning_return(p_before[0], p_before[1]);
  const SearchBox box{{0.0, 0.0}, {pmax, n == 2 ? pmax : 0.0}};
  const SearchResult r = maximise([&](const std::vector<double>& x) { return tuning_return(x[0], x[1]); }, box,
                                  config.search, std::vector<double>{p_before[0], p_before[1]});
  out.evaluations = r.evaluations + 1;
  // Keep p* unless the search found strictly better.
  if (r.value > out.tuning_before) {
    out.p_after = {r.x[0], r.x[1]};
    out.tuning_after = r.value;
  } else {
    out.p_after = p_before;
    out.tuning_after = out.tuning_before;
  }
  EvaluationOptions test;
  test.episodes = config.test_episodes;
  test.threads = threads;
  out.test_before = evaluate_feedback(policy, sims, task, {design, p_before[0], p_before[1], 0.0, 0.0}, test);
  out.test_after = evaluate_feedback(policy, sims, task, {design, out.p_after[0], out.p_after[1], 0.0, 0.0}, test);
  return out;
}


}  // namespace codesign::core
