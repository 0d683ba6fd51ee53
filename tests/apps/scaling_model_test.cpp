// The scaling model of apps/bench/scaling_model.hpp against values worked out by hand.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "bench/scaling_model.hpp"

namespace {

using codesign::cluster::iteration_seconds;
using codesign::cluster::ScalingCosts;

ScalingCosts paper_like() {
  ScalingCosts c;
  c.environments = 40;
  c.threads_per_rank = 2;
  c.env_collect_s = 0.25;
  c.exchanges = 51;
  c.exchange_s = 1e-5;
  c.update_s = 0.3;
  c.policy_s = 0.05;
  c.distribution_s = 0.001;
  return c;
}

TEST(ScalingModel, MatchesTheHandWorkedIterationTimes) {
  const ScalingCosts c = paper_like();
  const double serial = 0.3 + 0.05 + 0.001;
  // 1 rank: 40 environments on 2 threads = 20 rounds of 0.25 s, no messages.
  EXPECT_NEAR(iteration_seconds(c, 1), 20 * 0.25 + serial, 1e-12);
  // 16 ranks: the busiest holds 3 (40 = 8·3 + 8·2) -> 2 rounds; 15 · 51 exchanges of 10 µs.
  EXPECT_NEAR(iteration_seconds(c, 16), 2 * 0.25 + 15 * 51 * 1e-5 + serial, 1e-12);
  // 40 ranks: one environment each -> 1 round; 39 · 51 exchanges.
  EXPECT_NEAR(iteration_seconds(c, 40), 0.25 + 39 * 51 * 1e-5 + serial, 1e-12);
  // 3 ranks of 1 thread: the busiest holds 14 -> 14 rounds.
  ScalingCosts one = c;
  one.threads_per_rank = 1;
  EXPECT_NEAR(iteration_seconds(one, 3), 14 * 0.25 + 2 * 51 * 1e-5 + serial, 1e-12);
}

TEST(ScalingModel, CollectionRoundsAreTheBusiestRanksEnvironmentsOverItsThreads) {
  using codesign::cluster::collection_rounds;
  EXPECT_EQ(collection_rounds(40, 1, 2), 20u);   // 40 on one rank of 2 threads
  EXPECT_EQ(collection_rounds(40, 16, 2), 2u);   // the busiest of 16 holds 3
  EXPECT_EQ(collection_rounds(40, 3, 1), 14u);   // 14 + 13 + 13
  EXPECT_EQ(collection_rounds(40, 40, 2), 1u);   // one each, fewer than the threads
  EXPECT_THROW(collection_rounds(40, 2, 0), std::invalid_argument);
  EXPECT_THROW(collection_rounds(40, 41, 1), std::invalid_argument);
}

TEST(ScalingModel, ASpreadUpdateDividesOnlyTheUpdateByTheRanks) {
  ScalingCosts c = paper_like();
  c.update_spread = true;
  // 1 rank: as before (the whole update on the one rank).
  EXPECT_NEAR(iteration_seconds(c, 1), 20 * 0.25 + 0.3 + 0.05 + 0.001, 1e-12);
  // 16 ranks: 2 rounds, 15 · 51 exchanges, the update 0.3 / 16; policy and distribution stay whole.
  EXPECT_NEAR(iteration_seconds(c, 16), 2 * 0.25 + 15 * 51 * 1e-5 + 0.3 / 16 + 0.05 + 0.001, 1e-12);
}

TEST(ScalingModel, ASpreadUpdatePaysItsGradientsLeastMessagesPerMinibatch) {
  ScalingCosts c = paper_like();
  c.update_spread = true;
  c.update_minibatches = 20;       // e.g. 2.5 epochs of 8 minibatches
  c.gradient_transfer_s = 1.5e-3;  // one gradient between two ranks
  // 1 rank: no messages (2 · 0/1).
  EXPECT_NEAR(iteration_seconds(c, 1), 20 * 0.25 + 0.3 + 0.05 + 0.001, 1e-12);
  // 2 ranks: 20 rounds → 10; each minibatch moves 2 · 1/2 gradient: 20 · 1.5 ms = 30 ms.
  EXPECT_NEAR(iteration_seconds(c, 2), 10 * 0.25 + 51 * 1e-5 + 0.3 / 2 + 20 * 1.5e-3 + 0.05 + 0.001, 1e-12);
  // 16 ranks: 2 · 15/16 gradients per minibatch: 20 · 1.875 · 1.5 ms = 56.25 ms.
  EXPECT_NEAR(iteration_seconds(c, 16), 2 * 0.25 + 15 * 51 * 1e-5 + 0.3 / 16 + 0.05625 + 0.05 + 0.001, 1e-12);
  // The messages belong to the spread update only: on rank 0 the update is u whatever g and y.
  c.update_spread = false;
  EXPECT_NEAR(iteration_seconds(c, 16), 2 * 0.25 + 15 * 51 * 1e-5 + 0.3 + 0.05 + 0.001, 1e-12);
  // A share that computes 1.6 times slower per sample than the whole minibatch: e · u / N.
  c.update_spread = true;
  c.update_share_cost = 1.6;
  EXPECT_NEAR(iteration_seconds(c, 16), 2 * 0.25 + 15 * 51 * 1e-5 + 1.6 * 0.3 / 16 + 0.05625 + 0.05 + 0.001, 1e-12);
  c.gradient_transfer_s = -1e-3;
  EXPECT_THROW(iteration_seconds(c, 2), std::invalid_argument);
  c.gradient_transfer_s = 1e-3;
  c.update_share_cost = -1.0;
  EXPECT_THROW(iteration_seconds(c, 2), std::invalid_argument);
}

TEST(ScalingModel, TheBusiestRanksFactorScalesOnlyTheCollectionRounds) {
  ScalingCosts c = paper_like();
  c.collect_factor = 1.5;
  // 16 ranks: 1.5 · 2 rounds of 0.25 s; messages, update, policy and distribution unchanged.
  EXPECT_NEAR(iteration_seconds(c, 16), 1.5 * 2 * 0.25 + 15 * 51 * 1e-5 + 0.3 + 0.05 + 0.001, 1e-12);
  c.collect_factor = -0.1;
  EXPECT_THROW(iteration_seconds(c, 2), std::invalid_argument);
}

// The ranks' starts during rank 0's update: they cost the iteration only where they outlast the
// update, and nothing on one rank (which has no other rank to start early).
TEST(ScalingModel, StartsDuringTheUpdateCostOnlyWhatOutlastsIt) {
  ScalingCosts c = paper_like();
  const double plain = iteration_seconds(c, 16);
  c.prestart_s = 0.2;  // under the update's 0.3 s
  EXPECT_DOUBLE_EQ(iteration_seconds(c, 16), plain);
  c.prestart_s = 0.45;  // 0.15 s over it
  EXPECT_NEAR(iteration_seconds(c, 16), plain + 0.15, 1e-12);
  EXPECT_DOUBLE_EQ(iteration_seconds(c, 1), iteration_seconds(paper_like(), 1));
  c.prestart_s = -0.1;
  EXPECT_THROW(iteration_seconds(c, 16), std::invalid_argument);
}

// A whole run projected iteration by iteration: 40 environments, the run on 2 threads (20 rounds),
// 16 ranks of 2 threads (2 rounds): each iteration's collection less its policy scales by 2/20.
// Iteration 1: collect 4.2, policy 0.2, update 0.1 -> s = 0.4: 0.8 · 0.4 + 0.2 + max(0.1, 0.5 · 0.4)
// = 0.72; iteration 2: 2.2, 0.2, 0.5 -> s = 0.2: 0.16 + 0.2 + max(0.5, 0.1) = 0.86. On one rank of
// 2 threads (s = 4.0 and 2.0) P has no other rank: 3.2 + 0.3 + 1.6 + 0.7 = 5.8.
TEST(ScalingModel, AWholeRunIsProjectedIterationByIteration) {
  using codesign::cluster::projected_run_seconds;
  using codesign::cluster::RunIteration;
  const std::vector<RunIteration> run = {{4.2, 0.2, 0.1}, {2.2, 0.2, 0.5}};
  EXPECT_NEAR(projected_run_seconds(run, 40, 2, 16, 2, 0.8, 0.5), 0.72 + 0.86, 1e-12);
  EXPECT_NEAR(projected_run_seconds(run, 40, 2, 1, 2, 0.8, 0.5), 5.8, 1e-12);
  EXPECT_THROW(projected_run_seconds({}, 40, 2, 16, 2, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(projected_run_seconds({{1.0, 0.1, -0.1}}, 40, 2, 16, 2, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(projected_run_seconds(run, 40, 2, 41, 2, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(projected_run_seconds(run, 40, 2, 16, 2, -1.0, 0.0), std::invalid_argument);
}

TEST(ScalingModel, NeverFasterThanItsSerialPartAndRefusesBadInput) {
  const ScalingCosts c = paper_like();
  for (int n = 1; n <= 40; ++n) {
    EXPECT_GT(iteration_seconds(c, n), c.update_s + c.policy_s + c.distribution_s + c.env_collect_s - 1e-12);
  }
  EXPECT_THROW(iteration_seconds(c, 0), std::invalid_argument);
  EXPECT_THROW(iteration_seconds(c, 41), std::invalid_argument);
  ScalingCosts bad = c;
  bad.threads_per_rank = 0;
  EXPECT_THROW(iteration_seconds(bad, 2), std::invalid_argument);
  bad = c;
  bad.exchange_s = -1.0;
  EXPECT_THROW(iteration_seconds(bad, 2), std::invalid_argument);
}

}  // namespace
