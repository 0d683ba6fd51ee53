#include "bench/cost_spread.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>

#include "bench/scaling_model.hpp"
#include "cluster/env_assignment.hpp"

namespace codesign::cluster {

namespace {

// The makespan of `costs` over `threads` threads that take the costliest first, each to the thread
// free soonest.
double makespan(std::vector<double> costs, int threads) {
  std::sort(costs.begin(), costs.end(), std::greater<>());
  std::vector<double> load(static_cast<std::size_t>(threads), 0.0);
  for (double c : costs) *std::min_element(load.begin(), load.end()) += c;
  return *std::max_element(load.begin(), load.end());
}

double busiest(const std::vector<double>& actual, const std::vector<std::size_t>& order,
               const std::vector<EnvSlice>& slices, int threads) {
  double worst = 0.0;
  for (const EnvSlice& s : slices) {
    std::vector<double> mine;
    for (std::size_t j = s.first; j < s.first + s.count; ++j) mine.push_back(actual[order[j]]);
    worst = std::max(worst, makespan(mine, threads));
  }
  return worst;
}

// The makespan of `costs` over `threads` threads that take them in `order`, each to the thread free
// soonest (ThreadPool::parallel_for_ordered). `load` is scratch of `threads` entries.
double list_makespan(const std::vector<double>& costs, const std::vector<std::size_t>& order,
                     std::vector<double>& load) {
  std::fill(load.begin(), load.end(), 0.0);
  for (std::size_t i : order) *std::min_element(load.begin(), load.end()) += costs[i];
  return *std::max_element(load.begin(), load.end());
}

// Indices 0 .. key.size()-1, largest key first (ties: lower index first).
std::vector<std::size_t> by_decreasing(const std::vector<double>& key) {
  std::vector<std::size_t> o(key.size());
  std::iota(o.begin(), o.end(), std::size_t{0});
  std::stable_sort(o.begin(), o.end(), [&](std::size_t a, std::size_t b) { return key[a] > key[b]; });
  return o;
}

// The index of another sample of the same design as sample s (the design's cost in another
// iteration, as the backend predicts it), drawn with `pick`; none when the design has one sample.
template <class Pick>
std::optional<std::size_t> another_sample_of_design(const std::vector<std::size_t>& same, std::size_t s, Pick& pick) {
  if (same.size() < 2) return std::nullopt;
  std::size_t o = same[pick(same.size() - 1)];
  if (o == s) o = same.back();
  return o;
}

}  // namespace

CostSummary summarize_costs(const std::vector<CostSample>& samples) {
  if (samples.empty()) throw std::invalid_argument("summarize_costs: no cost samples");
  std::map<int, std::pair<double, double>> by_design;  // sum, count
  double total = 0.0;
  for (const CostSample& c : samples) {
    auto& [sum, n] = by_design[c.design];
    sum += c.seconds;
    n += 1.0;
    total += c.seconds;
  }
  std::map<int, double> design_mean;
  for (const auto& [d, sn] : by_design) design_mean[d] = sn.first / sn.second;
  CostSummary out;
  out.designs = design_mean.size();
  out.mean = total / static_cast<double>(samples.size());
  out.least_design = std::numeric_limits<double>::infinity();
  out.largest_design = -std::numeric_limits<double>::infinity();
  double mean_of_means = 0.0;
  for (const auto& [d, m] : design_mean) {
    mean_of_means += m;
    out.least_design = std::min(out.least_design, m);
    out.largest_design = std::max(out.largest_design, m);
  }
  mean_of_means /= static_cast<double>(out.designs);
  double across = 0.0, within = 0.0;
  for (const auto& [d, m] : design_mean) across += (m - mean_of_means) * (m - mean_of_means);
  for (const CostSample& c : samples) {
    const double m = design_mean.at(c.design);
    within += (c.seconds - m) * (c.seconds - m);
  }
  out.across_designs = std::sqrt(across / static_cast<double>(out.designs));
  out.within_design = std::sqrt(within / static_cast<double>(samples.size()));
  return out;
}

BusiestLoad busiest_load_factor(const std::vector<CostSample>& samples, std::size_t environments, int ranks,
                                int threads, int draws, std::uint64_t seed) {
  if (samples.empty()) throw std::invalid_argument("busiest_load_factor: no cost samples");
  if (draws < 1) throw std::invalid_argument("busiest_load_factor: draws < 1");
  double total = 0.0;
  std::map<int, std::vector<std::size_t>> of_design;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    if (!std::isfinite(samples[k].seconds) || samples[k].seconds < 0.0)
      throw std::invalid_argument("busiest_load_factor: a cost is negative or not finite");
    total += samples[k].seconds;
    of_design[samples[k].design].push_back(k);
  }
  const double mean = total / static_cast<double>(samples.size());
  const double rounds = static_cast<double>(collection_rounds(environments, ranks, threads));
  const std::vector<EnvSlice> slices = env_slices(environments, ranks);
  std::vector<std::size_t> identity(environments);
  std::iota(identity.begin(), identity.end(), std::size_t{0});

  std::mt19937_64 rng(seed);
  auto pick = [&rng](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  std::vector<double> actual(environments), predicted(environments);
  double sum_contiguous = 0.0, sum_by_cost = 0.0;
  for (int k = 0; k < draws; ++k) {
    for (std::size_t i = 0; i < environments; ++i) {
      const std::size_t s = pick(samples.size());
      actual[i] = samples[s].seconds;
      const std::optional<std::size_t> o = another_sample_of_design(of_design.at(samples[s].design), s, pick);
      predicted[i] = o ? samples[*o].seconds : mean;
    }
    sum_contiguous += busiest(actual, identity, slices, threads);
    sum_by_cost += busiest(actual, assign_by_cost(predicted, slices, {}), slices, threads);
  }
  const double norm = static_cast<double>(draws) * rounds * mean;
  if (norm <= 0.0) return {};
  return {sum_contiguous / norm, sum_by_cost / norm};
}

MeetingLoad meeting_load_factor(const std::vector<DecisionCosts>& samples, std::size_t environments, int ranks,
                                int threads, int draws, std::uint64_t seed, double update) {
  if (samples.empty()) throw std::invalid_argument("meeting_load_factor: no cost samples");
  if (draws < 1) throw std::invalid_argument("meeting_load_factor: draws < 1");
  if (!(update >= 0.0) || !std::isfinite(update)) throw std::invalid_argument("meeting_load_factor: a negative update");
  const std::size_t points = samples.front().seconds.size();
  if (points == 0) throw std::invalid_argument("meeting_load_factor: an empty profile");
  std::vector<double> total(samples.size(), 0.0);
  std::map<int, std::vector<std::size_t>> of_design;
  double sum = 0.0;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (samples[s].seconds.size() != points)
      throw std::invalid_argument("meeting_load_factor: profiles of different lengths");
    for (double c : samples[s].seconds) {
      if (!std::isfinite(c) || c < 0.0) throw std::invalid_argument("meeting_load_factor: a cost is negative or not finite");
      total[s] += c;
    }
    sum += total[s];
    of_design[samples[s].design].push_back(s);
  }
  const double mean = sum / static_cast<double>(samples.size());
  const double rounds = static_cast<double>(collection_rounds(environments, ranks, threads));
  const std::vector<EnvSlice> slices = env_slices(environments, ranks);

  std::mt19937_64 rng(seed);
  auto pick = [&rng](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  std::vector<std::size_t> drawn(environments);
  std::vector<double> predicted(environments);
  std::vector<double> load(static_cast<std::size_t>(threads));
  std::vector<double> rank_sum(slices.size());  // per rank: its time summed over the points
  std::vector<double> slowest(points);          // per point: the slowest rank's time
  std::vector<double> rank_start(slices.size());  // per rank: its time at point 0
  double sum_lockstep = 0.0, sum_run_ahead = 0.0, sum_start = 0.0, sum_floor = 0.0, sum_prestarted = 0.0,
         sum_prestart = 0.0, sum_after = 0.0;
  for (int d = 0; d < draws; ++d) {
    for (std::size_t i = 0; i < environments; ++i) {
      const std::size_t s = pick(samples.size());
      drawn[i] = s;
      const std::optional<std::size_t> o = another_sample_of_design(of_design.at(samples[s].design), s, pick);
      predicted[i] = o ? total[*o] : mean;
    }
    const std::vector<std::size_t> order = assign_by_cost(predicted, slices, {});
    std::fill(rank_sum.begin(), rank_sum.end(), 0.0);
    std::fill(slowest.begin(), slowest.end(), 0.0);
    double floor_here = 0.0;  // this draw's: the largest over the ranks
    for (std::size_t r = 0; r < slices.size(); ++r) {
      double longest = 0.0, all = 0.0;
      for (std::size_t j = slices[r].first; j < slices[r].first + slices[r].count; ++j) {
        longest = std::max(longest, total[drawn[order[j]]]);
        all += total[drawn[order[j]]];
      }
      floor_here = std::max(floor_here, std::max(longest, all / static_cast<double>(threads)));
      // This rank's environments at each point, in the order of their previous costs (at the
      // start: of the predicted totals).
      std::vector<double> key, now(slices[r].count);
      for (std::size_t j = slices[r].first; j < slices[r].first + slices[r].count; ++j) key.push_back(predicted[order[j]]);
      for (std::size_t k = 0; k < points; ++k) {
        for (std::size_t e = 0; e < now.size(); ++e) now[e] = samples[drawn[order[slices[r].first + e]]].seconds[k];
        const double t = list_makespan(now, by_decreasing(key), load);
        rank_sum[r] += t;
        if (k == 0) rank_start[r] = t;
        slowest[k] = std::max(slowest[k], t);
        key = now;
      }
    }
    const double lockstep = std::accumulate(slowest.begin(), slowest.end(), 0.0);
    sum_lockstep += lockstep;
    sum_start += slowest.front();
    sum_run_ahead += *std::max_element(rank_sum.begin(), rank_sum.end());
    sum_floor += floor_here;
    double prestarted = rank_sum.front(), prestart = 0.0, after = rank_sum.front();
    for (std::size_t r = 1; r < slices.size(); ++r) {
      const double rest = rank_sum[r] - rank_start[r];
      prestarted = std::max(prestarted, rest);
      prestart = std::max(prestart, rank_start[r]);
      after = std::max(after, std::max(0.0, rank_start[r] - update) + rest);
    }
    sum_prestarted += prestarted;
    sum_prestart += prestart;
    sum_after += after;
  }
  const double norm = static_cast<double>(draws) * rounds * mean;
  if (norm <= 0.0) return {};
  return {sum_lockstep / norm, sum_run_ahead / norm, sum_start / norm, sum_floor / norm, sum_prestarted / norm,
          sum_prestart / norm, sum_after / norm};
}

}  // namespace codesign::cluster
