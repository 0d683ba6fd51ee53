// How the ψ environments of an iteration are shared out over MPI ranks (cluster/env_assignment.hpp):
// how many each rank steps (env_slice: contiguous slices covering every environment once, sizes
// differing by at most one, the larger first; rank counts that leave a rank without an environment
// refused) and which ones (assign_by_cost: the greedy longest-processing-time rule with the slices'
// sizes as capacities, telemetry's environments pinned to their place on rank 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "cluster/env_assignment.hpp"

namespace {

using codesign::cluster::assign_by_cost;
using codesign::cluster::env_slice;
using codesign::cluster::env_slices;
using codesign::cluster::EnvSlice;

std::vector<double> loads(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                          const std::vector<std::size_t>& order) {
  std::vector<double> l;
  for (const EnvSlice& s : slices) {
    double sum = 0.0;
    for (std::size_t j = s.first; j < s.first + s.count; ++j) sum += cost[order[j]];
    l.push_back(sum);
  }
  return l;
}

TEST(EnvSlice, SlicesCoverEveryEnvironmentOnceInOrder) {
  for (std::size_t n : {1u, 2u, 4u, 7u, 40u, 41u}) {
    for (int ranks = 1; ranks <= static_cast<int>(std::min<std::size_t>(n, 9)); ++ranks) {
      std::size_t next = 0, largest = 0, smallest = n;
      for (int r = 0; r < ranks; ++r) {
        const EnvSlice s = env_slice(n, r, ranks);
        EXPECT_EQ(s.first, next) << n << " envs, rank " << r << " of " << ranks;
        EXPECT_GE(s.count, 1u);
        if (r > 0) {
          EXPECT_LE(s.count, env_slice(n, r - 1, ranks).count);  // the larger slices first
        }
        largest = std::max(largest, s.count);
        smallest = std::min(smallest, s.count);
        next = s.first + s.count;
      }
      EXPECT_EQ(next, n);
      EXPECT_LE(largest - smallest, 1u);
      const std::vector<EnvSlice> all = env_slices(n, ranks);  // every rank's env_slice, rank 0 first
      ASSERT_EQ(all.size(), static_cast<std::size_t>(ranks));
      for (int r = 0; r < ranks; ++r) {
        EXPECT_EQ(all[static_cast<std::size_t>(r)].first, env_slice(n, r, ranks).first);
        EXPECT_EQ(all[static_cast<std::size_t>(r)].count, env_slice(n, r, ranks).count);
      }
    }
  }
  // 40 environments (the paper's ψ) on 16 ranks: 8 ranks of 3, then 8 of 2.
  EXPECT_EQ(env_slice(40, 7, 16).count, 3u);
  EXPECT_EQ(env_slice(40, 8, 16).count, 2u);
  EXPECT_EQ(env_slice(40, 8, 16).first, 24u);
}

TEST(EnvSlice, RankCountsThatLeaveARankEmptyAreRefused) {
  EXPECT_THROW(env_slice(4, 0, 5), std::invalid_argument);
  EXPECT_THROW(env_slice(4, 0, 0), std::invalid_argument);
  EXPECT_THROW(env_slice(4, 2, 2), std::invalid_argument);
  EXPECT_THROW(env_slice(4, -1, 2), std::invalid_argument);
  EXPECT_THROW(env_slices(4, 5), std::invalid_argument);
  EXPECT_THROW(env_slices(4, 0), std::invalid_argument);
}

// Worked by hand: six environments on two ranks of three places, environment 0 pinned (cost 1).
// Costliest first: 1 (9) to rank 1 (load 0 < 1); 2 (8) to rank 0 (1 < 9); 4 (7) to rank 0 (9 = 9,
// the lower rank; now full); 5 (3) and 3 (2) to rank 1. Loads 16 and 14, where the contiguous
// slices {0, 1, 2} and {3, 4, 5} would carry 18 and 12.
TEST(AssignByCost, HandWorkedSplitOfSixOverTwoRanks) {
  const std::vector<double> cost = {1, 9, 8, 2, 7, 3};
  const auto slices = env_slices(6, 2);
  const std::vector<std::size_t> order = assign_by_cost(cost, slices, {0});
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 2, 4, 1, 3, 5}));
  EXPECT_EQ(loads(cost, slices, order), (std::vector<double>{16, 14}));
  // Without the pin: 1 (9) to rank 0 (0 = 0, the lower rank); 2 (8) to rank 1; 4 (7) to rank 1
  // (8 < 9); 5 (3) and 3 (2) to rank 0 (9, then 12 < 15), now full; 0 (1) to rank 1.
  const std::vector<std::size_t> free_order = assign_by_cost(cost, slices, {});
  EXPECT_EQ(free_order, (std::vector<std::size_t>{1, 3, 5, 0, 2, 4}));
  EXPECT_EQ(loads(cost, slices, free_order), (std::vector<double>{14, 16}));
}

// Ties go to the lower index first and to the lower rank: five equal costs on 3 + 2 places deal
// 0 to rank 0, 1 to rank 1, 2 to rank 0, 3 to rank 1, 4 to rank 0.
TEST(AssignByCost, TiesDealInIndexAndRankOrder) {
  const std::vector<std::size_t> order = assign_by_cost(std::vector<double>(5, 0.25), env_slices(5, 2), {});
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 2, 4, 1, 3}));
  // One rank: the identity, whatever the costs.
  EXPECT_EQ(assign_by_cost({3, 1, 2}, env_slices(3, 1), {0}), (std::vector<std::size_t>{0, 1, 2}));
}

// Random costs: a permutation; pins at their own place; each rank's others in ascending order; and
// the greedy rule's bound for these capacities: the busiest rank carries at most the largest cost
// more than the least busy (ranks that filled up took their last environment while least busy;
// the others then took only environments no costlier than every one before).
TEST(AssignByCost, RandomCostsGiveAPermutationWithinTheGreedyBound) {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> u(0.05, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const std::size_t n = 1 + rng() % 48;
    const int ranks = 1 + static_cast<int>(rng() % std::min<std::size_t>(n, 9));
    const auto slices = env_slices(n, ranks);
    std::vector<double> cost(n);
    for (double& c : cost) c = u(rng);
    const bool pin = trial % 2 == 1;
    const std::vector<std::size_t> pinned = pin ? std::vector<std::size_t>{0} : std::vector<std::size_t>{};
    const std::vector<std::size_t> order = assign_by_cost(cost, slices, pinned);
    std::vector<std::size_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t j = 0; j < n; ++j) ASSERT_EQ(sorted[j], j);
    if (pin) {
      EXPECT_EQ(order[0], 0u);
    }
    for (const EnvSlice& s : slices)
      for (std::size_t j = s.first + 1; j < s.first + s.count; ++j) EXPECT_LT(order[j - 1], order[j]);
    if (!pin) {
      const std::vector<double> l = loads(cost, slices, order);
      const double spread = *std::max_element(l.begin(), l.end()) - *std::min_element(l.begin(), l.end());
      EXPECT_LE(spread, *std::max_element(cost.begin(), cost.end()) + 1e-12)
          << "trial " << trial << ": " << n << " environments, " << ranks << " ranks";
    }
  }
}

TEST(AssignByCost, BadInputIsRefused) {
  const auto slices = env_slices(4, 2);
  EXPECT_THROW(assign_by_cost({1, 1, 1}, slices, {}), std::invalid_argument);           // 3 costs, 4 places
  EXPECT_THROW(assign_by_cost({1, -1, 1, 1}, slices, {}), std::invalid_argument);       // negative
  EXPECT_THROW(assign_by_cost({1, std::nan(""), 1, 1}, slices, {}), std::invalid_argument);
  EXPECT_THROW(assign_by_cost({1, std::numeric_limits<double>::infinity(), 1, 1}, slices, {}), std::invalid_argument);
  EXPECT_THROW(assign_by_cost({1, 1, 1, 1}, slices, {2}), std::invalid_argument);       // not on rank 0's places
  EXPECT_THROW(assign_by_cost({1, 1, 1, 1}, slices, {1, 1}), std::invalid_argument);    // repeated
  EXPECT_THROW(assign_by_cost({1, 1, 1, 1}, {{0, 2}, {3, 2}}, {}), std::invalid_argument);  // a gap
  EXPECT_THROW(assign_by_cost({}, {}, {}), std::invalid_argument);                      // no rank
}

}  // namespace
