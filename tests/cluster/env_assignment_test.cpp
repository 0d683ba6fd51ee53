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
using codesign::cluster::BuildCosts;
using codesign::cluster::predict_costs;
using codesign::cluster::record_held;
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

// 1 to 48 environments on 1 to 9 ranks (never more ranks than environments), costs in [0.05, 1).
struct RandomCase {
  std::size_t n;
  int ranks;
  std::vector<EnvSlice> slices;
  std::vector<double> cost;
};
RandomCase random_case(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.05, 1.0);
  RandomCase c;
  c.n = 1 + rng() % 48;
  c.ranks = 1 + static_cast<int>(rng() % std::min<std::size_t>(c.n, 9));
  c.slices = env_slices(c.n, c.ranks);
  c.cost.resize(c.n);
  for (double& x : c.cost) x = u(rng);
  return c;
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
  for (int trial = 0; trial < 400; ++trial) {
    const auto [n, ranks, slices, cost] = random_case(rng);
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

// Each rank's total with its builds, recounted from the final order: a rank that steps k
// environments of a design it holds h simulators of builds max(0, k - h) simulators, and the
// design's model too if h = 0 < k (from its mesh where that is known).
std::vector<double> totals(const std::vector<double>& cost, const std::vector<EnvSlice>& slices,
                           const std::vector<std::size_t>& order, const BuildCosts& b) {
  std::vector<double> l = loads(cost, slices, order);
  for (std::size_t r = 0; r < slices.size(); ++r) {
    std::vector<int> k;
    for (std::size_t j = slices[r].first; j < slices[r].first + slices[r].count; ++j) {
      const int d = b.design[order[j]];
      if (d < 0) continue;
      if (k.size() <= static_cast<std::size_t>(d)) k.resize(static_cast<std::size_t>(d) + 1, 0);
      ++k[static_cast<std::size_t>(d)];
    }
    for (std::size_t d = 0; d < k.size(); ++d) {
      const int h = d < b.held[r].size() ? b.held[r][d] : 0;
      const bool mesh_known = d < b.meshed.size() && b.meshed[d];
      if (h == 0 && k[d] > 0) l[r] += mesh_known ? b.model_from_mesh : b.model;
      l[r] += std::max(0, k[d] - h) * b.simulator;
    }
  }
  return l;
}

// Four equal costs, designs 3, 8, 3, 8; rank 0 holds a simulator of 8, rank 1 one of 3 (model 0.5,
// simulator 0.25). Environment 0 (3): rank 0 would build 0.75, rank 1 nothing -> rank 1 (1).
// 1 (8): rank 0, nothing to build (0 < 1.75) -> rank 0 (1). 2 (3): rank 0 1 + 0.75, rank 1 1 + 0.25
// (its one simulator is taken) -> rank 1 (2.25). 3 (8): rank 1 is full -> rank 0, 1 + 0.25 (2.25).
// Without the builds the ties would deal 0 and 2 to rank 0, which holds neither.
TEST(AssignByCost, BuildsSendADesignToTheRankThatHoldsIt) {
  const std::vector<double> cost(4, 1.0);
  const auto slices = env_slices(4, 2);
  BuildCosts b{0.5, 0.25, {3, 8, 3, 8}, {std::vector<int>(9, 0), std::vector<int>(9, 0)}};
  b.held[0][8] = 1;
  b.held[1][3] = 1;
  const std::vector<std::size_t> order = assign_by_cost(cost, slices, {}, b);
  EXPECT_EQ(order, (std::vector<std::size_t>{1, 3, 0, 2}));
  EXPECT_EQ(totals(cost, slices, order, b), (std::vector<double>{2.25, 2.25}));
  EXPECT_EQ(assign_by_cost(cost, slices, {}), (std::vector<std::size_t>{0, 2, 1, 3}));
  // Afterwards each rank holds what it steps now, and keeps what it held.
  record_held(order, slices, b);
  EXPECT_EQ(b.held[0][8], 2);
  EXPECT_EQ(b.held[0][3], 0);
  EXPECT_EQ(b.held[1][3], 2);
  EXPECT_EQ(b.held[1][8], 0);
  // A rank with no row for a design yet grows one; a negative design builds nothing.
  BuildCosts grow{1.0, 1.0, {12, -1}, {{}, {}}};
  record_held({0, 1}, env_slices(2, 2), grow);
  std::vector<int> want(13, 0);
  want[12] = 1;
  EXPECT_EQ(grow.held[0], want);
  EXPECT_TRUE(grow.held[1].empty());
}

// A known mesh makes a design cheap to take up for a rank that has not built it. Four equal costs
// (1), designs 6, 6, 7, 8; rank 0 holds two simulators of 6, rank 1 nothing; a model costs 1 to
// mesh, 0.1 from a known mesh; simulators cost nothing. Meshes unknown: 0 -> rank 0 (1 < 2); 1:
// rank 0 2, rank 1 2 -> rank 0 (tie), full; 2 and 3 -> rank 1 (4: two meshings); no swap lowers
// the larger total (1 <-> 2 gives 3 and 4 at a larger sum). Design 6's mesh known: 0 -> rank 0 (1 <
// 1.1); 1 -> rank 1 (1.1 < 2); 2: rank 0 3, rank 1 3.1 -> rank 0, full; 3 -> rank 1 (3.1); swaps
// of 1 or 0 with 2 or 3 give a larger total of 4.
TEST(AssignByCost, AKnownMeshMakesADesignCheapToTakeUp) {
  const std::vector<double> cost(4, 1.0);
  const auto slices = env_slices(4, 2);
  BuildCosts b{1.0, 0.0, {6, 6, 7, 8}, {std::vector<int>(9, 0), std::vector<int>(9, 0)}};
  b.held[0][6] = 2;
  b.model_from_mesh = 0.1;
  const std::vector<std::size_t> unknown = assign_by_cost(cost, slices, {}, b);
  EXPECT_EQ(unknown, (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_EQ(totals(cost, slices, unknown, b), (std::vector<double>{2.0, 4.0}));
  b.meshed.assign(7, 0);
  b.meshed[6] = 1;
  const std::vector<std::size_t> known = assign_by_cost(cost, slices, {}, b);
  EXPECT_EQ(known, (std::vector<std::size_t>{0, 2, 1, 3}));
  const std::vector<double> t = totals(cost, slices, known, b);
  EXPECT_NEAR(t[0], 3.0, 1e-12);
  EXPECT_NEAR(t[1], 3.1, 1e-12);
  b.model_from_mesh = -0.1;
  EXPECT_THROW(assign_by_cost(cost, slices, {}, b), std::invalid_argument);
  b.model_from_mesh = std::numeric_limits<double>::infinity();
  EXPECT_THROW(assign_by_cost(cost, slices, {}, b), std::invalid_argument);
}

// Random costs, designs and held simulators: with both build costs zero the order is the plain
// rule's; with them, a permutation, each rank's environments in ascending order, that no swap
// improves (the swaps' rule, checked on totals recounted from the order). (The plain rule's
// bound on the spread does not carry over: once a rank's slice is full the others may have to take
// environments they must build for, so the builds are a heuristic's input, judged by whole runs:
// docs/journal/cluster.md, "Builds and wall thickness in the split".)
TEST(AssignByCost, RandomBuildsKeepThePlainRuleAtZeroCost) {
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> u(0.05, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    const auto [n, ranks, slices, cost] = random_case(rng);
    BuildCosts b{0.0, 0.0, std::vector<int>(n), std::vector<std::vector<int>>(static_cast<std::size_t>(ranks))};
    for (int& d : b.design) d = static_cast<int>(rng() % 12) - 1;  // -1: builds nothing
    for (std::vector<int>& row : b.held) {
      row.assign(rng() % 12, 0);
      for (int& h : row) h = static_cast<int>(rng() % 3);
    }
    EXPECT_EQ(assign_by_cost(cost, slices, {}, b), assign_by_cost(cost, slices, {})) << "trial " << trial;
    b.model = 0.5 * u(rng);
    b.simulator = 0.5 * u(rng);
    const std::vector<std::size_t> order = assign_by_cost(cost, slices, {}, b);
    std::vector<std::size_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t j = 0; j < n; ++j) ASSERT_EQ(sorted[j], j);
    for (const EnvSlice& sl : slices)
      for (std::size_t j = sl.first + 1; j < sl.first + sl.count; ++j) EXPECT_LT(order[j - 1], order[j]);
    // No swap of two environments between two ranks lowers the larger of their totals, or keeps it
    // and lowers their sum (recounted here from the order).
    const std::vector<double> l = totals(cost, slices, order, b);
    std::vector<std::size_t> rank_at(n);
    for (std::size_t r = 0; r < slices.size(); ++r)
      for (std::size_t j = slices[r].first; j < slices[r].first + slices[r].count; ++j) rank_at[j] = r;
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t q = p + 1; q < n; ++q) {
        const std::size_t a = rank_at[p], c = rank_at[q];
        if (a == c) continue;
        std::vector<std::size_t> swapped = order;
        std::swap(swapped[p], swapped[q]);
        const std::vector<double> m = totals(cost, slices, swapped, b);
        // The rule compares to 1e-9 s; flagged here only what lies clearly beyond that.
        const double was = std::max(l[a], l[c]), now = std::max(m[a], m[c]);
        EXPECT_FALSE(now < was - 2e-9 || (now <= was + 0.5e-9 && m[a] + m[c] < l[a] + l[c] - 2e-9))
            << "trial " << trial << ": swapping places " << p << " and " << q << " improves";
      }
  }
}

// Builds only tip the balance by their size: rank 0 holds design 5, but after 2 (cost 3) went to
// rank 0 and 1 (cost 1) to rank 1, environment 0 (cost 0.5, design 5) would total 3.5 on rank 0 and
// 1 + 0.5 + 0.2 + 0.1 = 1.8 on rank 1, which builds for it; rank 1 is then full and 3 goes to
// rank 0 (3.25).
TEST(AssignByCost, BuildsDoNotOutweighALargerImbalance) {
  const std::vector<double> cost = {0.5, 1.0, 3.0, 0.25};
  const auto slices = env_slices(4, 2);
  BuildCosts b{0.2, 0.1, {5, -1, -1, -1}, {std::vector<int>(6, 0), {}}};
  b.held[0][5] = 1;
  const std::vector<std::size_t> order = assign_by_cost(cost, slices, {}, b);
  EXPECT_EQ(order, (std::vector<std::size_t>{2, 3, 0, 1}));
  EXPECT_EQ(totals(cost, slices, order, b), (std::vector<double>{3.25, 1.8}));
}

// The swaps after the greedy: costs 1, 0.5, 0.45, 0.4 of designs 1, 2, 3, 4, rank 0 holding 2,
// model 0.1. The greedy: 0 to rank 0 (1.1); 1 to rank 1 (0.1 + 0.5 = 0.6 < 1.1, though rank 0
// holds it); 2 to rank 1 (1.15 < 1.2), now full; 3 to rank 0 (1.6). Swapping 1 and 3 keeps the
// larger total 1.6 (rank 0: 1 + 0.1 + 0.5) and lowers rank 1's to 0.45 + 0.4 + 0.2 = 1.05; no swap
// improves on that.
TEST(AssignByCost, SwapsGiveAHeldDesignBackToItsHolder) {
  const std::vector<double> cost = {1.0, 0.5, 0.45, 0.4};
  const auto slices = env_slices(4, 2);
  BuildCosts b{0.1, 0.0, {1, 2, 3, 4}, {std::vector<int>(5, 0), {}}};
  b.held[0][2] = 1;
  const std::vector<std::size_t> order = assign_by_cost(cost, slices, {}, b);
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3}));
  const std::vector<double> t = totals(cost, slices, order, b);
  EXPECT_NEAR(t[0], 1.6, 1e-12);
  EXPECT_NEAR(t[1], 1.05, 1e-12);
}

// Designs 0..4 are {1, 20 mm, 2.0..4.0 mm}, 5..9 {1, 22 mm, 2.0..4.0 mm} (fem/design.hpp's index):
// 0 and 5 share the thickness 2.0 mm, 1 and 6 2.5 mm; 2, 7, 12 are 3.0 mm.
TEST(PredictCosts, UnknownDesignsTakeTheMeanOfTheirWallThickness) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> cost(110, nan);
  EXPECT_TRUE(predict_costs(cost, {0, 1}).empty());  // nothing known yet
  cost[0] = 0.8;
  cost[5] = 0.6;
  cost[1] = 0.5;
  cost[2] = 0.3;
  const std::vector<double> p = predict_costs(cost, {0, 10, 6, 7, 3, -1, 110});
  ASSERT_EQ(p.size(), 7u);
  EXPECT_EQ(p[0], 0.8);               // known: its own
  EXPECT_DOUBLE_EQ(p[1], 0.7);        // 10 = {1, 24 mm, 2.0 mm}: mean of 0 and 5
  EXPECT_EQ(p[2], 0.5);               // 6 (2.5 mm): design 1's
  EXPECT_EQ(p[3], 0.3);               // 7 (3.0 mm): design 2's
  EXPECT_DOUBLE_EQ(p[4], 2.2 / 4.0);  // 3 (3.5 mm): none known of it, the mean of all four
  EXPECT_DOUBLE_EQ(p[5], 2.2 / 4.0);  // no design
  EXPECT_DOUBLE_EQ(p[6], 2.2 / 4.0);  // beyond the 110
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
  const std::vector<double> c(4, 1.0);
  const BuildCosts ok{0.1, 0.1, {0, 1, 2, 3}, {{}, {}}};
  EXPECT_NO_THROW(assign_by_cost(c, slices, {}, ok));
  BuildCosts bad = ok;
  bad.design.pop_back();  // 3 designs for 4 environments
  EXPECT_THROW(assign_by_cost(c, slices, {}, bad), std::invalid_argument);
  bad = ok;
  bad.held.pop_back();  // 1 row for 2 ranks
  EXPECT_THROW(assign_by_cost(c, slices, {}, bad), std::invalid_argument);
  EXPECT_THROW(record_held({0, 1, 2, 3}, slices, bad), std::invalid_argument);
  bad = ok;
  bad.model = -0.1;
  EXPECT_THROW(assign_by_cost(c, slices, {}, bad), std::invalid_argument);
  bad = ok;
  bad.simulator = std::numeric_limits<double>::infinity();
  EXPECT_THROW(assign_by_cost(c, slices, {}, bad), std::invalid_argument);
  bad = ok;
  bad.held[1] = {0, -1};
  EXPECT_THROW(assign_by_cost(c, slices, {}, bad), std::invalid_argument);
  BuildCosts short_order = ok;
  EXPECT_THROW(record_held({0, 1, 2}, slices, short_order), std::invalid_argument);  // a place left empty
}

}  // namespace
