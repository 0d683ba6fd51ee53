// ActorCritic::InferenceCache: the rollout's reusable forward scratch keeps packed bf16 weights
// between calls; weights_changed() must make the next call use the current parameters.
#include <gtest/gtest.h>

#include "rl/actor_critic.hpp"
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

// Issue 20 (docs/cluster.md, "The meeting at every decision, counted"): ranks that ran ahead would
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
