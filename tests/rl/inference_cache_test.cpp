// ActorCritic::InferenceCache: the rollout's reusable forward scratch keeps packed bf16 weights
// between calls; weights_changed() must make the next call use the current parameters.
#include <gtest/gtest.h>

#include "rl/actor_critic.hpp"
#include "rl/rng.hpp"

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
    Eigen::MatrixXf obs(6, 40);
    Rng data(4);
    for (Eigen::Index i = 0; i < obs.size(); ++i) obs(i) = static_cast<float>(data.normal());

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

}  // namespace
}  // namespace codesign::rl
