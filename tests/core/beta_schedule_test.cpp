// The two β schedules of q_disc = softmax(β R̂): the paper's ramp (unchanged) and the
// target-entropy schedule (β solved by bisection so that H(q_disc) follows a line in t).
//
// Tolerances. entropy_matching_beta returns the upper end of a bracket [lo, hi] around the exact
// root with hi − lo ≤ kBetaRelTolerance·hi, so |β − β_exact| ≤ kBetaRelTolerance·β, plus the
// effect of rounding in H itself: H is computed to a few 1e-16 nats, which moves the root by
// about 1e-16/|dH/dβ|; |dH/dβ| = β·Var_q(R̂) is ≥ 0.17 at every root below, so that term is
// < 1e-14 (kRootSlack). In H, the bracket is worth |dH/dβ|·(hi − lo) ≤ β²·Var_q·1e-12, below
// 1e-11 for every case here (kEntropySlack = 1e-10 leaves room).
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/codesign_config.hpp"
#include "core/design_distribution.hpp"

namespace codesign::core {
namespace {

constexpr double kRootSlack = 1e-14;
constexpr double kEntropySlack = 1e-10;

Eigen::VectorXd scores(std::initializer_list<double> v) {
  Eigen::VectorXd s(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) s(i++) = x;
  return s;
}

// Binary entropy in nats.
double h2(double p) { return -p * std::log(p) - (1.0 - p) * std::log(1.0 - p); }

void expect_root(double beta, double exact, const char* what = "") {
  EXPECT_NEAR(beta, exact, kBetaRelTolerance * exact + kRootSlack) << what;
}

// T1 = 100, T2 = 300 (as the distribution tests' toy schedule), entropy schedule.
DistributionConfig entropy_config(double entropy_end) {
  DistributionConfig c;
  c.exploration_end = 100;
  c.exploitation_start = 300;
  c.beta_schedule = BetaSchedule::Entropy;
  c.entropy_end = entropy_end;
  return c;
}

DesignSample design(int j) {
  DesignSample s;
  s.design = j;
  return s;
}

TEST(BetaSchedule, DefaultsAreTheRampAndLn3) {
  EXPECT_EQ(CodesignConfig{}.distribution.beta_schedule, BetaSchedule::Ramp);
  EXPECT_EQ(DistributionConfig{}.beta_schedule, BetaSchedule::Ramp);
  EXPECT_EQ(kDefaultEntropyEnd, std::log(3.0));
  EXPECT_EQ(CodesignConfig{}.distribution.entropy_end, std::log(3.0));
  EXPECT_EQ(DistributionConfig{}.entropy_end, std::log(3.0));
  EXPECT_STREQ(to_string(BetaSchedule::Ramp), "ramp");
  EXPECT_STREQ(to_string(BetaSchedule::Entropy), "entropy");
}

// ---------------------------------------------------------------------------------------------
// The solver against closed forms

// R̂ = (1, 0): q = (p, 1 − p) with p = sigmoid(β), H = h2(p), so the β of H = h2(p) is ln(p/(1 − p)).
TEST(EntropyMatchingBeta, TwoDesignsMatchTheLogitOfTheClosedForm) {
  const Eigen::VectorXd r = scores({1.0, 0.0});
  for (const double p : {0.6, 0.75, 0.9, 0.99}) {
    SCOPED_TRACE(p);
    const double target = h2(p);
    const double b = entropy_matching_beta(r, target);
    expect_root(b, std::log(p / (1.0 - p)));
    const double h = softmax_entropy(r, b);
    EXPECT_LE(h, target);  // the upper end of the bracket: never above the target
    EXPECT_GE(h, target - kEntropySlack);
  }
}

// R̂ = (1, 0, 0): at β = ln 2 the weights are (2, 1, 1), q = (1/2, 1/4, 1/4), H = 1.5 ln 2.
TEST(EntropyMatchingBeta, ThreeDesignsByHand) {
  const double target = 1.5 * std::log(2.0);
  expect_root(entropy_matching_beta(scores({1.0, 0.0, 0.0}), target), std::log(2.0));
  // Any order of the designs gives the same β.
  expect_root(entropy_matching_beta(scores({0.0, 0.0, 1.0}), target), std::log(2.0));
}

// Shifting every score changes nothing; scaling them by c divides β by c and leaves q (and H) as
// they were: the schedule is independent of the reward scale, which the ramp is not.
TEST(EntropyMatchingBeta, IndependentOfTheRewardScaleAndOffset) {
  const double target = 1.5 * std::log(2.0);
  expect_root(entropy_matching_beta(scores({2.0, 0.0, 0.0}), target), std::log(2.0) / 2.0);
  expect_root(entropy_matching_beta(scores({8.0, 0.0, 0.0}), target), std::log(2.0) / 8.0);
  expect_root(entropy_matching_beta(scores({6.0, 5.0, 5.0}), target), std::log(2.0));
  expect_root(entropy_matching_beta(scores({-3.0, -4.0, -4.0}), target), std::log(2.0));
}

// Two designs tied at the top: the entropy falls from ln 3 towards ln 2 and no β goes below.
TEST(EntropyMatchingBeta, TiesAtTheTopFloorTheEntropy) {
  const Eigen::VectorXd r = scores({1.0, 1.0, 0.0});
  // Reachable: at β = ln 2 the weights are (2, 2, 1), q = (0.4, 0.4, 0.2).
  const double reachable = -0.8 * std::log(0.4) - 0.2 * std::log(0.2);
  expect_root(entropy_matching_beta(r, reachable), std::log(2.0));
  // Below the floor ln 2: the cap, 746/Δ with Δ = 1 the gap below the top, where the third
  // weight exp(−746) is exactly 0 and q = (1/2, 1/2, 0).
  const double b = entropy_matching_beta(r, 0.5);
  EXPECT_EQ(b, kBetaCapLogit / 1.0);
  EXPECT_NEAR(softmax_entropy(r, b), std::log(2.0), 1e-15);
  EXPECT_GT(softmax_entropy(r, b), 0.5);  // what the logs show: entropy above its target
  // The cap scales with the gap: Δ = 0.25 gives 4·746.
  EXPECT_EQ(entropy_matching_beta(scores({0.5, 0.5, 0.25}), 0.5), 4.0 * kBetaCapLogit);
  // A single top design can be driven to any entropy above 0.
  const double b0 = entropy_matching_beta(scores({1.0, 0.0, 0.0}), 1e-3);
  EXPECT_LE(softmax_entropy(scores({1.0, 0.0, 0.0}), b0), 1e-3);
  EXPECT_LT(b0, kBetaCapLogit);
}

TEST(EntropyMatchingBeta, AllEqualOneDesignAndTheStartGiveZero) {
  EXPECT_EQ(entropy_matching_beta(scores({2.0, 2.0, 2.0}), 0.1), 0.0);  // q is uniform for any β
  EXPECT_EQ(entropy_matching_beta(scores({0.0, 0.0}), 0.0), 0.0);
  EXPECT_EQ(entropy_matching_beta(scores({5.0}), 0.0), 0.0);              // n = 1: H = 0 = ln 1
  EXPECT_EQ(entropy_matching_beta(scores({1.0, 0.0, 0.0}), std::log(3.0)), 0.0);  // target ln n (T1)
  EXPECT_EQ(entropy_matching_beta(scores({1.0, 0.0, 0.0}), 2.0), 0.0);            // above ln n
}

// ---------------------------------------------------------------------------------------------
// The schedule inside the distribution

TEST(BetaSchedule, RampIsUnchangedAndHasNoTarget) {
  DistributionConfig c = entropy_config(kDefaultEntropyEnd);
  c.beta_schedule = BetaSchedule::Ramp;
  c.beta_start = 0.2;
  c.beta_end = 1.0;
  const DesignDistribution q(c, {2, 2});
  EXPECT_FALSE(q.target_entropy(150).has_value());
  EXPECT_EQ(q.beta(50), 0.0);
  EXPECT_EQ(q.beta(200), 0.2 + (1.0 - 0.2) * (100.0 / 200.0));
  EXPECT_EQ(q.beta(400), 1.0);
  // entropy_end is not checked against ln n under the ramp (it is unused there).
  EXPECT_NO_THROW(DesignDistribution(c, {2}));
}

TEST(BetaSchedule, TargetIsALineFromLnNAtT1ToEntropyEndAtT2) {
  const double end = 1.5 * std::log(2.0);
  const DesignDistribution q(entropy_config(end), {2, 1, 2});
  const double ln3 = std::log(3.0);
  EXPECT_EQ(*q.target_entropy(0), ln3);
  EXPECT_EQ(*q.target_entropy(99), ln3);
  EXPECT_EQ(*q.target_entropy(100), ln3);
  EXPECT_NEAR(*q.target_entropy(200), ln3 + 0.5 * (end - ln3), 1e-15);
  EXPECT_NEAR(*q.target_entropy(250), ln3 + 0.75 * (end - ln3), 1e-15);
  EXPECT_EQ(*q.target_entropy(300), end);
  EXPECT_EQ(*q.target_entropy(1'000'000), end);
}

// A design never sampled keeps R̂ = 0 and enters the softmax like any other: designs 1 (returns
// ≤ 0 keep the exploration best-so-far at 0) and 2 (never sampled) both have R̂ = 0.
TEST(BetaSchedule, SolvesForTheTargetWithADesignNeverSampled) {
  DesignDistribution q(entropy_config(1.5 * std::log(2.0)), {2, 1, 2});
  q.update({design(0), design(1)}, {2.0, -1.0}, 10);
  ASSERT_EQ(q.state().score, scores({2.0, 0.0, 0.0}));
  ASSERT_EQ(q.state().samples[2], 0);
  // Exploration: β = 0 whatever R̂ (the paper), q uniform.
  EXPECT_EQ(q.beta(10), 0.0);
  EXPECT_NEAR(q.entropy(10), std::log(3.0), 1e-15);
  // T1: the target is ln 3 itself, β = 0.
  EXPECT_EQ(q.beta(100), 0.0);
  // From T2 on: H = 1.5 ln 2, β = ln 2 / 2 (weights 2, 1, 1), q = (1/2, 1/4, 1/4).
  expect_root(q.beta(300), std::log(2.0) / 2.0);
  const Eigen::VectorXd p = q.probabilities(300);
  EXPECT_NEAR(p(0), 0.5, 1e-12);
  EXPECT_NEAR(p(1), 0.25, 1e-12);
  EXPECT_NEAR(p(2), 0.25, 1e-12);
  // Mid-transition: the entropy is the target, from below, within the solver's tolerance.
  const double target = *q.target_entropy(200);
  EXPECT_LE(q.entropy(200), target);
  EXPECT_GE(q.entropy(200), target - kEntropySlack);
}

// Along the schedule, with R̂ fixed, β rises and H(q) falls, following its target.
TEST(BetaSchedule, EntropyFallsMonotonicallyAlongTheSchedule) {
  DesignDistribution fresh(entropy_config(0.3), {2, 2, 1, 2});
  DistributionState s = fresh.state();
  s.score = scores({3.0, 1.0, 2.5, 0.0});
  const DesignDistribution q(entropy_config(0.3), {2, 2, 1, 2}, s);
  double last_beta = 0.0, last_h = std::log(4.0);
  for (std::int64_t t = 100; t <= 320; t += 10) {
    SCOPED_TRACE(t);
    const double b = q.beta(t), h = q.entropy(t), target = *q.target_entropy(t);
    EXPECT_GE(b, last_beta);
    EXPECT_LE(h, last_h + 1e-15);
    EXPECT_LE(h, target + 1e-15);  // at T1 (β = 0) the rounding of ln 4 in H(0); after, ≤ exactly
    EXPECT_GE(h, target - kEntropySlack);
    if (t > 100 && t <= 300) {
      EXPECT_LT(h, last_h);  // strictly: the target falls 0.054 nats a step
    }
    last_beta = b;
    last_h = h;
  }
  EXPECT_NEAR(q.entropy(300), 0.3, kEntropySlack);
}

TEST(BetaSchedule, AllEqualScoresAndOneDesignKeepBetaZero) {
  const DesignDistribution fresh(entropy_config(0.5), {2, 2, 2});  // R̂ = 0 everywhere
  for (const std::int64_t t : {0, 100, 200, 300, 5000}) {
    EXPECT_EQ(fresh.beta(t), 0.0);
    EXPECT_NEAR(fresh.entropy(t), std::log(3.0), 1e-15);  // above the target: nothing to separate
  }
  // n = 1: ln 1 = 0, so entropy_end must be 0; q = (1) and β = 0 throughout.
  DistributionConfig one = entropy_config(0.0);
  DesignDistribution single(one, {1});
  single.update({design(0)}, {4.0}, 10);
  for (const std::int64_t t : {0, 150, 300}) {
    EXPECT_EQ(single.beta(t), 0.0);
    EXPECT_EQ(single.probabilities(t)(0), 1.0);
    EXPECT_EQ(single.entropy(t), 0.0);
    EXPECT_EQ(*single.target_entropy(t), 0.0);
  }
}

TEST(BetaSchedule, EntropyEndIsCheckedAgainstLnN) {
  try {
    DesignDistribution(entropy_config(0.5), {1});
    ADD_FAILURE() << "entropy_end 0.5 accepted with one design";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "DistributionConfig.entropy_end: value 0.5 is out of range; allowed [0, ln 1 = 0]");
  }
  EXPECT_THROW(DesignDistribution(entropy_config(std::log(2.0) + 1e-12), {2, 2}), std::invalid_argument);
  EXPECT_NO_THROW(DesignDistribution(entropy_config(std::log(2.0)), {2, 2}));
  for (const double bad : std::vector<double>{-0.1, std::nan(""), INFINITY}) {
    DistributionConfig c = entropy_config(bad);
    c.beta_schedule = BetaSchedule::Ramp;  // checked by validate() under either schedule
    try {
      c.validate();
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("DistributionConfig.entropy_end: value ", 0), 0u) << e.what();
    }
  }
}

// β is not part of the state: a distribution restored from a state gives the same β, q and H.
TEST(BetaSchedule, RestoredDistributionGivesTheSameBeta) {
  DesignDistribution q(entropy_config(0.4), {2, 1, 2, 2});
  q.update({design(0), design(1), design(3)}, {1.5, 0.5, 1.25}, 10);
  q.update({design(0), design(3), design(3)}, {1.0, 2.0, 0.5}, 180);
  const DesignDistribution r(entropy_config(0.4), {2, 1, 2, 2}, q.state());
  for (const std::int64_t t : {180, 250, 300}) {
    EXPECT_EQ(r.beta(t), q.beta(t));
    EXPECT_EQ(r.probabilities(t), q.probabilities(t));
    EXPECT_EQ(r.entropy(t), q.entropy(t));
  }
}

}  // namespace
}  // namespace codesign::core
