#include "core/design_survey.hpp"

#include <algorithm>
#include <utility>

#include "fem/design.hpp"

namespace codesign::core {

std::vector<SurveyRow> survey_designs(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                      const SurveyOptions& o, rl::ThreadPool& pool) {
  TaskConfig zeroed_task = task;  // the same episodes, with ε₀ computed for each
  zeroed_task.strain_offset = StrainOffset::Inflated;
  const double pmax = task.pressure_max_kPa;
  const int first = o.first_design;
  const int count = o.last_design - first + 1;
  std::vector<SurveyRow> rows(static_cast<std::size_t>(count));
  pool.parallel_for(static_cast<std::size_t>(count), [&](std::size_t i) {
    const int j = first + static_cast<int>(i);
    SurveyRow& row = rows[i];
    const int n = fem::design_from_index(j).n;
    std::vector<std::pair<double, double>> ps{{0.0, 0.0}, {pmax, 0.0}};
    if (n == 2) ps.insert(ps.end(), {{0.0, pmax}, {pmax, pmax}});
    EvaluationOptions eo;
    eo.episodes = 1;
    for (const auto& [p1, p2] : ps)
      for (double th : {-task.theta_max_rad, 0.0, task.theta_max_rad}) {
        const DesignEvaluation e = evaluate_design(nullptr, sims, zeroed_task, {j, p1, p2, 0.0, th}, eo);
        for (const TraceRow& r : e.trace) {
          row.strain_min = std::min(row.strain_min, r.strain);
          row.strain_max = std::max(row.strain_max, r.strain);
          row.zeroed_min = std::min(row.zeroed_min, r.strain - r.strain_zero);
          row.zeroed_max = std::max(row.zeroed_max, r.strain - r.strain_zero);
        }
        if (p1 == 0.0 && p2 == 0.0 && th == 0.0) {
          double sum = 0.0;
          for (const TraceRow& r : e.trace) {
            sum += r.force_mN;
            row.force_min = std::min(row.force_min, r.force_mN);
            row.force_max = std::max(row.force_max, r.force_mN);
          }
          row.force_mean = e.trace.empty() ? 0.0 : sum / static_cast<double>(e.trace.size());
        }
      }
    if (o.fixed_theta) row.fixed = best_fixed_theta(sims, task, {j, 0.0, 0.0, 0.0, 0.0}, o.phases, 1);
  });
  return rows;
}

}  // namespace codesign::core
