// How much the designs' different costs load the busiest rank (apps/bench/cost_spread.hpp): 1 when
// every cost is the same, a hand-enumerated case for both splits, and bad input refused; the same
// for the ranks' meeting at every decision (meeting_load_factor).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "bench/cost_spread.hpp"

namespace {

using codesign::cluster::busiest_load_factor;
using codesign::cluster::BusiestLoad;
using codesign::cluster::CostSample;
using codesign::cluster::DecisionCosts;
using codesign::cluster::meeting_load_factor;
using codesign::cluster::MeetingLoad;

TEST(CostSpread, EqualCostsGiveFactorOne) {
  const std::vector<CostSample> same = {{3, 0.2}, {7, 0.2}, {7, 0.2}, {40, 0.2}};
  for (int ranks : {1, 2, 3, 16})
    for (int threads : {1, 2, 3}) {
      const BusiestLoad f = busiest_load_factor(same, 40, ranks, threads, 50, 1);
      EXPECT_NEAR(f.contiguous, 1.0, 1e-12) << ranks << " ranks, " << threads << " threads";
      EXPECT_NEAR(f.by_cost, 1.0, 1e-12) << ranks << " ranks, " << threads << " threads";
    }
}

// Two designs, costs 1 and 3, equally likely; 4 environments on 2 ranks of one thread; each
// design's samples agree, so the split by cost predicts exactly. The normaliser is 2 rounds · mean
// cost 2 = 4.
// Contiguous: each rank's sum of two draws is 2, 4 or 6 with probabilities 1/4, 1/2, 1/4;
// P(max ≤ 2) = 1/16, P(max ≤ 4) = 9/16, so E[max] = 2/16 + 4 · 8/16 + 6 · 7/16 = 4.75: F = 1.1875.
// By cost, with k draws of 3 (binomial, 1 4 6 4 1 over 16): the busiest rank carries 2, 4, 4, 6, 6
// (k = 1: 3 + 1 against 1 + 1; k = 3: 3 + 3 against 3 + 1), E = 72/16 = 4.5: F = 1.125.
// Monte Carlo tolerance: a rank's maximum lies in [2, 6], so its standard deviation is at most 2,
// and over 40 000 draws 4 standard errors of the mean are 4 · 2 / 200 = 0.04 s, 0.01 in F.
TEST(CostSpread, TwoDesignsOnTwoRanksMatchTheEnumeration) {
  const std::vector<CostSample> two = {{0, 1.0}, {0, 1.0}, {1, 3.0}, {1, 3.0}};
  const BusiestLoad f = busiest_load_factor(two, 4, 2, 1, 40000, 20261204);
  EXPECT_NEAR(f.contiguous, 1.1875, 0.01);
  EXPECT_NEAR(f.by_cost, 1.125, 0.01);
  // One rank: nothing to split; two threads take 3s first, so the makespan is the enumerated
  // E[max over two longest-first bins] — here only the bound F ≥ 1 and F equal for both splits.
  const BusiestLoad one = busiest_load_factor(two, 4, 1, 2, 2000, 5);
  EXPECT_GE(one.contiguous, 1.0 - 1e-12);
  EXPECT_DOUBLE_EQ(one.contiguous, one.by_cost);
}

// Design 1: 1 and 3 (mean 2); design 2: 4 (mean 4). Overall mean 8/3; the designs' means 2 and 4
// (population standard deviation 1); within a design: distances 1, 1, 0, root mean square √(2/3).
TEST(CostSpread, SummaryByHand) {
  const codesign::cluster::CostSummary s = codesign::cluster::summarize_costs({{1, 1.0}, {2, 4.0}, {1, 3.0}});
  EXPECT_EQ(s.designs, 2u);
  EXPECT_NEAR(s.mean, 8.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.least_design, 2.0, 1e-12);
  EXPECT_NEAR(s.largest_design, 4.0, 1e-12);
  EXPECT_NEAR(s.across_designs, 1.0, 1e-12);
  EXPECT_NEAR(s.within_design, std::sqrt(2.0 / 3.0), 1e-12);
  EXPECT_THROW(codesign::cluster::summarize_costs({}), std::invalid_argument);
}

TEST(CostSpread, BadInputIsRefused) {
  const std::vector<CostSample> ok = {{0, 1.0}};
  EXPECT_THROW(busiest_load_factor({}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(busiest_load_factor({{0, -1.0}}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(busiest_load_factor({{0, std::nan("")}}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(busiest_load_factor(ok, 4, 2, 1, 0, 1), std::invalid_argument);
  EXPECT_THROW(busiest_load_factor(ok, 4, 5, 1, 10, 1), std::invalid_argument);  // more ranks than environments
  EXPECT_THROW(busiest_load_factor(ok, 4, 2, 0, 10, 1), std::invalid_argument);  // no thread
}

// Every environment with the same costs at each point (the points differ): a rank's time at a
// point is ⌈its environments / threads⌉ times the point's cost, the busiest rank's ⌈⌈ψ/N⌉/t⌉
// rounds, so both factors are 1 for any split.
TEST(MeetingLoad, EqualProfilesGiveOne) {
  const std::vector<double> p = {0.5, 0.1, 0.3, 0.0, 0.2};
  const std::vector<DecisionCosts> same = {{3, p}, {7, p}, {7, p}, {40, p}};
  for (int ranks : {1, 2, 3, 16})
    for (int threads : {1, 2, 3}) {
      const MeetingLoad m = meeting_load_factor(same, 40, ranks, threads, 50, 1);
      EXPECT_NEAR(m.lockstep, 1.0, 1e-12) << ranks << " ranks, " << threads << " threads";
      EXPECT_NEAR(m.run_ahead, 1.0, 1e-12) << ranks << " ranks, " << threads << " threads";
      // The busiest rank's busiest thread holds `rounds` environments at every point, the start
      // included: rounds · 0.5 over rounds · 1.1.
      EXPECT_NEAR(m.start, 0.5 / 1.1, 1e-12) << ranks << " ranks, " << threads << " threads";
      // Starts before the update: rank 0 (a largest slice) still carries its rounds' starts, so
      // the iteration's end is unchanged; the other ranks' starts take their busiest's rounds ·
      // 0.5: the rounds of rank 0 for every split tried (40 = 2·20, 8·3 + 8·2; 14+13+13 on 2 or 3
      // threads) but 13 of rank 0's 14 for 3 ranks of one thread.
      EXPECT_NEAR(m.prestarted, 1.0, 1e-12) << ranks << " ranks, " << threads << " threads";
      const double rounds_ratio = ranks == 3 && threads == 1 ? 13.0 / 14.0 : 1.0;
      EXPECT_NEAR(m.prestart, ranks == 1 ? 0.0 : rounds_ratio * 0.5 / 1.1, 1e-12)
          << ranks << " ranks, " << threads << " threads";
    }
}

// Two designs of one sample each: A costs 2 at the first decision, B 2 at the second (both 0 at
// the start), so each iteration total is 2 and the prediction (the mean, one sample per design)
// cannot tell them apart. Two environments on two ranks of one thread: a rank's total is always 2,
// so meeting only at the end takes 2 (run_ahead = 1 exactly, over 1 round · mean 2); meeting at
// every decision takes max(2, 2) + 0 = 2 when both drew the same design (probability 1/2) and
// 2 + 2 = 4 when they differ: E = 3, lockstep = 1.5. One rank of two threads: each point's
// makespan is the larger of the two costs, the same enumeration, and one rank has nothing to
// meet: both factors 1.5. Monte Carlo tolerance: a draw's time is 2 or 4 (standard deviation 1),
// so over 40 000 draws 4 standard errors are 4 / 200 = 0.02 s, 0.01 in the factor.
TEST(MeetingLoad, TwoDesignsOnTwoRanksMatchTheEnumeration) {
  const std::vector<DecisionCosts> two = {{0, {0.0, 2.0, 0.0}}, {1, {0.0, 0.0, 2.0}}};
  const MeetingLoad m = meeting_load_factor(two, 2, 2, 1, 40000, 20261205);
  EXPECT_NEAR(m.lockstep, 1.5, 0.01);
  EXPECT_DOUBLE_EQ(m.run_ahead, 1.0);
  const MeetingLoad one = meeting_load_factor(two, 2, 1, 2, 40000, 20261205);
  EXPECT_NEAR(one.lockstep, 1.5, 0.01);
  EXPECT_DOUBLE_EQ(one.lockstep, one.run_ahead);
  EXPECT_DOUBLE_EQ(m.start, 0.0);  // both start at no cost
}

// The start's share: A costs 1 at the start and 1 at the decision, B 3 and 1 (totals 2 and 4,
// mean 3). Two environments on two ranks of one thread: the start's meeting takes 1 when both drew
// A (probability 1/4), else 3: E = 2.5, start = 2.5 / (1 round · 3) = 5/6; the decision always
// takes 1, so lockstep = 3.5 / 3 = 7/6; meeting at the end takes the larger total, 2 or 4 with
// the same probabilities: 7/6 too. Tolerance: the start's time lies in [1, 3] (standard deviation
// at most 1), so 4 standard errors over 40 000 draws are 0.02 s, 0.007 in the factor.
TEST(MeetingLoad, TheStartsShareMatchesTheEnumeration) {
  const std::vector<DecisionCosts> two = {{0, {1.0, 1.0}}, {1, {3.0, 1.0}}};
  const MeetingLoad m = meeting_load_factor(two, 2, 2, 1, 40000, 20261206);
  EXPECT_NEAR(m.start, 5.0 / 6.0, 0.007);
  EXPECT_NEAR(m.lockstep, 7.0 / 6.0, 0.007);
  EXPECT_NEAR(m.run_ahead, 7.0 / 6.0, 0.007);
  EXPECT_NEAR(m.lockstep - m.start, 1.0 / 3.0, 1e-12);  // every draw's decision takes exactly 1
  // Rank 1 started before the update: its iteration is its decision's 1, rank 0's its whole total
  // (2 or 4, whichever design it drew, probability 1/2 each): prestarted = E[max(total, 1)] / 3 =
  // 3 / 3; rank 1's start, 1 or 3, gives prestart = 2 / 3. Tolerance as above (each a two-point
  // variable of standard deviation 1).
  EXPECT_NEAR(m.prestarted, 1.0, 0.007);
  EXPECT_NEAR(m.prestart, 2.0 / 3.0, 0.007);
  // With the update given: none (0) leaves rank 1 its whole total, as meeting at the end; an
  // update of 1 hides A's start and 1 of B's 3, so rank 1 takes 1 or 3 after it against rank 0's
  // 2 or 4: E[max] = (2 + 3 + 4 + 4) / 4 = 13/4, over 3; one beyond every start hides them all.
  EXPECT_NEAR(m.after_update, m.run_ahead, 1e-12);
  EXPECT_NEAR(meeting_load_factor(two, 2, 2, 1, 40000, 20261206, 1.0).after_update, 13.0 / 12.0, 0.007);
  const MeetingLoad hidden = meeting_load_factor(two, 2, 2, 1, 40000, 20261206, 5.0);
  EXPECT_DOUBLE_EQ(hidden.after_update, hidden.prestarted);
  EXPECT_THROW(meeting_load_factor(two, 2, 2, 1, 10, 1, -1.0), std::invalid_argument);
}

// 60 profiles of 11 points, costs uniform in [0, 1), of 10 designs (6 samples each).
std::vector<DecisionCosts> random_profiles(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> cost(0.0, 1.0);
  std::vector<DecisionCosts> samples;
  for (int k = 0; k < 60; ++k) {
    DecisionCosts d{k % 10, {}};
    for (int p = 0; p < 11; ++p) d.seconds.push_back(cost(rng));
    samples.push_back(d);
  }
  return samples;
}

// The maximum of the ranks' sums never exceeds the sum of the per-point maxima: run_ahead ≤
// lockstep for any costs; on random profiles of 10 designs, 40 environments, 1 to 8 ranks.
TEST(MeetingLoad, MeetingOnlyAtTheEndIsNeverSlower) {
  const std::vector<DecisionCosts> samples = random_profiles(7);
  for (int ranks : {1, 2, 4, 8})
    for (int threads : {1, 2}) {
      const MeetingLoad m = meeting_load_factor(samples, 40, ranks, threads, 200, 3);
      EXPECT_LE(m.run_ahead, m.lockstep + 1e-12) << ranks << " ranks, " << threads << " threads";
      if (ranks == 1) {
        EXPECT_DOUBLE_EQ(m.run_ahead, m.lockstep);
      }
    }
}

// The floor of any order of a rank's jobs. Every job 1 s, a start and 50 decisions (totals 51):
// 40 environments on 16 ranks of 2 threads, the busiest holding 3: max(51, 153 / 2) = 76.5 over
// the normaliser 2 rounds x 51: 0.75, where meeting at each decision takes 1; on 2 ranks of one
// thread both are 1. Two designs whose totals are 1 and 3 on one rank of 2 threads holding both
// environments: max(3, 4 / 2) = 3 when the draws differ (probability 1/2), 3 (both 3) or 1 (both 1)
// otherwise: E = 3/2 + 3/4 + 1/4 = 2.5 over 1 round x mean 2: 1.25 (Monte Carlo: a draw lies in
// [1, 3], so 4 standard errors over 40 000 draws are 0.02 s, 0.01 in the factor).
TEST(MeetingLoad, TheFloorMatchesTheCount) {
  const std::vector<double> p(51, 1.0);
  const std::vector<DecisionCosts> same = {{3, p}, {7, p}};
  const MeetingLoad busiest_of_three = meeting_load_factor(same, 40, 16, 2, 20, 1);
  EXPECT_NEAR(busiest_of_three.floor, 0.75, 1e-12);
  EXPECT_NEAR(busiest_of_three.run_ahead, 1.0, 1e-12);
  EXPECT_NEAR(meeting_load_factor(same, 40, 2, 1, 20, 1).floor, 1.0, 1e-12);
  const std::vector<DecisionCosts> two = {{0, {0.5, 0.5}}, {1, {1.0, 2.0}}};
  EXPECT_NEAR(meeting_load_factor(two, 2, 1, 2, 40000, 20261207).floor, 1.25, 0.01);
}

// No order of a rank's jobs beats the floor, the meeting at each decision within a rank included:
// floor <= run_ahead on random profiles of 10 designs, 40 environments, 1 to 16 ranks.
TEST(MeetingLoad, TheFloorIsNeverAboveMeetingAtTheEnd) {
  const std::vector<DecisionCosts> samples = random_profiles(11);
  for (int ranks : {1, 2, 4, 16})
    for (int threads : {1, 2, 3}) {
      const MeetingLoad m = meeting_load_factor(samples, 40, ranks, threads, 200, 5);
      EXPECT_LE(m.floor, m.run_ahead + 1e-12) << ranks << " ranks, " << threads << " threads";
    }
}

TEST(MeetingLoad, BadInputIsRefused) {
  const std::vector<DecisionCosts> ok = {{0, {1.0, 1.0}}};
  EXPECT_THROW(meeting_load_factor({}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor({{0, {}}}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor({{0, {1.0}}, {1, {1.0, 2.0}}}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor({{0, {1.0, -1.0}}}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor({{0, {std::nan("")}}}, 4, 2, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor(ok, 4, 2, 1, 0, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor(ok, 4, 5, 1, 10, 1), std::invalid_argument);
  EXPECT_THROW(meeting_load_factor(ok, 4, 2, 0, 10, 1), std::invalid_argument);
}

}  // namespace
