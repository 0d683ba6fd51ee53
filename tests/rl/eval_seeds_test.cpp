// Evaluation seeds are disjoint by construction (rl::eval_seed_first, src/rl/trainer.hpp):
// episode k of training seed s is reset with 2^63 + s * 2^20 + k. These tests record the seeds
// that VecEnv (training) and evaluate() (evaluation) actually pass to reset(), and check that
// no seed, and no Pendulum start state, is used twice.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "rl/pendulum.hpp"
#include "rl/trainer.hpp"
#include "rl/vec_env.hpp"

namespace codesign::rl {
namespace {

// One-step episodes; records every explicit reset seed into a shared log.
class SeedRecorder final : public Env {
 public:
  explicit SeedRecorder(std::vector<std::uint64_t>* log) : log_(log) {
    spec_.observation = {Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Constant(1, 1.0)};
    spec_.action = {Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Constant(1, 1.0)};
  }
  const EnvSpec& spec() const override { return spec_; }
  Eigen::VectorXd reset(std::optional<std::uint64_t> seed) override {
    if (seed) log_->push_back(*seed);
    return Eigen::VectorXd::Zero(1);
  }
  StepResult step(const Eigen::VectorXd&) override {
    StepResult r;
    r.obs = Eigen::VectorXd::Zero(1);
    r.terminated = true;
    return r;
  }

 private:
  std::vector<std::uint64_t>* log_;
  EnvSpec spec_;
};

EnvFactory recorder_factory(std::vector<std::uint64_t>* log) {
  return [log](std::size_t) { return std::make_unique<SeedRecorder>(log); };
}

const DeterministicPolicy kZero = [](const Eigen::VectorXd&) {
  return Eigen::VectorXd::Zero(1).eval();
};

// The acceptance benchmark's case: training seeds 0..4 with 4 envs each, 100 evaluation
// episodes each. The 500 evaluation seeds are distinct, and none is a training seed. (Training
// seeds s + i of neighbouring s overlap by VecEnv's design: 0..7 for s = 0..4.)
TEST(EvalSeeds, BenchmarkSeedsAreAllDistinct) {
  constexpr int kEpisodes = 100;
  constexpr std::size_t kEnvs = 4;
  std::vector<std::uint64_t> train, eval;
  for (std::uint64_t s = 0; s < 5; ++s) {
    VecEnv venv(recorder_factory(&train), kEnvs, s, 1);
    venv.reset();
    evaluate(kZero, recorder_factory(&eval), kEpisodes, eval_seed_first(s, kEpisodes));
  }
  ASSERT_EQ(train.size(), 5 * kEnvs);
  ASSERT_EQ(eval.size(), 5u * kEpisodes);
  const std::set<std::uint64_t> train_set(train.begin(), train.end());
  EXPECT_EQ(train_set, (std::set<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  std::set<std::uint64_t> all = train_set;
  all.insert(eval.begin(), eval.end());
  EXPECT_EQ(all.size(), train_set.size() + eval.size());
  // The old scheme (s + 1'000'000'007 + k) shared 99 of 100 seeds between s and s + 1.
  // Here evaluation k of seed s is exactly 2^63 + s * 2^20 + k.
  EXPECT_EQ(eval[0], std::uint64_t{1} << 63);
  EXPECT_EQ(eval[kEpisodes - 1], (std::uint64_t{1} << 63) + 99);
  EXPECT_EQ(eval[kEpisodes], (std::uint64_t{1} << 63) + (std::uint64_t{1} << 20));
  EXPECT_EQ(eval[4 * kEpisodes + 99], (std::uint64_t{1} << 63) + 4 * (std::uint64_t{1} << 20) + 99);
}

// The same 500 evaluation episodes and 20 training resets of Pendulum give 520 distinct start
// states (not only distinct seeds).
TEST(EvalSeeds, BenchmarkPendulumStartStatesAreAllDistinct) {
  std::set<std::array<double, 3>> starts;
  std::size_t n = 0;
  for (std::uint64_t s = 0; s < 5; ++s) {
    for (std::uint64_t i = 0; i < 4; ++i) {
      const Eigen::VectorXd o = make_pendulum()->reset(s + i);
      starts.insert({o(0), o(1), o(2)});
      ++n;
    }
    const std::uint64_t first = eval_seed_first(s, 100);
    for (std::uint64_t k = 0; k < 100; ++k) {
      const Eigen::VectorXd o = make_pendulum()->reset(first + k);
      starts.insert({o(0), o(1), o(2)});
      ++n;
    }
  }
  EXPECT_EQ(n, 520u);
  // Training seeds s + i overlap between neighbouring s by design (VecEnv); count those once.
  // Seeds 0..7 are the training seeds of s = 0..4 with 4 envs: 8 distinct + 500 evaluations.
  EXPECT_EQ(starts.size(), 8u + 500u);
}

// The extremes of the scheme: the last seed of the largest training seed is 2^64 - 1 (no
// wrap-around), neighbouring blocks touch without overlap, and everything outside the proven
// range is refused.
TEST(EvalSeeds, RangeLimitsAreEnforced) {
  const std::uint64_t max_episodes = kEvalSeedStride;
  EXPECT_EQ(max_episodes, std::uint64_t{1} << 20);
  EXPECT_EQ(kMaxEvalTrainSeed, (std::uint64_t{1} << 43) - 1);
  const std::uint64_t last_block = eval_seed_first(kMaxEvalTrainSeed, 1 << 20);
  EXPECT_EQ(last_block + (max_episodes - 1), ~std::uint64_t{0});
  EXPECT_EQ(eval_seed_first(kMaxEvalTrainSeed - 1, 1 << 20) + max_episodes, last_block);
  // Every evaluation seed has bit 63 set; every training seed s + i (s <= 2^43 - 1) has it clear.
  EXPECT_EQ(eval_seed_first(0, 1) >> 63, 1u);
  EXPECT_EQ((kMaxEvalTrainSeed + 4096) >> 63, 0u);

  EXPECT_THROW(eval_seed_first(kMaxEvalTrainSeed + 1, 100), std::invalid_argument);
  EXPECT_THROW(eval_seed_first(0, (1 << 20) + 1), std::invalid_argument);
  EXPECT_THROW(eval_seed_first(0, 0), std::invalid_argument);
  EXPECT_NO_THROW(eval_seed_first(0, 1 << 20));
}

}  // namespace
}  // namespace codesign::rl
