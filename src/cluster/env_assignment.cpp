#include "cluster/env_assignment.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace codesign::cluster {

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

  std::vector<int> rank_of(n, -1);
  std::vector<double> load(ranks, 0.0);
  std::vector<std::size_t> free_places(ranks);
  for (std::size_t r = 0; r < ranks; ++r) free_places[r] = slices[r].count;
  for (std::size_t i : pinned) {
    if (i >= slices[0].count || rank_of[i] != -1)
      throw std::invalid_argument("assign_by_cost: pinned environment " + std::to_string(i) +
                                  " is repeated or not on rank 0's " + std::to_string(slices[0].count) + " places");
    rank_of[i] = 0;
    load[0] += cost[i];
    --free_places[0];
  }

  std::vector<std::size_t> by_cost(n);
  std::iota(by_cost.begin(), by_cost.end(), std::size_t{0});
  std::stable_sort(by_cost.begin(), by_cost.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  for (std::size_t i : by_cost) {
    if (rank_of[i] != -1) continue;
    std::size_t best = ranks;
    for (std::size_t r = 0; r < ranks; ++r)
      if (free_places[r] > 0 && (best == ranks || load[r] < load[best])) best = r;
    rank_of[i] = static_cast<int>(best);
    load[best] += cost[i];
    --free_places[best];
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

}  // namespace codesign::cluster
