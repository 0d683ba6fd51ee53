#include "codesign/rollout_waves.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <stdexcept>

namespace codesign::core {

double longest_first_makespan(std::vector<double> costs, std::size_t threads) {
  if (threads < 1) throw std::invalid_argument("longest_first_makespan: no threads");
  std::sort(costs.begin(), costs.end(), std::greater<double>());
  std::vector<double> load(std::min(threads, std::max<std::size_t>(costs.size(), 1)), 0.0);
  for (double c : costs) *std::min_element(load.begin(), load.end()) += c;
  return *std::max_element(load.begin(), load.end());
}

std::vector<std::size_t> next_wave(const std::vector<WaveEnv>& envs, std::size_t threads, double pass_s) {
  if (threads < 1) throw std::invalid_argument("next_wave: no threads");
  if (!std::isfinite(pass_s) || pass_s < 0.0) throw std::invalid_argument("next_wave: pass_s negative or not finite");
  std::vector<std::size_t> open;
  std::vector<double> left(envs.size(), 0.0), job(envs.size(), 0.0);
  for (std::size_t i = 0; i < envs.size(); ++i) {
    const WaveEnv& e = envs[i];
    if (!std::isfinite(e.start_cost) || e.start_cost < 0.0 || !std::isfinite(e.step_cost) || e.step_cost < 0.0)
      throw std::invalid_argument("next_wave: a cost negative or not finite");
    if (e.jobs_left <= 0) continue;
    open.push_back(i);
    job[i] = e.started ? e.step_cost : e.start_cost;
    left[i] = e.step_cost * (e.jobs_left - (e.started ? 0 : 1)) + (e.started ? 0.0 : e.start_cost);
  }
  std::stable_sort(open.begin(), open.end(), [&](std::size_t a, std::size_t b) { return left[a] > left[b]; });
  const std::size_t n = open.size();
  if (n == 0) return open;
  // Candidates from the largest down; a smaller one must beat the best so far by more than 1 %: the
  // predictions are the last jobs' costs, which vary, and a wave left short costs a forward pass.
  std::vector<std::size_t> sizes{n};
  for (std::size_t m = (n - 1) / threads * threads; m >= threads; m -= threads) sizes.push_back(m);
  std::size_t best = n;
  double best_rate = -1.0;
  std::vector<double> costs;
  for (std::size_t m : sizes) {
    costs.clear();
    bool steps = false;
    for (std::size_t k = 0; k < m; ++k) {
      costs.push_back(job[open[k]]);
      steps = steps || envs[open[k]].started;
    }
    const double work = std::accumulate(costs.begin(), costs.end(), 0.0);
    const double wall = longest_first_makespan(costs, threads) + (steps ? pass_s : 0.0);
    const double rate = wall > 0.0 ? work / wall : 0.0;
    if (rate > best_rate * 1.01 || best_rate < 0.0) {
      best_rate = rate;
      best = m;
    }
  }
  open.resize(best);
  return open;
}

}  // namespace codesign::core
