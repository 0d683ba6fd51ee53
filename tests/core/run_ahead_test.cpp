// Whole rollouts run by shares of the environments alone (run_ahead.hpp), as MPI ranks run them,
// against the one-process step-by-step rollout: the same numbers, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/outer_loop.hpp"
#include "core/run_ahead.hpp"
#include "tiny_loop.hpp"

namespace {

using namespace codesign;
using namespace codesign::core;
using test_loops::TinyLoop;
using test_loops::tiny_loop;

// The environments split into shares, each with a pool and forward-pass cache of its own (as a
// rank has), each environment at its place in the ψ-wide batch. Only whole rollouts: a step-by-step
// call is a test failure.
class SharedOutPool final : public EnvPool, public RunAhead {
 public:
  // threads > 1 with vary: each share's pool changes how many of its threads step at every start,
  // step and environment its calling thread steps (1, 2, ... threads, round and round), in the
  // middle of a step too, as an MPI rank's pool does when threads are lent to it.
  SharedOutPool(const TinyLoop& s, std::vector<std::vector<std::size_t>> shares, std::size_t threads = 1, bool vary = false)
      : sims_(std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver)), shares_(std::move(shares)), vary_(vary) {
    for (const auto& places : shares_) {
      pools_.push_back(std::make_unique<ThreadEnvPool>(sims_, s.loop.task, places.size(), threads));
      n_ += places.size();
    }
    caches_.resize(shares_.size());
  }
  std::size_t size() const override { return n_; }
  const rl::EnvSpec& spec() const override { return pools_.front()->spec(); }
  Eigen::MatrixXd start(const std::vector<EpisodeSetup>&) override { throw std::logic_error("start() called"); }
  const rl::VecStepResult& step(const Eigen::MatrixXd&, bool) override { throw std::logic_error("step() called"); }
  int last_in_band(std::size_t) const override { throw std::logic_error("last_in_band() called"); }
  double settle_seconds() const override { return 0.0; }
  double step_seconds() const override { return 0.0; }
  double build_seconds() const override { return 0.0; }
  void set_step_observer(std::size_t, StepObserver, int) override {}
  std::vector<double> work_since_start() const override { return std::vector<double>(n_, 0.0); }
  RunAhead* run_ahead() override { return this; }

  ShareRollout rollout(const std::vector<EpisodeSetup>& setups, const rl::ActorCritic& model,
                       const std::vector<Eigen::MatrixXd>& normals, double gamma) override {
    ++rollouts;
    ShareRollout all = empty_share(static_cast<int>(normals.size()), n_, spec().observation.dim(), spec().action.dim());
    for (std::size_t s = 0; s < shares_.size(); ++s) {
      std::vector<EpisodeSetup> mine;
      for (std::size_t p : shares_[s]) mine.push_back(setups[p]);
      ThreadEnvPool& pool = *pools_[s];
      std::size_t k = 0;
      if (vary_)
        pool.set_lender([&] {
          const std::size_t n = 1 + k++ % pool.threads();
          used = std::max(used, n);
          return n;
        });
      place_share(run_share(pool, mine, model, caches_[s], shares_[s], n_, normals, gamma), shares_[s], all);
      pool.set_lender({});
    }
    return all;
  }
  int rollouts = 0;
  std::size_t used = 1;  // the most threads a share stepped with

 private:
  std::shared_ptr<SimulatorPool> sims_;
  std::vector<std::vector<std::size_t>> shares_;
  std::vector<std::unique_ptr<ThreadEnvPool>> pools_;
  std::vector<rl::ActorCritic::InferenceCache> caches_;
  std::size_t n_ = 0;
  bool vary_ = false;
};

// Environment i in share i % k, each share's places in falling order: neither contiguous nor sorted.
std::vector<std::vector<std::size_t>> interleaved(std::size_t n, std::size_t k) {
  std::vector<std::vector<std::size_t>> shares(k);
  for (std::size_t i = n; i-- > 0;) shares[i % k].push_back(i);
  return shares;
}

void expect_same_iterations(const TinyLoop& s, std::size_t shares, int iterations, std::size_t threads = 1,
                            bool vary = false) {
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  const auto n = static_cast<std::size_t>(s.loop.codesign.designs_per_update);
  OuterLoop one(s.loop, std::make_unique<ThreadEnvPool>(sims, s.loop.task, n, 1));
  auto pool = std::make_unique<SharedOutPool>(s, interleaved(n, shares), threads, vary);
  SharedOutPool& split_pool = *pool;
  OuterLoop split(s.loop, std::move(pool));
  for (int k = 0; k < iterations; ++k) {
    const IterationReport a = one.iterate(), b = split.iterate();
    ASSERT_EQ(a.episodes.size(), b.episodes.size()) << "iteration " << k;
    for (std::size_t e = 0; e < a.episodes.size(); ++e) {
      EXPECT_EQ(a.episodes[e].env, b.episodes[e].env);
      EXPECT_EQ(a.episodes[e].episode_return, b.episodes[e].episode_return);
      EXPECT_EQ(a.episodes[e].decisions, b.episodes[e].decisions);
      EXPECT_EQ(a.episodes[e].in_band, b.episodes[e].in_band);
      EXPECT_EQ(a.episodes[e].reason, b.episodes[e].reason);
      EXPECT_EQ(a.episodes[e].first, b.episodes[e].first);
    }
    const rl::RolloutBuffer &x = one.buffer(), &y = split.buffer();
    EXPECT_TRUE(x.observations() == y.observations()) << "iteration " << k;
    EXPECT_TRUE(x.actions() == y.actions()) << "iteration " << k;
    EXPECT_TRUE(x.rewards() == y.rewards()) << "iteration " << k;
    EXPECT_TRUE(x.episode_starts() == y.episode_starts()) << "iteration " << k;
    EXPECT_TRUE(x.values() == y.values()) << "iteration " << k;
    EXPECT_TRUE(x.log_probs() == y.log_probs()) << "iteration " << k;
    EXPECT_TRUE(x.advantages() == y.advantages()) << "iteration " << k;
    EXPECT_EQ(a.returns, b.returns) << "iteration " << k;
  }
  EXPECT_EQ(split_pool.rollouts, iterations);
  EXPECT_EQ(split_pool.used, vary ? threads : 1u);
  EXPECT_TRUE(one.model().actor().params() == split.model().actor().params());
  EXPECT_TRUE(one.model().critic().params() == split.model().critic().params());
  EXPECT_TRUE(one.model().log_std() == split.model().log_std());
  EXPECT_EQ(one.state().rng_act, split.state().rng_act);
}

TEST(RunAhead, SharesRunAloneGiveTheOneProcessIterations) {
  // 4 environments in shares of 2, 1, 1: every forward pass takes Eigen's products.
  expect_same_iterations(tiny_loop(), 3, 3);
}

TEST(RunAhead, SharesRunAloneGiveTheOneProcessIterationsWithTheWideProducts) {
  // 32 environments and hidden layers of 64: products wide enough for the blocked GEMMs where the
  // CPU has AVX-512 (mlp.cpp's fast_eligible), Eigen's blocked product elsewhere, while each share
  // holds 10 or 11 columns of its own. Episodes of 2 decisions of one design keep it short.
  TinyLoop s = tiny_loop();
  s.loop.task.episode_steps = 10;
  s.loop.ppo.n_steps = 2;
  s.loop.codesign.designs_per_update = 32;
  s.loop.codesign.total_timesteps = 2 * 32 * 2;
  s.loop.codesign.distribution.exploration_end = 64;
  s.loop.codesign.distribution.exploitation_start = 96;
  s.loop.ppo.batch_size = 32;
  s.loop.ppo.actor_hidden = {64, 64};
  s.loop.ppo.critic_hidden = {64, 64};
  s.loop.codesign.baseline = Baseline::SingleDesign;  // one design to mesh; plate phases still differ
  expect_same_iterations(s, 3, 2);
}

TEST(RunAhead, SharesWhoseThreadsChangeBetweenDecisionsGiveTheOneProcessIterations) {
  // As an MPI rank that takes up threads lent by ranks done before it (cluster/lent_threads.hpp):
  // shares of 4 and 3 environments on pools of 3 threads, 1, 2 or 3 of them in use by turns,
  // changing within a step too.
  TinyLoop s = tiny_loop();
  s.loop.codesign.designs_per_update = 7;
  s.loop.codesign.total_timesteps = 3 * 7 * s.loop.ppo.n_steps;
  s.loop.ppo.batch_size = 7;
  expect_same_iterations(s, 2, 3, 3, true);
}

TEST(RunAhead, RunShareRefusesPlacesAndDrawsThatDoNotFit) {
  const TinyLoop s = tiny_loop();
  auto sims = std::make_shared<SimulatorPool>(s.spec, s.scene, s.solver);
  ThreadEnvPool pool(sims, s.loop.task, 2, 1);
  rl::ActorCritic model = feed_forward_model(s.loop, pool);
  rl::ActorCritic::InferenceCache cache;
  const std::vector<EpisodeSetup> setups(2);
  const std::vector<Eigen::MatrixXd> normals(1, Eigen::MatrixXd::Zero(pool.spec().action.dim(), 4));
  EXPECT_THROW(run_share(pool, setups, model, cache, {0, 4}, 4, normals, 0.99), std::invalid_argument);
  EXPECT_THROW(run_share(pool, setups, model, cache, {0}, 4, normals, 0.99), std::invalid_argument);
  EXPECT_THROW(run_share(pool, setups, model, cache, {0, 1}, 5, normals, 0.99), std::invalid_argument);
}

}  // namespace
