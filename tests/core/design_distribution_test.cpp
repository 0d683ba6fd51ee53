// Tests of the hybrid design distribution (Algorithm 2, Eq. 5–9).
// Tolerances: hand computations use 1e-12 relative (kRel; the code and the hand arithmetic differ
// only by a few roundings of order 1e-16 relative); Monte Carlo checks use 5 standard errors
// computed from the sample size (a true mismatch of that size has probability < 1e-6 per check,
// and the seeds are fixed anyway).
#include "core/design_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

namespace codesign::core {
namespace {

constexpr double kRel = 1e-12;

// |actual − expected| ≤ 1e-12·max(1, |expected|): relative, absolute near zero.
void expect_close(double actual, double expected, const char* what = "") {
  EXPECT_NEAR(actual, expected, kRel * std::max(1.0, std::abs(expected))) << what;
}

// Small, readable schedule: T1 = 100, T2 = 300, β from 0.2 to 1.0.
DistributionConfig toy_config() {
  DistributionConfig c;
  c.exploration_end = 100;
  c.exploitation_start = 300;
  c.alpha = 0.1;
  c.phi = 0.05;
  c.beta_start = 0.2;
  c.beta_end = 1.0;
  c.reward_buffer = 100;
  c.pressure_max_kPa = 20.0;
  c.latent_mu0 = 0.0;
  c.latent_sigma0 = 1.0;
  c.latent_sigma_min = 1e-3;
  return c;
}

constexpr std::int64_t kExplore = 10;    // t < T1
constexpr std::int64_t kTransit = 150;   // T1 ≤ t < T2
constexpr std::int64_t kExploit = 300;   // t ≥ T2

DesignSample at(int design, double z1, double z2) {
  DesignSample s;
  s.design = design;
  s.latent = Eigen::Vector2d(z1, z2);
  return s;
}

void expect_same_state(const DistributionState& a, const DistributionState& b) {
  EXPECT_EQ(a.score, b.score);
  EXPECT_EQ(a.baseline, b.baseline);
  ASSERT_EQ(a.mu.size(), b.mu.size());
  for (std::size_t j = 0; j < a.mu.size(); ++j) {
    EXPECT_EQ(a.mu[j], b.mu[j]) << "design " << j;
    EXPECT_EQ(a.sigma[j], b.sigma[j]) << "design " << j;
  }
  EXPECT_EQ(a.buffer, b.buffer);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(a.collapsed, b.collapsed);
  EXPECT_EQ(a.best_design, b.best_design);
  EXPECT_EQ(a.best_latent, b.best_latent);
}

// ---------------------------------------------------------------------------------------------
// Configuration and construction

TEST(DesignDistributionConfig, DefaultsArePaperValuesAndValid) {
  const DistributionConfig c;
  EXPECT_NO_THROW(c.validate());
  EXPECT_EQ(c.exploration_end, 220'000);
  EXPECT_EQ(c.exploitation_start, 800'000);
  EXPECT_EQ(c.alpha, 0.1);
  EXPECT_EQ(c.phi, 0.05);
  EXPECT_EQ(c.pressure_max_kPa, 20.0);
}

TEST(DesignDistributionConfig, ValidateRejectsEachBadFieldByName) {
  const double nan = std::nan("");
  const double inf = INFINITY;
  struct Case {
    std::string field;
    std::function<void(DistributionConfig&)> spoil;
  };
  const std::vector<Case> cases = {
      {"exploration_end", [](auto& c) { c.exploration_end = -1; }},
      {"exploitation_start", [](auto& c) { c.exploitation_start = c.exploration_end; }},
      {"alpha", [](auto& c) { c.alpha = 0.0; }},
      {"alpha", [&](auto& c) { c.alpha = nan; }},
      {"phi", [](auto& c) { c.phi = -0.01; }},
      {"phi", [](auto& c) { c.phi = 1.5; }},
      {"beta_start", [](auto& c) { c.beta_start = -1.0; }},
      {"beta_end", [&](auto& c) { c.beta_end = inf; }},
      {"reward_buffer", [](auto& c) { c.reward_buffer = 1; }},
      {"pressure_max_kPa", [](auto& c) { c.pressure_max_kPa = 0.0; }},
      {"latent_mu0", [&](auto& c) { c.latent_mu0 = nan; }},
      {"latent_sigma0", [](auto& c) { c.latent_sigma0 = 0.0; }},
      {"latent_sigma_min", [](auto& c) { c.latent_sigma_min = 0.0; }},
      {"latent_sigma_min", [](auto& c) { c.latent_sigma_min = 2.0 * c.latent_sigma0; }},
  };
  for (const auto& k : cases) {
    DistributionConfig c = toy_config();
    k.spoil(c);
    try {
      c.validate();
      ADD_FAILURE() << k.field << ": no exception";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("DistributionConfig." + k.field + ":"),
                std::string::npos)
          << e.what();
    }
    EXPECT_THROW(DesignDistribution(c, {2}), std::invalid_argument) << k.field;
  }
}

TEST(DesignDistribution, ConstructorRejectsBadChambers) {
  EXPECT_THROW(DesignDistribution(toy_config(), {}), std::invalid_argument);
  EXPECT_THROW(DesignDistribution(toy_config(), {1, 0}), std::invalid_argument);
  EXPECT_THROW(DesignDistribution(toy_config(), {3}), std::invalid_argument);
}

TEST(DesignDistribution, InitialStateIsMu0Sigma0AndZeroScores) {
  DistributionConfig c = toy_config();
  c.latent_mu0 = 0.25;
  c.latent_sigma0 = 1.5;
  const DesignDistribution q(c, {1, 2, 2});
  EXPECT_EQ(q.design_count(), 3);
  EXPECT_EQ(q.chambers(0), 1);
  EXPECT_EQ(q.chambers(2), 2);
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(q.state().score(j), 0.0);
    EXPECT_EQ(q.state().baseline(j), 0.0);
    EXPECT_EQ(q.state().mu[j], Eigen::Vector2d(0.25, 0.25));
    EXPECT_EQ(q.state().sigma[j], (Eigen::Matrix2d() << 2.25, 0.0, 0.0, 2.25).finished());
    EXPECT_TRUE(q.state().buffer[j].empty());
    EXPECT_EQ(q.state().samples[j], 0);
  }
  EXPECT_FALSE(q.state().collapsed);
  EXPECT_EQ(q.state().best_design, -1);
}

// ---------------------------------------------------------------------------------------------
// Schedule and q_disc

TEST(DesignDistribution, PhasesAndBetaSchedule) {
  const DesignDistribution q(toy_config(), {2});
  EXPECT_EQ(q.phase(0), Phase::Exploration);
  EXPECT_EQ(q.phase(99), Phase::Exploration);
  EXPECT_EQ(q.phase(100), Phase::Transition);
  EXPECT_EQ(q.phase(299), Phase::Transition);
  EXPECT_EQ(q.phase(300), Phase::Exploitation);
  EXPECT_STREQ(to_string(Phase::Exploration), "exploration");
  EXPECT_STREQ(to_string(Phase::Transition), "transition");
  EXPECT_STREQ(to_string(Phase::Exploitation), "exploitation");

  EXPECT_EQ(q.beta(0), 0.0);
  EXPECT_EQ(q.beta(99), 0.0);
  expect_close(q.beta(100), 0.2, "T1: beta_start");
  expect_close(q.beta(200), 0.6, "midpoint: 0.2 + 0.8 * 100/200");
  expect_close(q.beta(299), 0.996, "0.2 + 0.8 * 199/200");
  expect_close(q.beta(300), 1.0, "T2: beta_end");
  expect_close(q.beta(1'000'000), 1.0, "after T2");
}

TEST(DesignDistribution, ProbabilitiesAreSoftmaxByHandForThreeDesigns) {
  DesignDistribution fresh(toy_config(), {2, 1, 2});
  DistributionState s = fresh.state();
  s.score << 1.0, 2.0, 4.0;
  const DesignDistribution q(toy_config(), {2, 1, 2}, s);

  // Exploration: β = 0, uniform.
  const Eigen::VectorXd u = q.probabilities(kExplore);
  for (int j = 0; j < 3; ++j) expect_close(u(j), 1.0 / 3.0);
  expect_close(q.entropy(kExplore), std::log(3.0), "uniform entropy ln 3");

  // t = 200: β = 0.6, logits 0.6, 1.2, 2.4.
  const double e0 = std::exp(0.6), e1 = std::exp(1.2), e2 = std::exp(2.4);
  const double z = e0 + e1 + e2;
  const double q0 = e0 / z, q1 = e1 / z, q2 = e2 / z;
  const Eigen::VectorXd p = q.probabilities(200);
  expect_close(p(0), q0);
  expect_close(p(1), q1);
  expect_close(p(2), q2);
  // The sum of three doubles ≤ 1 is exact to a few ulp (≤ 4.4e-16); 1e-15 leaves room.
  EXPECT_NEAR(p.sum(), 1.0, 1e-15);
  const double h = -(q0 * std::log(q0) + q1 * std::log(q1) + q2 * std::log(q2));
  expect_close(q.entropy(200), h);
}

TEST(DesignDistribution, ProbabilitiesAreStableForHugeLogits) {
  DesignDistribution fresh(toy_config(), {2, 2});
  DistributionState s = fresh.state();
  s.score << 5000.0, 0.0;  // β = 1: e^-5000 underflows to 0, never NaN
  const DesignDistribution q(toy_config(), {2, 2}, s);
  const Eigen::VectorXd p = q.probabilities(kExploit);
  EXPECT_EQ(p(0), 1.0);
  EXPECT_EQ(p(1), 0.0);
  EXPECT_EQ(q.entropy(kExploit), 0.0);
}

TEST(DesignDistribution, RankingIsByScoreWithLowerIndexFirstOnTies) {
  DesignDistribution fresh(toy_config(), {2, 2, 2, 2, 2});
  DistributionState s = fresh.state();
  s.score << 1.0, 3.0, 3.0, 2.0, 3.0;
  const DesignDistribution q(toy_config(), {2, 2, 2, 2, 2}, s);
  EXPECT_EQ(q.ranking(), (std::vector<int>{1, 2, 4, 3, 0}));
}

// ---------------------------------------------------------------------------------------------
// The latent map

TEST(DesignDistribution, LatentMapAndDeltaMethodByHand) {
  DesignDistribution fresh(toy_config(), {2, 1});
  DistributionState s = fresh.state();
  s.mu[0] = Eigen::Vector2d(std::log(3.0), -std::log(3.0));  // sigmoid = 3/4 and 1/4
  s.sigma[0] << 4.0, 0.5, 0.5, 9.0;
  s.mu[1] = Eigen::Vector2d(0.0, 2.0);
  const DesignDistribution q(toy_config(), {2, 1}, s);

  const Eigen::Vector2d mid = q.pressures_kPa(Eigen::Vector2d::Zero(), 0);
  expect_close(mid(0), 10.0, "20 * 1/2");
  expect_close(mid(1), 10.0);
  const Eigen::Vector2d m = q.mean_pressures_kPa(0);
  expect_close(m(0), 15.0, "20 * 3/4");
  expect_close(m(1), 5.0, "20 * 1/4");
  // std ≈ 20 · s(1 − s) · sqrt(Σ_ii): 20 · 3/16 · 2 = 7.5 and 20 · 3/16 · 3 = 11.25.
  const Eigen::Vector2d sd = q.sigma_pressures_kPa(0);
  expect_close(sd(0), 7.5);
  expect_close(sd(1), 11.25);

  // Tails stay inside [0, p_max] without NaN.
  const Eigen::Vector2d lo = q.pressures_kPa(Eigen::Vector2d(-800.0, 800.0), 0);
  EXPECT_EQ(lo(0), 0.0);
  EXPECT_EQ(lo(1), 20.0);

  // One chamber: p2 = 0 whatever z2.
  EXPECT_EQ(q.pressures_kPa(Eigen::Vector2d(0.0, 3.0), 1)(1), 0.0);
  EXPECT_EQ(q.mean_pressures_kPa(1)(1), 0.0);
  EXPECT_EQ(q.sigma_pressures_kPa(1)(1), 0.0);
  expect_close(q.sigma_pressures_kPa(1)(0), 5.0, "20 * 1/4 * 1");

  EXPECT_THROW(q.pressures_kPa(Eigen::Vector2d::Zero(), 2), std::invalid_argument);
  EXPECT_THROW(q.mean_pressures_kPa(-1), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Algorithm 2

TEST(DesignDistributionUpdate, Eq7And8ByHandFromFreshTwoChamberDesign) {
  DesignDistribution q(toy_config(), {2});
  // First transition return: buffer {2}, population std 0 → A = 0, no continuous update.
  q.update({at(0, 1.0, -2.0)}, {2.0}, kTransit);
  expect_close(q.state().score(0), 2.0, "R̂ = mean{2}");
  expect_close(q.state().baseline(0), 0.1, "b = 0.95*0 + 0.05*2");
  EXPECT_EQ(q.state().mu[0], Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(q.state().sigma[0], Eigen::Matrix2d::Identity());

  // Second: buffer {2, 4}: mean 3, population std 1; A = (4 − 0.1)/1 = 3.9; αA = 0.39;
  // d = z − μ = (1, −2); d dᵀ − Σ = [[1 − 1, −2], [−2, 4 − 1]] = [[0, −2], [−2, 3]].
  q.update({at(0, 1.0, -2.0)}, {4.0}, kTransit);
  const auto& s = q.state();
  expect_close(s.score(0), 3.0);
  expect_close(s.mu[0](0), 0.39, "0 + 0.39 * 1");
  expect_close(s.mu[0](1), -0.78, "0 + 0.39 * -2");
  expect_close(s.sigma[0](0, 0), 1.0, "1 + 0.39 * 0");
  expect_close(s.sigma[0](0, 1), -0.78, "0 + 0.39 * -2");
  expect_close(s.sigma[0](1, 0), -0.78);
  expect_close(s.sigma[0](1, 1), 2.17, "1 + 0.39 * 3");
  expect_close(s.baseline(0), 0.295, "0.95 * 0.1 + 0.05 * 4");
  EXPECT_EQ(s.buffer[0], (std::vector<double>{2.0, 4.0}));
  EXPECT_EQ(s.samples[0], 2);
}

TEST(DesignDistributionUpdate, Eq7And8ByHandUseOldMeanAndCovariance) {
  DesignDistribution fresh(toy_config(), {2});
  DistributionState st = fresh.state();
  st.mu[0] = Eigen::Vector2d(0.5, -0.5);
  st.sigma[0] << 1.0, 0.2, 0.2, 0.5;
  st.buffer[0] = {1.0, 3.0};
  st.samples[0] = 2;
  st.baseline(0) = 1.0;
  DesignDistribution q(toy_config(), {2}, st);

  // R = 5: buffer {1, 3, 5}, mean 3, population variance (4 + 0 + 4)/3 = 8/3;
  // A = (5 − 1)/sqrt(8/3) = sqrt(16 · 3/8) = sqrt(6); αA = 0.1·sqrt(6).
  // d = (1.5, 0.5) − (0.5, −0.5) = (1, 1); d dᵀ − Σ = [[0, 0.8], [0.8, 0.5]].
  q.update({at(0, 1.5, 0.5)}, {5.0}, kTransit);
  const double step = 0.1 * std::sqrt(6.0);
  const auto& s = q.state();
  expect_close(s.score(0), 3.0);
  expect_close(s.mu[0](0), 0.5 + step * 1.0);
  expect_close(s.mu[0](1), -0.5 + step * 1.0);
  expect_close(s.sigma[0](0, 0), 1.0 + step * 0.0);
  expect_close(s.sigma[0](0, 1), 0.2 + step * 0.8);
  expect_close(s.sigma[0](1, 0), 0.2 + step * 0.8);
  expect_close(s.sigma[0](1, 1), 0.5 + step * 0.5);
  expect_close(s.baseline(0), 1.2, "0.95 * 1 + 0.05 * 5");
}

TEST(DesignDistributionUpdate, OneChamberKeepsZeroOffDiagonalsAndZeroP2) {
  DesignDistribution q(toy_config(), {1});
  // Same numbers as the two-chamber case: αA = 0.39, d = (1, −2); Σ12 would be −0.78.
  q.update({at(0, 1.0, -2.0)}, {2.0}, kTransit);
  q.update({at(0, 1.0, -2.0)}, {4.0}, kTransit);
  const auto& s = q.state();
  expect_close(s.mu[0](0), 0.39);
  expect_close(s.mu[0](1), -0.78, "z2 is still carried");
  EXPECT_EQ(s.sigma[0](0, 1), 0.0);
  EXPECT_EQ(s.sigma[0](1, 0), 0.0);
  expect_close(s.sigma[0](0, 0), 1.0);
  expect_close(s.sigma[0](1, 1), 2.17);
  // A third, correlated sample: buffer {2, 4, 7}, still Σ12 = 0 exactly.
  q.update({at(0, 3.0, 3.0)}, {7.0}, kTransit);
  EXPECT_EQ(q.state().sigma[0](0, 1), 0.0);
  EXPECT_EQ(q.state().sigma[0](1, 0), 0.0);

  rl::Rng rng(5);
  for (int i = 0; i < 200; ++i) {
    const DesignSample d = q.sample(kTransit, rng);
    EXPECT_EQ(d.pressures_kPa(1), 0.0);
    EXPECT_GT(d.pressures_kPa(0), 0.0);
  }
  EXPECT_EQ(q.mean_pressures_kPa(0)(1), 0.0);
  EXPECT_EQ(q.sigma_pressures_kPa(0)(1), 0.0);
}

TEST(DesignDistributionUpdate, NeverSampledDesignKeepsItsInitialState) {
  DistributionConfig c = toy_config();
  c.latent_mu0 = 0.25;
  c.latent_sigma0 = 1.5;
  DesignDistribution q(c, {2, 2, 1});
  q.update({at(0, 1.0, 1.0), at(0, 0.0, 2.0)}, {3.0, 1.0}, kExplore);
  q.update({at(0, 1.0, 1.0), at(0, -1.0, 2.0), at(0, 2.0, 0.0)}, {2.0, 6.0, 4.0}, kTransit);
  q.update({at(0, 1.0, 1.0)}, {5.0}, kExploit);
  const auto& s = q.state();
  for (int j : {1, 2}) {
    EXPECT_EQ(s.score(j), 0.0);
    EXPECT_EQ(s.baseline(j), 0.0);
    EXPECT_EQ(s.mu[j], Eigen::Vector2d(0.25, 0.25));
    EXPECT_EQ(s.sigma[j], (Eigen::Matrix2d() << 2.25, 0.0, 0.0, 2.25).finished());
    EXPECT_TRUE(s.buffer[j].empty());
    EXPECT_EQ(s.samples[j], 0);
  }
  EXPECT_EQ(s.samples[0], 6);
  EXPECT_NE(s.mu[0], Eigen::Vector2d(0.25, 0.25));  // design 0 did move in transition
}

TEST(DesignDistributionUpdate, ZeroVarianceBufferUpdatesScoreAndBaselineOnly) {
  DesignDistribution fresh(toy_config(), {2});
  DistributionState st = fresh.state();
  st.score(0) = 10.0;  // e.g. a best-so-far from exploration
  st.baseline(0) = 1.0;
  st.buffer[0] = {3.0};
  st.samples[0] = 1;
  st.mu[0] = Eigen::Vector2d(0.2, 0.3);
  st.sigma[0] << 0.5, 0.1, 0.1, 0.4;
  DesignDistribution q(toy_config(), {2}, st);

  q.update({at(0, 5.0, -5.0)}, {3.0}, kTransit);  // buffer {3, 3}: population std 0 → A = 0
  const auto& s = q.state();
  EXPECT_EQ(s.mu[0], st.mu[0]);
  EXPECT_EQ(s.sigma[0], st.sigma[0]);
  expect_close(s.score(0), 3.0, "running mean of {3, 3} replaces the best-so-far 10");
  expect_close(s.baseline(0), 1.1, "0.95 * 1 + 0.05 * 3");
}

TEST(DesignDistributionUpdate, ExplorationKeepsBestSoFarAndResetsToMu0Sigma0) {
  DistributionConfig c = toy_config();
  c.latent_mu0 = 0.25;
  c.latent_sigma0 = 1.5;
  DesignDistribution fresh(c, {2});
  DistributionState st = fresh.state();
  st.mu[0] = Eigen::Vector2d(1.0, 1.0);
  st.sigma[0] << 2.0, 0.3, 0.3, 2.0;
  DesignDistribution q(c, {2}, st);

  q.update({at(0, 4.0, 4.0)}, {-1.0}, kExplore);  // −1 is not > R̂ = 0: nothing but b
  EXPECT_EQ(q.state().score(0), 0.0);
  EXPECT_EQ(q.state().mu[0], st.mu[0]);
  EXPECT_EQ(q.state().sigma[0], st.sigma[0]);

  q.update({at(0, 4.0, 4.0)}, {3.0}, kExplore);  // new best: R̂ = 3, μ0, Σ0
  EXPECT_EQ(q.state().score(0), 3.0);
  EXPECT_EQ(q.state().mu[0], Eigen::Vector2d(0.25, 0.25));
  EXPECT_EQ(q.state().sigma[0], (Eigen::Matrix2d() << 2.25, 0.0, 0.0, 2.25).finished());

  q.update({at(0, 4.0, 4.0)}, {2.0}, kExplore);  // worse: R̂ stays 3
  EXPECT_EQ(q.state().score(0), 3.0);
  EXPECT_EQ(q.state().buffer[0], (std::vector<double>{-1.0, 3.0, 2.0}));
  // b: 0.95*0 − 0.05 = −0.05; 0.95*(−0.05) + 0.15 = 0.1025; 0.95*0.1025 + 0.1 = 0.197375.
  expect_close(q.state().baseline(0), 0.197375);
}

TEST(DesignDistributionUpdate, BaselineFollowsEq9InEveryPhaseAndInSampleOrder) {
  DesignDistribution q(toy_config(), {2, 2});
  // Design 0, one return per call across the phases: 1, 2 (exploration), 3 (transition),
  // 4 (exploitation). Design 1: the same returns in one call.
  q.update({at(0, 0.0, 0.0)}, {1.0}, kExplore);
  expect_close(q.state().baseline(0), 0.05, "0.05 * 1");
  q.update({at(0, 0.0, 0.0)}, {2.0}, 20);
  expect_close(q.state().baseline(0), 0.1475, "0.95 * 0.05 + 0.05 * 2");
  q.update({at(0, 0.0, 0.0)}, {3.0}, kTransit);
  expect_close(q.state().baseline(0), 0.290125, "0.95 * 0.1475 + 0.05 * 3");
  q.update({at(0, 0.0, 0.0)}, {4.0}, kExploit);
  expect_close(q.state().baseline(0), 0.47561875, "0.95 * 0.290125 + 0.05 * 4");

  q.update({at(1, 0.0, 0.0), at(1, 0.0, 0.0), at(1, 0.0, 0.0), at(1, 0.0, 0.0)},
           {1.0, 2.0, 3.0, 4.0}, kExplore);
  expect_close(q.state().baseline(1), 0.47561875);
  EXPECT_EQ(q.state().score(1), 4.0);  // best-so-far
}

TEST(DesignDistributionUpdate, RewardBufferKeepsTheLastEntriesOldestFirst) {
  DistributionConfig c = toy_config();
  c.reward_buffer = 3;
  DesignDistribution q(c, {2});
  for (double r : {1.0, 2.0, 3.0, 4.0, 5.0}) q.update({at(0, 0.0, 0.0)}, {r}, kExplore);
  EXPECT_EQ(q.state().buffer[0], (std::vector<double>{3.0, 4.0, 5.0}));
  EXPECT_EQ(q.state().samples[0], 5);
  q.update({at(0, 0.0, 0.0)}, {9.0}, kTransit);
  expect_close(q.state().score(0), 6.0, "mean{4, 5, 9}");
}

TEST(DesignDistributionUpdate, EigenvalueFloorKeepsSigmaPositiveDefinite) {
  for (int n : {2, 1}) {
    DesignDistribution fresh(toy_config(), {n});
    DistributionState st = fresh.state();
    st.buffer[0] = {0.0, 1.0};
    st.samples[0] = 2;
    DesignDistribution q(toy_config(), {n}, st);

    // R = −1000: buffer {0, 1, −1000}, mean −333, A = (−1000 − 0)/std ≈ −2.12; d = (10, 10).
    q.update({at(0, 10.0, 10.0)}, {-1000.0}, kTransit);
    const double mean = -999.0 / 3.0;
    const double var = ((0.0 - mean) * (0.0 - mean) + (1.0 - mean) * (1.0 - mean) +
                        (-1000.0 - mean) * (-1000.0 - mean)) / 3.0;
    const double step = 0.1 * (-1000.0 / std::sqrt(var));
    const double floor = 1e-3 * 1e-3;
    const Eigen::Matrix2d& s = q.state().sigma[0];
    expect_close(q.state().mu[0](0), step * 10.0);
    EXPECT_EQ(s(0, 1), s(1, 0));
    if (n == 2) {
      // Before the floor: Σ = (1 − αA) I + 100 αA [[1, 1], [1, 1]]: eigenvalue 1 − αA on
      // (1, −1)/√2 and 1 + 199 αA ≈ −41 on (1, 1)/√2; the latter is raised to σ_min².
      // Expected Σ = [[(λ1 + λ2)/2, (λ1 − λ2)/2], ...] with λ1 = σ_min², λ2 = 1 − αA.
      // Tolerance: the eigen-decomposition of a matrix of norm ~42 is exact to ~10 ulp of 42
      // (≈ 1e-13); 1e-12 absolute.
      const double l1 = floor, l2 = 1.0 - step;
      EXPECT_NEAR(s(0, 0), 0.5 * (l1 + l2), 1e-12);
      EXPECT_NEAR(s(1, 1), 0.5 * (l1 + l2), 1e-12);
      EXPECT_NEAR(s(0, 1), 0.5 * (l1 - l2), 1e-12);
    } else {
      // Diagonal: Σ11 = Σ22 = 1 + αA(100 − 1) < 0 → σ_min²; off-diagonals zero.
      EXPECT_EQ(s(0, 0), floor);
      EXPECT_EQ(s(1, 1), floor);
      EXPECT_EQ(s(0, 1), 0.0);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(s);
    // Smallest eigenvalue σ_min² = 1e-6 up to the 1e-12 reconstruction error above.
    EXPECT_GT(eig.eigenvalues().minCoeff(), floor - 1e-12);
    EXPECT_EQ(Eigen::LLT<Eigen::Matrix2d>(s).info(), Eigen::Success);
    rl::Rng rng(3);
    for (int i = 0; i < 50; ++i) EXPECT_TRUE(q.sample(kTransit, rng).latent.allFinite());
  }
}

TEST(DesignDistributionUpdate, RejectsBadInputWithoutChangingState) {
  DesignDistribution q(toy_config(), {2, 2});
  q.update({at(0, 1.0, 2.0)}, {1.0}, kExplore);
  const DistributionState before = q.state();
  EXPECT_THROW(q.update({at(0, 0.0, 0.0)}, {}, kTransit), std::invalid_argument);
  EXPECT_THROW(q.update({at(0, 0.0, 0.0), at(2, 0.0, 0.0)}, {1.0, 1.0}, kTransit),
               std::invalid_argument);
  EXPECT_THROW(q.update({at(0, 0.0, 0.0)}, {std::nan("")}, kTransit), std::invalid_argument);
  EXPECT_THROW(q.update({at(0, INFINITY, 0.0)}, {1.0}, kTransit), std::invalid_argument);
  // Finite but overflowing: d dᵀ = (1e300)² = inf.
  EXPECT_THROW(q.update({at(0, 0.0, 0.0), at(0, 1e300, 0.0)}, {5.0, 9.0}, kTransit),
               std::invalid_argument);
  expect_same_state(q.state(), before);
}

// ---------------------------------------------------------------------------------------------
// Sampling

TEST(DesignDistributionSample, LatentMomentsMatchMuAndSigma) {
  DesignDistribution fresh(toy_config(), {2});
  DistributionState st = fresh.state();
  st.mu[0] = Eigen::Vector2d(0.3, -0.4);
  st.sigma[0] << 0.5, 0.2, 0.2, 0.3;
  const DesignDistribution q(toy_config(), {2}, st);
  const Eigen::Matrix2d sigma = st.sigma[0];

  constexpr int kN = 20000;
  rl::Rng rng(7);
  std::vector<Eigen::Vector2d> z(kN);
  for (int i = 0; i < kN; ++i) {
    const DesignSample d = q.sample(kTransit, rng);
    ASSERT_EQ(d.design, 0);
    z[i] = d.latent;
    if (i < 100) {  // p = 20 / (1 + e^{−z}), by hand
      expect_close(d.pressures_kPa(0), 20.0 / (1.0 + std::exp(-d.latent(0))));
      expect_close(d.pressures_kPa(1), 20.0 / (1.0 + std::exp(-d.latent(1))));
    }
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& v : z) mean += v;
  mean /= kN;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& v : z) cov += (v - mean) * (v - mean).transpose();
  cov /= (kN - 1);
  for (int a = 0; a < 2; ++a) {
    // Standard error of a Gaussian sample mean: sqrt(Σ_aa / N).
    EXPECT_NEAR(mean(a), st.mu[0](a), 5.0 * std::sqrt(sigma(a, a) / kN)) << a;
    for (int b = 0; b < 2; ++b) {
      // Standard error of a Gaussian sample covariance: sqrt((Σ_aa Σ_bb + Σ_ab²) / N).
      const double se = std::sqrt((sigma(a, a) * sigma(b, b) + sigma(a, b) * sigma(a, b)) / kN);
      EXPECT_NEAR(cov(a, b), sigma(a, b), 5.0 * se) << a << "," << b;
    }
  }
}

TEST(DesignDistributionSample, DesignFrequenciesMatchQdisc) {
  DesignDistribution fresh(toy_config(), {2, 1, 2});
  DistributionState st = fresh.state();
  st.score << 0.0, 1.0, 2.0;
  const DesignDistribution q(toy_config(), {2, 1, 2}, st);
  // t = 200: β = 0.6, q ∝ (1, e^0.6, e^1.2).
  const double z = 1.0 + std::exp(0.6) + std::exp(1.2);
  const double expected[3] = {1.0 / z, std::exp(0.6) / z, std::exp(1.2) / z};

  for (std::int64_t t : {std::int64_t{200}, kExplore}) {
    constexpr int kN = 20000;
    rl::Rng rng(11);
    int count[3] = {0, 0, 0};
    for (int i = 0; i < kN; ++i) ++count[q.sample(t, rng).design];
    for (int j = 0; j < 3; ++j) {
      const double qj = t == kExplore ? 1.0 / 3.0 : expected[j];
      // Standard error of a multinomial frequency: sqrt(q (1 − q) / N).
      EXPECT_NEAR(static_cast<double>(count[j]) / kN, qj, 5.0 * std::sqrt(qj * (1 - qj) / kN))
          << "t " << t << " design " << j;
    }
  }
}

TEST(DesignDistributionSample, DrawsOneUniformAndTwoNormalsInEveryPhase) {
  DesignDistribution fresh(toy_config(), {2, 1});
  DistributionState st = fresh.state();
  st.score << 1.0, 2.0;
  DesignDistribution q(toy_config(), {2, 1}, st);
  for (int k = 0; k < 2; ++k) {  // k = 1: after the collapse
    for (std::int64_t t : {kExplore, kTransit, kExploit}) {
      rl::Rng rng(99), reference(99);
      (void)q.sample(t, rng);
      (void)reference.uniform();
      (void)reference.normal();
      (void)reference.normal();
      EXPECT_EQ(rng.next_u64(), reference.next_u64()) << to_string(q.phase(t)) << " " << k;
      EXPECT_EQ(rng.normal(), reference.normal());  // same Box-Muller cache state
    }
    q.collapse();
  }
}

TEST(DesignDistributionSample, CollapsePicksArgmaxLowestIndexThenAlwaysReturnsDstar) {
  DesignDistribution fresh(toy_config(), {2, 1, 2, 2});
  DistributionState st = fresh.state();
  st.score << 1.0, 3.0, 3.0, 2.0;
  for (int j = 0; j < 4; ++j) st.mu[j] = Eigen::Vector2d(0.1 * j, -0.2 * j);
  DesignDistribution q(toy_config(), {2, 1, 2, 2}, st);

  // t ≥ T2 before any update: sample() already returns argmax R̂ (lowest index of the tie).
  rl::Rng rng(1);
  DesignSample d = q.sample(kExploit, rng);
  EXPECT_EQ(d.design, 1);
  EXPECT_EQ(d.latent, st.mu[1]);
  EXPECT_FALSE(q.state().collapsed);

  // The first update at t ≥ T2 collapses; the exploitation return of design 3 changes only b.
  q.update({at(3, 5.0, 5.0)}, {100.0}, kExploit);
  EXPECT_TRUE(q.state().collapsed);
  EXPECT_EQ(q.state().best_design, 1);
  EXPECT_EQ(q.state().best_latent, st.mu[1]);
  EXPECT_EQ(q.state().score(3), 2.0);
  EXPECT_EQ(q.state().mu[3], st.mu[3]);
  EXPECT_EQ(q.state().sigma[3], st.sigma[3]);
  expect_close(q.state().baseline(3), 5.0, "0.05 * 100");

  const Eigen::Vector2d p_star(20.0 / (1.0 + std::exp(-0.1)), 0.0);  // n = 1: p2 = 0
  for (std::int64_t t : {kExploit, std::int64_t{1'000'000}}) {
    for (int i = 0; i < 100; ++i) {
      d = q.sample(t, rng);
      EXPECT_EQ(d.design, 1);
      EXPECT_EQ(d.latent, st.mu[1]);
      expect_close(d.pressures_kPa(0), p_star(0));
      EXPECT_EQ(d.pressures_kPa(1), 0.0);
    }
  }
  // Collapse is idempotent.
  q.collapse();
  EXPECT_EQ(q.state().best_design, 1);

  // All scores equal: design 0.
  DesignDistribution flat(toy_config(), {2, 2, 2});
  flat.collapse();
  EXPECT_EQ(flat.state().best_design, 0);
}

TEST(DesignDistributionSample, SameSeedGivesIdenticalSamples) {
  DesignDistribution a(toy_config(), {2, 1, 2});
  a.update({at(0, 0.5, 0.5), at(1, -0.5, 1.0)}, {2.0, 1.0}, kExplore);
  const DesignDistribution b(toy_config(), {2, 1, 2}, a.state());
  rl::Rng ra(123), rb(123);
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t t = i % 3 == 0 ? kExplore : kTransit;
    const DesignSample x = a.sample(t, ra), y = b.sample(t, rb);
    ASSERT_EQ(x.design, y.design);
    ASSERT_EQ(x.latent, y.latent);
    ASSERT_EQ(x.pressures_kPa, y.pressures_kPa);
  }
}

// ---------------------------------------------------------------------------------------------
// Checkpoint restore

// A synthetic co-design run: 40 designs per iteration, return = −|p1 − 7| − 0.3 j (noisy),
// t += 40 per iteration so T1 = 100 and T2 = 300 are crossed.
void iterate(DesignDistribution& q, std::int64_t t, rl::Rng& rng, rl::Rng& noise) {
  std::vector<DesignSample> samples;
  std::vector<double> returns;
  for (int i = 0; i < 40; ++i) {
    samples.push_back(q.sample(t, rng));
    returns.push_back(-std::abs(samples.back().pressures_kPa(0) - 7.0) -
                      0.3 * samples.back().design + noise.normal());
  }
  q.update(samples, returns, t);
}

TEST(DesignDistributionRestore, RestoredStateContinuesIdentically) {
  const std::vector<int> chambers = {2, 1, 2, 1, 2};
  DesignDistribution a(toy_config(), chambers);
  rl::Rng rng(2024), noise(77);
  std::int64_t t = 0;
  for (; t < 160; t += 40) iterate(a, t, rng, noise);  // into the transition
  ASSERT_EQ(a.phase(t), Phase::Transition);

  DesignDistribution b(toy_config(), chambers, a.state());
  expect_same_state(b.state(), a.state());
  rl::Rng rng_b = rng, noise_b = noise;
  for (; t < 440; t += 40) {
    iterate(a, t, rng, noise);
    iterate(b, t, rng_b, noise_b);
    expect_same_state(b.state(), a.state());
  }
  EXPECT_TRUE(a.state().collapsed);
  // Continuous parameters moved in the transition for the sampled designs.
  int moved = 0;
  for (int j = 0; j < 5; ++j) moved += a.state().mu[j] != Eigen::Vector2d::Zero();
  EXPECT_GT(moved, 0);
}

TEST(DesignDistributionRestore, RejectsStatesThatDoNotFit) {
  const DesignDistribution fresh(toy_config(), {2, 1});
  const DistributionState good = fresh.state();
  EXPECT_NO_THROW(DesignDistribution(toy_config(), {2, 1}, good));
  const std::vector<std::function<void(DistributionState&)>> spoil = {
      [](auto& s) { s.score.resize(3); },
      [](auto& s) { s.mu.pop_back(); },
      [](auto& s) { s.baseline(0) = std::nan(""); },
      [](auto& s) { s.sigma[0] << 1.0, 2.0, 2.0, 1.0; },  // eigenvalues 3 and −1
      [](auto& s) { s.sigma[0] << 1.0, 0.1, 0.2, 1.0; },  // not symmetric
      [](auto& s) { s.sigma[1] << 1.0, 0.1, 0.1, 1.0; },  // 1 chamber with Σ12 ≠ 0
      [](auto& s) { s.buffer[0].assign(101, 1.0); s.samples[0] = 101; },
      [](auto& s) { s.buffer[0] = {1.0, 2.0}; },  // samples[0] = 0 < 2
      [](auto& s) { s.collapsed = true; s.best_design = 2; },
      [](auto& s) { s.best_design = 0; },  // not collapsed
  };
  for (std::size_t k = 0; k < spoil.size(); ++k) {
    DistributionState s = good;
    spoil[k](s);
    EXPECT_THROW(DesignDistribution(toy_config(), {2, 1}, s), std::invalid_argument) << k;
  }
}

}  // namespace
}  // namespace codesign::core
