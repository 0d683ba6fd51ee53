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

namespace {

// Throws std::invalid_argument unless the slices cover the costs' places contiguously from 0, every
// cost and build cost is finite and not negative, `build` has one design per environment and one
// row of held counts per rank, and no held count is negative.
void check_assignment_input(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                            const BuildCosts& build) {
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
}

// An assignment while it is made: the rank of each environment placed so far (-1: not yet), each
// rank's total (its environments' costs and what it builds for them), its free places, and the
// simulators of each design its environments take.
class PartialAssignment {
 public:
  PartialAssignment(const std::vector<double>& cost, const std::vector<EnvSlice>& slices, const BuildCosts& build)
      : cost_(cost), build_(build), rank_of_(cost.size(), -1), load_(slices.size(), 0.0),
        free_places_(slices.size()), taken_(slices.size()) {
    for (std::size_t r = 0; r < slices.size(); ++r) free_places_[r] = slices[r].count;
  }

  std::size_t environments() const { return cost_.size(); }
  std::size_t ranks() const { return load_.size(); }
  bool placed(std::size_t env) const { return rank_of_[env] != -1; }
  std::size_t rank_of(std::size_t env) const { return static_cast<std::size_t>(rank_of_[env]); }
  const std::vector<int>& ranks_of_environments() const { return rank_of_; }
  bool has_free_place(std::size_t rank) const { return free_places_[rank] != 0; }

  // Rank `rank`'s total if it took environment `env` too.
  double total_with(std::size_t rank, std::size_t env) { return load_[rank] + extra_builds(rank, env); }

  void place(std::size_t env, std::size_t rank) {
    load_[rank] += cost_[env] + extra_builds(rank, env);
    if (build_.design[env] >= 0) ++taken_of(rank, static_cast<std::size_t>(build_.design[env]));
    rank_of_[env] = static_cast<int>(rank);
    --free_places_[rank];
  }

  // Swaps environments i and j, on different ranks, if that lowers the larger of their ranks'
  // totals, or keeps it (to 1e-9 s) and lowers their sum. Returns whether it swapped.
  bool swap_if_better(std::size_t i, std::size_t j) {
    const std::size_t rank_i = rank_of(i), rank_j = rank_of(j);
    const int design_i = build_.design[i], design_j = build_.design[j];
    double total_i = load_[rank_i] - cost_[i] + cost_[j], total_j = load_[rank_j] - cost_[j] + cost_[i];
    if (design_i != design_j) {
      total_i += build_change(rank_i, design_i, -1) + build_change(rank_i, design_j, +1);
      total_j += build_change(rank_j, design_j, -1) + build_change(rank_j, design_i, +1);
    }
    const double was = std::max(load_[rank_i], load_[rank_j]), now = std::max(total_i, total_j), eps = 1e-9;
    if (!(now < was - eps || (now <= was + eps && total_i + total_j < load_[rank_i] + load_[rank_j] - eps)))
      return false;
    if (design_i >= 0) {
      --taken_of(rank_i, static_cast<std::size_t>(design_i));
      ++taken_of(rank_j, static_cast<std::size_t>(design_i));
    }
    if (design_j >= 0) {
      --taken_of(rank_j, static_cast<std::size_t>(design_j));
      ++taken_of(rank_i, static_cast<std::size_t>(design_j));
    }
    load_[rank_i] = total_i;
    load_[rank_j] = total_j;
    rank_of_[i] = static_cast<int>(rank_j);
    rank_of_[j] = static_cast<int>(rank_i);
    return true;
  }

 private:
  int held(std::size_t rank, std::size_t design) const {
    return design < build_.held[rank].size() ? build_.held[rank][design] : 0;
  }
  int& taken_of(std::size_t rank, std::size_t design) {
    if (taken_[rank].size() <= design) taken_[rank].resize(design + 1, 0);
    return taken_[rank][design];
  }
  // What `rank` builds to step `count` environments of `design`.
  double builds(std::size_t rank, std::size_t design, int count) const {
    if (count <= 0) return 0.0;
    const int holds = held(rank, design);
    const bool mesh_known = design < build_.meshed.size() && build_.meshed[design];
    return (holds == 0 ? (mesh_known ? build_.model_from_mesh : build_.model) : 0.0) +
           std::max(0, count - holds) * build_.simulator;
  }
  // What `rank` builds more if it steps `by` more environments of `design` than it has taken so
  // far (negative design: nothing).
  double build_change(std::size_t rank, int design, int by) {
    if (design < 0) return 0.0;
    const auto index = static_cast<std::size_t>(design);
    const int now = taken_of(rank, index);
    return builds(rank, index, now + by) - builds(rank, index, now);
  }
  double extra_builds(std::size_t rank, std::size_t env) { return build_change(rank, build_.design[env], +1); }

  const std::vector<double>& cost_;
  const BuildCosts& build_;
  std::vector<int> rank_of_;
  std::vector<double> load_;
  std::vector<std::size_t> free_places_;
  std::vector<std::vector<int>> taken_;  // per rank, per design: simulators its environments take
};

// Rank 0 takes the pinned environments (throws std::invalid_argument for one repeated or beyond
// rank 0's places).
void place_pinned(PartialAssignment& assignment, const std::vector<std::size_t>& pinned, std::size_t rank0_places) {
  for (std::size_t i : pinned) {
    if (i >= rank0_places || assignment.placed(i))
      throw std::invalid_argument("assign_by_cost: pinned environment " + std::to_string(i) +
                                  " is repeated or not on rank 0's " + std::to_string(rank0_places) + " places");
    assignment.place(i, 0);
  }
}

// The greedy rule: the costliest environment not yet placed first (ties: lower index), to the rank
// with a free place whose total would be least after it (ties: lower rank).
void place_costliest_first(PartialAssignment& assignment, const std::vector<double>& cost) {
  std::vector<std::size_t> by_cost(assignment.environments());
  std::iota(by_cost.begin(), by_cost.end(), std::size_t{0});
  std::stable_sort(by_cost.begin(), by_cost.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  for (std::size_t i : by_cost) {
    if (assignment.placed(i)) continue;
    std::size_t best = assignment.ranks();
    double best_total = 0.0;
    for (std::size_t r = 0; r < assignment.ranks(); ++r) {
      if (!assignment.has_free_place(r)) continue;
      const double total = assignment.total_with(r, i);
      if (best == assignment.ranks() || total < best_total) best = r, best_total = total;
    }
    assignment.place(i, best);
  }
}

// Then swaps of two environments between two ranks, while one lowers the larger of the two
// ranks' totals, or keeps it and lowers their sum (fewer builds): the greedy places one
// environment at a time, so a design one rank holds often lands on another that must build it.
// Each swap keeps every slice's size. Passes over all pairs go on until none swaps, at most 64 (a
// swap that lowers the larger total may raise the sum, so no single measure falls at every swap;
// the random cases of the tests needed at most 10).
void swap_while_better(PartialAssignment& assignment, const std::vector<std::size_t>& pinned) {
  const std::size_t n = assignment.environments();
  std::vector<char> is_pinned(n, 0);
  for (std::size_t i : pinned) is_pinned[i] = 1;
  for (int pass = 0; pass < 64; ++pass) {
    bool swapped = false;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        if (assignment.rank_of(i) == assignment.rank_of(j) || is_pinned[i] || is_pinned[j]) continue;
        if (assignment.swap_if_better(i, j)) swapped = true;
      }
    if (!swapped) break;
  }
}

// The permutation of places: the ranks' environments in ascending order, rank 0's pins first at
// their own places.
std::vector<std::size_t> lay_out(const std::vector<int>& rank_of, const std::vector<std::size_t>& pinned,
                                 const std::vector<EnvSlice>& slices) {
  const std::size_t n = rank_of.size();
  std::vector<std::size_t> order(n, n);
  for (std::size_t i : pinned) order[i] = i;
  std::vector<std::size_t> cursor(slices.size());
  for (std::size_t r = 0; r < slices.size(); ++r) cursor[r] = slices[r].first;
  for (std::size_t i = 0; i < n; ++i) {
    if (rank_of[i] == 0 && std::find(pinned.begin(), pinned.end(), i) != pinned.end()) continue;
    const auto r = static_cast<std::size_t>(rank_of[i]);
    while (order[cursor[r]] != n) ++cursor[r];  // skip rank 0's pinned places
    order[cursor[r]++] = i;
  }
  return order;
}

}  // namespace

std::vector<std::size_t> assign_by_cost(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                                        const std::vector<std::size_t>& pinned) {
  return assign_by_cost(cost, slices, pinned, BuildCosts{0.0, 0.0, std::vector<int>(cost.size(), -1),
                                                          std::vector<std::vector<int>>(slices.size())});
}

std::vector<std::size_t> assign_by_cost(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                                        const std::vector<std::size_t>& pinned, const BuildCosts& build) {
  check_assignment_input(cost, slices, build);
  PartialAssignment assignment(cost, slices, build);
  place_pinned(assignment, pinned, slices[0].count);
  place_costliest_first(assignment, cost);
  swap_while_better(assignment, pinned);
  return lay_out(assignment.ranks_of_environments(), pinned, slices);
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
