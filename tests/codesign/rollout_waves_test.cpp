// The choice of a share's waves (codesign/rollout_waves.hpp), against values worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "codesign/rollout_waves.hpp"

namespace {

using codesign::core::longest_first_makespan;
using codesign::core::next_wave;
using codesign::core::WaveEnv;

std::vector<WaveEnv> started(const std::vector<double>& step_costs, int jobs) {
  std::vector<WaveEnv> e;
  for (double c : step_costs) e.push_back({jobs, true, 0.0, c});
  return e;
}

TEST(RolloutWaves, LongestFirstMakespan) {
  // {3, 2, 2} on 2 threads: 3 | 2 + 2 -> 4. Five equal jobs on 2: 3 and 2 -> 3.
  EXPECT_EQ(longest_first_makespan({2, 3, 2}, 2), 4.0);
  EXPECT_EQ(longest_first_makespan({1, 1, 1, 1, 1}, 2), 3.0);
  EXPECT_EQ(longest_first_makespan({5}, 4), 5.0);
  EXPECT_EQ(longest_first_makespan({}, 3), 0.0);
  EXPECT_THROW(longest_first_makespan({1}, 0), std::invalid_argument);
}

TEST(RolloutWaves, ThreeEqualEnvironmentsOnTwoThreadsGoTwoAtATimeWhileAPassCostsLessThanAStep) {
  // Rates: all three 3 / (2 + p), two of them 2 / (1 + p): two win while p < 1 step.
  EXPECT_EQ(next_wave(started({1, 1, 1}, 10), 2, 0.0), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(next_wave(started({1, 1, 1}, 10), 2, 0.5), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(next_wave(started({1, 1, 1}, 10), 2, 1.5), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(RolloutWaves, OneCostlyEnvironmentBesideTwoCheapOnesKeepsAllThreeInTheWave) {
  // Costs 2, 1, 1 on 2 threads: all three pack 2 | 1 + 1 (4 per 2 s); the two with most work left,
  // 2 and 1, give 3 per 2 s.
  EXPECT_EQ(next_wave(started({1, 2, 1}, 10), 2, 0.0), (std::vector<std::size_t>{1, 0, 2}));
}

TEST(RolloutWaves, ThreadsThatDivideTheEnvironmentsTakeThemAllEveryDecision) {
  EXPECT_EQ(next_wave(started(std::vector<double>(40, 0.004), 50), 2, 0.0006).size(), 40u);
  EXPECT_EQ(next_wave(started(std::vector<double>(20, 0.004), 50), 1, 0.0).size(), 20u);
  EXPECT_EQ(next_wave(started({1, 1}, 3), 4, 0.0).size(), 2u);  // fewer than the threads
  // Nothing measured yet (every cost 0): the largest wave.
  EXPECT_EQ(next_wave(started({0, 0, 0}, 5), 2, 0.0).size(), 3u);
  // Five equal on 2 threads: four at a time (4 per 2 steps) beat five (5 per 3).
  EXPECT_EQ(next_wave(started({1, 1, 1, 1, 1}, 10), 2, 0.0).size(), 4u);
}

TEST(RolloutWaves, MostWorkLeftFirstAndStartsCounted) {
  std::vector<WaveEnv> e = started({1, 1, 1}, 10);
  e[0].jobs_left = 5;
  EXPECT_EQ(next_wave(e, 2, 0.0), (std::vector<std::size_t>{1, 2}));
  // A start of 3 s to come and 10 steps (13 s left) before two started ones with 10 s left: all
  // three pack 3 | 1 + 1 (5 per 3 s) against 3 | 1 (4 per 3 s).
  std::vector<WaveEnv> f = started({1, 1}, 10);
  f.insert(f.begin() + 1, WaveEnv{11, false, 3.0, 1.0});
  EXPECT_EQ(next_wave(f, 2, 0.0), (std::vector<std::size_t>{1, 0, 2}));
  // Done environments are left out; none left: an empty wave.
  e[1].jobs_left = 0;
  EXPECT_EQ(next_wave(e, 2, 0.0), (std::vector<std::size_t>{2, 0}));
  EXPECT_TRUE(next_wave(started({1, 1}, 0), 2, 0.0).empty());
}

TEST(RolloutWaves, AWholeRolloutOfThreeOnTwoThreadsTakesOneAndAHalfStepsPerDecision) {
  // 3 environments, each a start and 50 decisions of cost 1: 153 jobs two at a time, the last
  // alone: 77 waves of 1 s, against 51 meetings of 2 s decision by decision.
  std::vector<WaveEnv> e(3, WaveEnv{51, false, 1.0, 1.0});
  int waves = 0;
  double wall = 0.0;
  for (;;) {
    const std::vector<std::size_t> w = next_wave(e, 2, 0.0);
    if (w.empty()) break;
    std::vector<double> costs;
    for (std::size_t i : w) {
      costs.push_back(e[i].started ? e[i].step_cost : e[i].start_cost);
      e[i].started = true;
      --e[i].jobs_left;
    }
    wall += longest_first_makespan(costs, 2);
    ++waves;
  }
  EXPECT_EQ(waves, 77);
  EXPECT_EQ(wall, 77.0);
}

TEST(RolloutWaves, RefusesNoThreadsAndBadCosts) {
  EXPECT_THROW(next_wave(started({1}, 2), 0, 0.0), std::invalid_argument);
  EXPECT_THROW(next_wave(started({-1}, 2), 1, 0.0), std::invalid_argument);
  EXPECT_THROW(next_wave(started({std::nan("")}, 2), 1, 0.0), std::invalid_argument);
  EXPECT_THROW(next_wave(started({1}, 2), 1, std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
