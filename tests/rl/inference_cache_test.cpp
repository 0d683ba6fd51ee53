// ActorCritic::InferenceCache: the rollout's reusable forward scratch keeps packed bf16 weights
// between calls; weights_changed() must make the next call use the current parameters.
#include <gtest/gtest.h>

#include "rl/actor_critic.hpp"
#include "rl/gaussian.hpp"
#include "rl/gemm.hpp"
#include "rl/rng.hpp"
#include "random_matrix.hpp"

namespace codesign::rl {
namespace {

TEST(InferenceCache, ReusedCacheMatchesFreshCallsAndFollowsWeightChanges) {
  for (MatmulPrecision p : {MatmulPrecision::Float32, MatmulPrecision::BFloat16}) {
    if (p == MatmulPrecision::BFloat16 && !bf16_gemm_available()) continue;
    // Hidden layers large enough for the blocked GEMMs (m >= 64, n >= 32, k >= 32).
    Rng init(3);
    ActorCritic model(6, 1, {96, 64}, {64, 96});
    model.init_orthogonal(init);
    model.set_matmul_precision(p);
    Rng data(4);
    const Eigen::MatrixXf obs = test::random_matrix(6, 40, data);

    ActorCritic::InferenceCache cache;
    for (int call = 0; call < 2; ++call) {  // second call reuses the packed weights
      Rng r1(9), r2(9);
      const auto fresh = model.act(obs, r1);
      const auto reused = model.act(obs, r2, cache);
      // Same arithmetic on the same packed operands: bit-identical.
      EXPECT_EQ(fresh.actions, reused.actions);
      EXPECT_EQ(fresh.values, reused.values);
      EXPECT_EQ(fresh.log_probs, reused.log_probs);
    }
    // Change every weight; after weights_changed() the cache must follow.
    model.actor().params() *= 1.5f;
    model.critic().params() *= 1.5f;
    cache.weights_changed();
    EXPECT_EQ(model.value(obs), model.value(obs, cache));
    Rng r1(5), r2(5);
    EXPECT_EQ(model.act(obs, r1).actions, model.act(obs, r2, cache).actions);
  }
}

// Whole rollouts on MPI ranks (core/run_ahead.hpp): an MPI rank runs its environments' rollouts on the ψ-wide
// batch with its own columns at their places and zeros elsewhere. That gives the one-process
// numbers if a column's action, value and log-probability depend on no other column's values:
// shown here for every kernel MlpT can take (blocked GEMMs in float32 and bf16 where the CPU has
// them, Eigen's products otherwise and with the fast GEMM off), at widths on either side of the
// blocked kernels' 32 columns. act_with(standard_normals(...)) is act() with the same draws.
TEST(InferenceCache, ColumnsDoNotDependOnTheOtherColumnsValues) {
  for (MatmulPrecision p : {MatmulPrecision::Float32, MatmulPrecision::BFloat16})
    for (bool fast : {true, false})
      for (Eigen::Index width : {4, 31, 40}) {
        if (p == MatmulPrecision::BFloat16 && (!bf16_gemm_available() || !fast)) continue;
        Rng init(3);
        ActorCritic model(6, 2, {96, 64}, {64, 96});
        model.init_orthogonal(init);
        model.set_matmul_precision(p);
        model.set_fast_gemm(fast);
        Rng data(4);
        const Eigen::MatrixXf obs = test::random_matrix(6, width, data);
        Rng draws(8), same(8);
        const Eigen::MatrixXd z = standard_normals(2, width, draws);
        ActorCritic::InferenceCache cache;
        const auto all = model.act_with(obs, z, cache);
        const auto sampled = model.act(obs, same, cache);
        EXPECT_EQ(all.actions, sampled.actions);
        EXPECT_EQ(all.log_probs, sampled.log_probs);
        EXPECT_EQ(draws.save(), same.save());
        // Keep every third column, from column 1 on; zero the others.
        Eigen::MatrixXf some = Eigen::MatrixXf::Zero(6, width);
        for (Eigen::Index j = 1; j < width; j += 3) some.col(j) = obs.col(j);
        const auto part = model.act_with(some, z, cache);
        const Eigen::RowVectorXf values = model.value(some, cache);
        for (Eigen::Index j = 1; j < width; j += 3) {
          EXPECT_EQ(part.actions.col(j), all.actions.col(j)) << "column " << j << " of " << width;
          EXPECT_EQ(part.values(j), all.values(j)) << "column " << j << " of " << width;
          EXPECT_EQ(part.log_probs(j), all.log_probs(j)) << "column " << j << " of " << width;
          EXPECT_EQ(values(j), all.values(j)) << "column " << j << " of " << width;
        }
      }
}

// Ranks that run ahead (docs/journal/cluster.md, "The meeting at every decision, counted") would
// compute the policy on their own few columns. With the blocked kernels (batches of >= 32 columns)
// a column's action, value and log-probability do not depend on how many columns are computed with
// it, edge tiles included (33); the paper's networks, both precisions. (Below 32 columns MlpT takes
// Eigen's product, and a one-off probe saw the last bits differ: not asserted.)
TEST(InferenceCache, BlockedKernelColumnsDoNotDependOnTheBatchWidth) {
  if (!fast_gemm_available()) GTEST_SKIP() << "no AVX-512: MlpT uses Eigen's product only";
  for (MatmulPrecision p : {MatmulPrecision::Float32, MatmulPrecision::BFloat16}) {
    if (p == MatmulPrecision::BFloat16 && !bf16_gemm_available()) continue;
    Rng init(3);
    ActorCritic model(3, 1, {512, 512, 512}, {512, 512, 512}, -2.0f);
    model.init_orthogonal(init);
    model.set_matmul_precision(p);
    Rng data(4);
    const Eigen::MatrixXf obs = test::random_matrix(3, 72, data);
    ActorCritic::InferenceCache cache;
    Rng r0(9);
    const auto full = model.act(obs, r0, cache);
    for (int w : {32, 33, 40}) {
      for (int start = 0; start + w <= 72; start += w) {
        ActorCritic::InferenceCache own;
        Rng r(9);
        for (int i = 0; i < start; ++i) r.normal();  // act_dim 1: the draws of the columns before
        const auto a = model.act(obs.middleCols(start, w), r, own);
        EXPECT_EQ(a.actions, full.actions.middleCols(start, w)) << "width " << w << ", from " << start;
        EXPECT_EQ(a.values, full.values.segment(start, w)) << "width " << w << ", from " << start;
        EXPECT_EQ(a.log_probs, full.log_probs.segment(start, w)) << "width " << w << ", from " << start;
      }
    }
  }
}

}  // namespace
}  // namespace codesign::rl
