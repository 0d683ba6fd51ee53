#include "codesign/refine.hpp"

#include <sstream>
#include <stdexcept>

#include "base/errors.hpp"
#include "fem/design.hpp"
#include "io/csv_log.hpp"

namespace codesign::core {

namespace {

std::string num(double v) { return io::CsvLog::num(v); }

}  // namespace

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

std::string with_refined_table(const std::string& text, const RefineResult& r) {
  std::string base = text;
  // Remove an earlier [refined] table: from its header line to the next table header or the end.
  std::size_t at = base.rfind("\n[refined]");
  if (at != std::string::npos) ++at;
  else if (base.rfind("[refined]", 0) == 0) at = 0;
  if (at != std::string::npos) {
    const std::size_t next = base.find("\n[", at);
    base.erase(at, next == std::string::npos ? std::string::npos : next + 1 - at);
  }
  if (!base.empty() && base.back() != '\n') base += '\n';
  // One blank line before the table (an erased earlier table left its blank line in place).
  const bool blank = base.empty() || base.ends_with("\n\n");
  std::ostringstream o;
  o << (blank ? "" : "\n") << "[refined]   # codesign refine: p* polished by NLopt (" << to_string(r.config.search.method)
    << ") with the policy and j* fixed\n"
    << "design = " << r.design << "\n"
    << "pressures_kPa_before = [" << num(r.p_before[0]) << ", " << num(r.p_before[1]) << "]\n"
    << "pressures_kPa = [" << num(r.p_after[0]) << ", " << num(r.p_after[1]) << "]\n"
    << "tuning_phases = " << r.config.tuning_phases << "   # plate phases 2*pi*(i + 0.618...)/n, searched on\n"
    << "tuning_return_before = " << num(r.tuning_before) << "\n"
    << "tuning_return = " << num(r.tuning_after) << "\n"
    << "evaluations = " << r.evaluations << "\n"
    << "test_episodes = " << r.test_after.returns.size() << "   # plate phases 2*pi*(k + 1/2)/n, never searched on\n"
    << "test_return_before = " << num(r.test_before.mean_return) << "\n"
    << "test_return_before_std = " << num(r.test_before.std_return) << "\n"
    << "test_return = " << num(r.test_after.mean_return) << "\n"
    << "test_return_std = " << num(r.test_after.std_return) << "\n"
    << "band_fraction = " << num(r.test_after.mean_band_fraction) << "\n";
  return base + o.str();
}

}  // namespace codesign::core
