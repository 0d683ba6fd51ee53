#include "cluster/env_assignment.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "fem/design.hpp"

namespace codesign::cluster {

std::vector<double> predict_costs(const std::vector<double>& design_cost, const std::vector<int>& env_design) {
  const auto known = [&](int d) {
    return d >= 0 && static_cast<std::size_t>(d) < design_cost.size() && std::isfinite(design_cost[static_cast<std::size_t>(d)]);
  };
  const auto wall_of = [](int d) { return d < fem::kDesignCount ? fem::design_from_index(d).wall_mm : -1.0; };
  double sum = 0.0, count = 0.0;
  std::map<double, std::pair<double, double>> by_wall;  // wall thickness -> sum, count of the known
  for (std::size_t d = 0; d < design_cost.size(); ++d)
    if (known(static_cast<int>(d))) {
      sum += design_cost[d], count += 1.0;
      auto& w = by_wall[wall_of(static_cast<int>(d))];
      w.first += design_cost[d], w.second += 1.0;
    }
  if (count == 0.0) return {};
  std::vector<double> predicted(env_design.size(), sum / count);
  for (std::size_t i = 0; i < env_design.size(); ++i) {
    const int d = env_design[i];
    if (known(d)) {
      predicted[i] = design_cost[static_cast<std::size_t>(d)];
    } else if (d >= 0 && d < fem::kDesignCount) {
      const auto w = by_wall.find(wall_of(d));
      if (w != by_wall.end()) predicted[i] = w->second.first / w->second.second;
    }
  }
  return predicted;
}

EnvSlice env_slice(std::size_t n_envs, int rank, int ranks) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("env_slice: rank " + std::to_string(rank) + " of " + std::to_string(ranks));
  const auto n = static_cast<std::size_t>(ranks), r = static_cast<std::size_t>(rank);
  if (n_envs < n)
    throw std::invalid_argument(std::to_string(ranks) + " MPI ranks for " + std::to_string(n_envs) +
                                " environments (designs_per_update): every rank needs at least one");
  const std::size_t base = n_envs / n, extra = n_envs % n;
  return {r * base + std::min(r, extra), base + (r < extra ? 1 : 0)};
}

std::vector<EnvSlice> env_slices(std::size_t n_envs, int ranks) {
  std::vector<EnvSlice> slices{env_slice(n_envs, 0, ranks)};  // throws for ranks < 1
  for (int r = 1; r < ranks; ++r) slices.push_back(env_slice(n_envs, r, ranks));
  return slices;
}

std::vector<std::size_t> assign_by_cost(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                                        const std::vector<std::size_t>& pinned) {
  return assign_by_cost(cost, slices, pinned, BuildCosts{0.0, 0.0, std::vector<int>(cost.size(), -1),
                                                          std::vector<std::vector<int>>(slices.size())});
}

std::vector<std::size_t> assign_by_cost(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                                        const std::vector<std::size_t>& pinned, const BuildCosts& build) {
  const std::size_t n = cost.size(), ranks = slices.size();
  std::size_t next = 0;
  for (const EnvSlice& s : slices) {
    if (s.first != next) throw std::invalid_argument("assign_by_cost: the slices are not contiguous from place 0");
    next += s.count;
  }
  if (ranks == 0 || next != n)
    throw std::invalid_argument("assign_by_cost: the slices hold " + std::to_string(next) + " places for " +
                                std::to_string(n) + " environments");
  for (double c : cost)
    if (!std::isfinite(c) || c < 0.0) throw std::invalid_argument("assign_by_cost: a cost is negative or not finite");
  if (build.design.size() != n || build.held.size() != ranks)
    throw std::invalid_argument("assign_by_cost: build costs for " + std::to_string(build.design.size()) +
                                " environments and " + std::to_string(build.held.size()) + " ranks, not " +
                                std::to_string(n) + " and " + std::to_string(ranks));
  if (!std::isfinite(build.model) || build.model < 0.0 || !std::isfinite(build.simulator) || build.simulator < 0.0 ||
      !std::isfinite(build.model_from_mesh) || build.model_from_mesh < 0.0)
    throw std::invalid_argument("assign_by_cost: a build cost is negative or not finite");
  for (const std::vector<int>& row : build.held)
    for (int h : row)
      if (h < 0) throw std::invalid_argument("assign_by_cost: a negative count of held simulators");

  std::vector<int> rank_of(n, -1);
  std::vector<double> load(ranks, 0.0);
  std::vector<std::size_t> free_places(ranks);
  for (std::size_t r = 0; r < ranks; ++r) free_places[r] = slices[r].count;
  // Simulators of each design taken on each rank by the environments placed so far.
  std::vector<std::vector<int>> taken(ranks);
  const auto held = [&](std::size_t r, std::size_t d) {
    return d < build.held[r].size() ? build.held[r][d] : 0;
  };
  const auto taken_of = [&](std::size_t r, std::size_t d) -> int& {
    if (taken[r].size() <= d) taken[r].resize(d + 1, 0);
    return taken[r][d];
  };
  // What rank r builds to step k environments of design d, and what it builds more if it steps
  // `by` more of d than it has taken so far (negative d: nothing).
  const auto builds = [&](std::size_t r, std::size_t d, int k) {
    if (k <= 0) return 0.0;
    const int h = held(r, d);
    const bool mesh_known = d < build.meshed.size() && build.meshed[d];
    return (h == 0 ? (mesh_known ? build.model_from_mesh : build.model) : 0.0) + std::max(0, k - h) * build.simulator;
  };
  const auto change = [&](std::size_t r, int d, int by) {
    if (d < 0) return 0.0;
    const auto k = static_cast<std::size_t>(d);
    const int now = taken_of(r, k);
    return builds(r, k, now + by) - builds(r, k, now);
  };
  const auto extra = [&](std::size_t r, std::size_t i) { return change(r, build.design[i], +1); };
  const auto place = [&](std::size_t i, std::size_t r) {
    load[r] += cost[i] + extra(r, i);
    if (build.design[i] >= 0) ++taken_of(r, static_cast<std::size_t>(build.design[i]));
    rank_of[i] = static_cast<int>(r);
    --free_places[r];
  };
  for (std::size_t i : pinned) {
    if (i >= slices[0].count || rank_of[i] != -1)
      throw std::invalid_argument("assign_by_cost: pinned environment " + std::to_string(i) +
                                  " is repeated or not on rank 0's " + std::to_string(slices[0].count) + " places");
    place(i, 0);
  }

  std::vector<std::size_t> by_cost(n);
  std::iota(by_cost.begin(), by_cost.end(), std::size_t{0});
  std::stable_sort(by_cost.begin(), by_cost.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  for (std::size_t i : by_cost) {
    if (rank_of[i] != -1) continue;
    std::size_t best = ranks;
    double best_total = 0.0;
    for (std::size_t r = 0; r < ranks; ++r) {
      if (free_places[r] == 0) continue;
      const double total = load[r] + extra(r, i);
      if (best == ranks || total < best_total) best = r, best_total = total;
    }
    place(i, best);
  }

  // Then swaps of two environments between two ranks, while one lowers the larger of the two
  // ranks' totals, or keeps it and lowers their sum (fewer builds): the greedy places one
  // environment at a time, so a design one rank holds often lands on another that must build it.
  // Each swap keeps every slice's size. Totals are compared to 1e-9 s. Passes over all pairs go on
  // until none swaps, at most 64 (a swap that lowers the larger total may raise the sum, so no
  // single measure falls at every swap; the random cases of the tests needed at most 10).
  std::vector<char> is_pinned(n, 0);
  for (std::size_t i : pinned) is_pinned[i] = 1;
  for (int pass = 0; pass < 64; ++pass) {
    bool swapped = false;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const auto a = static_cast<std::size_t>(rank_of[i]), b = static_cast<std::size_t>(rank_of[j]);
        if (a == b || is_pinned[i] || is_pinned[j]) continue;
        const int di = build.design[i], dj = build.design[j];
        double ta = load[a] - cost[i] + cost[j], tb = load[b] - cost[j] + cost[i];
        if (di != dj) {
          ta += change(a, di, -1) + change(a, dj, +1);
          tb += change(b, dj, -1) + change(b, di, +1);
        }
        const double was = std::max(load[a], load[b]), now = std::max(ta, tb), eps = 1e-9;
        if (!(now < was - eps || (now <= was + eps && ta + tb < load[a] + load[b] - eps))) continue;
        if (di >= 0) --taken_of(a, static_cast<std::size_t>(di)), ++taken_of(b, static_cast<std::size_t>(di));
        if (dj >= 0) --taken_of(b, static_cast<std::size_t>(dj)), ++taken_of(a, static_cast<std::size_t>(dj));
        load[a] = ta;
        load[b] = tb;
        rank_of[i] = static_cast<int>(b);
        rank_of[j] = static_cast<int>(a);
        swapped = true;
      }
    if (!swapped) break;
  }

  // Lay the ranks' environments out in ascending order; rank 0's pins first at their own places.
  std::vector<std::size_t> order(n, n);
  for (std::size_t i : pinned) order[i] = i;
  std::vector<std::size_t> cursor(ranks);
  for (std::size_t r = 0; r < ranks; ++r) cursor[r] = slices[r].first;
  for (std::size_t i = 0; i < n; ++i) {
    if (rank_of[i] == 0 && std::find(pinned.begin(), pinned.end(), i) != pinned.end()) continue;
    const auto r = static_cast<std::size_t>(rank_of[i]);
    while (order[cursor[r]] != n) ++cursor[r];  // skip rank 0's pinned places
    order[cursor[r]++] = i;
  }
  return order;
}

void record_held(const std::vector<std::size_t>& order, const std::vector<EnvSlice>& slices, BuildCosts& build) {
  if (build.held.size() != slices.size())
    throw std::invalid_argument("record_held: held simulators for " + std::to_string(build.held.size()) +
                                " ranks, not " + std::to_string(slices.size()));
  for (std::size_t r = 0; r < slices.size(); ++r) {
    std::vector<int> here;
    for (std::size_t j = slices[r].first; j < slices[r].first + slices[r].count; ++j) {
      if (j >= order.size() || order[j] >= build.design.size())
        throw std::invalid_argument("record_held: place " + std::to_string(j) + " has no environment");
      const int d = build.design[order[j]];
      if (d < 0) continue;
      const auto k = static_cast<std::size_t>(d);
      if (here.size() <= k) here.resize(k + 1, 0);
      ++here[k];
    }
    std::vector<int>& row = build.held[r];
    if (row.size() < here.size()) row.resize(here.size(), 0);
    for (std::size_t d = 0; d < here.size(); ++d) row[d] = std::max(row[d], here[d]);
  }
}

}  // namespace codesign::cluster
