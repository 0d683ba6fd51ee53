// The whisker task: reward by hand, observation layout, termination and truncation, and
// episodes that do not depend on what the simulator ran before.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <memory>
#include <numbers>

#include "core/whisker_env.hpp"
#include "fem/design.hpp"

namespace {

using namespace codesign;
using core::EpisodeSetup;
using core::ObservationSet;
using core::TaskConfig;
using core::WhiskerEnv;

std::shared_ptr<core::SimulatorPool> pool() {
  static auto p = std::make_shared<core::SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  return p;
}

// Runs one episode with a constant action; returns the rewards.
std::vector<double> episode(WhiskerEnv& env, const EpisodeSetup& s, double action, std::string* reason = nullptr) {
  env.set_episode(s);
  env.reset(std::nullopt);
  std::vector<double> rewards;
  Eigen::VectorXd a(1);
  a[0] = action;
  for (;;) {
    const rl::StepResult r = env.step(a);
    rewards.push_back(r.reward);
    if (r.done()) {
      if (reason) *reason = r.reason;
      break;
    }
  }
  return rewards;
}

TEST(ForceReward, RaisedCosineByHand) {
  TaskConfig t;  // F_t = 20 mN, band ±20 % = ±4 mN, κ = 1.5
  EXPECT_DOUBLE_EQ(core::force_reward(20.0, t), 1.0);
  // δ = 2/4 = 0.5: (½(1 + cos(π/2)))^1.5 = 0.5^1.5 = 0.35355339059327373 (exact arithmetic;
  // 1e-15 covers cos(π/2) ≈ 6e-17 and pow rounding).
  EXPECT_NEAR(core::force_reward(22.0, t), 0.35355339059327373, 1e-15);
  EXPECT_NEAR(core::force_reward(18.0, t), 0.35355339059327373, 1e-15);
  // δ = 1 (band edge) and beyond: 0.
  EXPECT_EQ(core::force_reward(24.0, t), 0.0);
  EXPECT_EQ(core::force_reward(0.0, t), 0.0);
  EXPECT_TRUE(core::in_band(23.9, t));
  EXPECT_FALSE(core::in_band(24.1, t));
}

TEST(WhiskerEnv, ObservationLayouts) {
  for (ObservationSet set : {ObservationSet::Paper, ObservationSet::Proprioceptive, ObservationSet::NoFeedback}) {
    TaskConfig t;
    t.observation = set;
    WhiskerEnv env(pool(), t);
    env.set_episode({63, 5.0, 15.0, 0.0, 0.0});
    const Eigen::VectorXd o = env.reset(std::nullopt);
    ASSERT_EQ(o.size(), core::observation_dim(t));
    // Pressures 5 and 15 of 20 kPa map to −0.5 and +0.5.
    const Eigen::Index p = set == ObservationSet::NoFeedback ? 0 : 3;
    EXPECT_NEAR(o[p], -0.5, 1e-12);
    EXPECT_NEAR(o[p + 1], 0.5, 1e-12);
    if (set != ObservationSet::NoFeedback) {
      const auto j = fem::normalised(fem::design_from_index(63));
      EXPECT_EQ(o[0], j[0]);
      EXPECT_EQ(o[1], j[1]);
      EXPECT_EQ(o[2], j[2]);
    }
    if (set == ObservationSet::Proprioceptive) {
      EXPECT_EQ(o[6], 0.0);  // θ = 0 at the start
      Eigen::VectorXd a(1);
      a[0] = 0.5;
      const rl::StepResult r = env.step(a);
      // θ = 0.5·θ_max = 5° of a 30° limit → 5/30.
      EXPECT_NEAR(r.obs[6], 5.0 / 30.0, 1e-9);
    }
  }
}

// history = k: each set's components, then the last k decisions' time-varying components and
// actions, newest first, padded at the start with the first observation and action 0.
TEST(WhiskerEnv, HistoryStacksPastObservationsAndActionsNewestFirst) {
  constexpr int k = 3;
  TaskConfig plain;
  plain.observation = ObservationSet::Proprioceptive;
  TaskConfig t = plain;
  t.history = k;
  ASSERT_EQ(core::observation_dim(t), 7 + k * 3);
  WhiskerEnv with(pool(), t), without(pool(), plain);
  const core::EpisodeSetup setup{41, 10.0, 0.0, 0.0, 0.0};
  with.set_episode(setup);
  without.set_episode(setup);
  std::vector<Eigen::VectorXd> seen{without.reset(std::nullopt)};
  Eigen::VectorXd o = with.reset(std::nullopt);
  ASSERT_EQ(o.size(), 7 + 3 * k);
  EXPECT_EQ(o.head<7>(), seen[0]);
  for (int i = 0; i < k; ++i) {
    EXPECT_EQ(o[7 + i], seen[0][5]) << "epsilon slot " << i;
    EXPECT_EQ(o[7 + k + i], seen[0][6]) << "theta slot " << i;
    EXPECT_EQ(o[7 + 2 * k + i], 0.0) << "action slot " << i;
  }
  const std::vector<double> actions{0.5, -0.25, 2.0, 0.1};  // 2.0 is applied (and kept) as 1.0
  std::vector<double> applied;
  for (double a : actions) {
    Eigen::VectorXd act(1);
    act[0] = a;
    const rl::StepResult r = with.step(act);
    seen.push_back(without.step(act).obs);
    applied.push_back(std::clamp(a, -1.0, 1.0));
    o = r.obs;
    const int d = static_cast<int>(applied.size());  // decisions taken
    EXPECT_EQ(o.head<7>(), seen.back()) << "decision " << d;  // history does not change the episode
    for (int i = 0; i < k; ++i) {
      const int past = std::max(d - 1 - i, 0);  // observation seen i + 1 decisions ago (padded)
      EXPECT_EQ(o[7 + i], seen[past][5]) << "decision " << d << " epsilon slot " << i;
      EXPECT_EQ(o[7 + k + i], seen[past][6]) << "decision " << d << " theta slot " << i;
      EXPECT_EQ(o[7 + 2 * k + i], d - 1 - i >= 0 ? applied[d - 1 - i] : 0.0) << "decision " << d << " action " << i;
    }
  }
  // The episode restarted: the history forgets the last one.
  o = with.reset(std::nullopt);
  for (int i = 0; i < k; ++i) EXPECT_EQ(o[7 + 2 * k + i], 0.0);
}

// privileged = true appends (F − F_t)/(tol·F_t), θ/θ_limit, sin and cos of the plate's phase
// ω t + φ, and 2·decision/decisions − 1, after an observation that is otherwise unchanged.
TEST(WhiskerEnv, PrivilegedFeaturesFollowTheTrueStateAndLeaveTheObservationAlone) {
  TaskConfig t;  // F_t = 20 mN, tol 0.2: band 4 mN; 250 steps of 0.01 s held 5: 50 decisions
  t.observation = ObservationSet::Proprioceptive;
  WhiskerEnv with(pool(), t, true), without(pool(), t);
  ASSERT_EQ(with.spec().observation.dim(), 7u + core::kPrivilegedDim);
  const double phi = 0.7;
  const core::EpisodeSetup setup{41, 10.0, 0.0, phi, 0.0};
  with.set_episode(setup);
  without.set_episode(setup);
  const fem::SceneConfig scene;  // the pool's: f = 0.8 Hz, θ limit 30°
  const double lim = scene.theta_limit_deg * std::numbers::pi / 180.0;
  auto expect_features = [&](const Eigen::VectorXd& o, const Eigen::VectorXd& plain, double t_s, int decision) {
    ASSERT_EQ(o.size(), 7 + core::kPrivilegedDim);
    EXPECT_EQ(o.head<7>(), plain) << "decision " << decision;
    const fem::Sensors s = with.simulator().sensors();
    EXPECT_NEAR(s.time_s, t_s, 1e-12);
    EXPECT_DOUBLE_EQ(o[7], std::clamp((s.contact_force_mN - 20.0) / 4.0, -core::kObservationClip,
                                      core::kObservationClip));
    EXPECT_DOUBLE_EQ(o[8], s.theta_rad / lim);
    const double phase = 2.0 * std::numbers::pi * scene.plate_frequency_Hz * t_s + phi;
    EXPECT_NEAR(o[9], std::sin(phase), 1e-12);
    EXPECT_NEAR(o[10], std::cos(phase), 1e-12);
    EXPECT_DOUBLE_EQ(o[11], 2.0 * decision / 50.0 - 1.0);
  };
  expect_features(with.reset(std::nullopt), without.reset(std::nullopt), 0.0, 0);
  Eigen::VectorXd a(1);
  for (int d = 1; d <= 3; ++d) {
    a[0] = -0.02 * d;  // small turns away: the force stays near the band (no clipping)
    const rl::StepResult r = with.step(a), p = without.step(a);
    EXPECT_LT(std::abs(r.obs[7]), core::kObservationClip);
    EXPECT_EQ(r.reward, p.reward);
    expect_features(r.obs, p.obs, 0.05 * d, d);
  }
  EXPECT_NEAR(with.simulator().sensors().theta_rad, -0.12 * t.theta_max_rad, 1e-9);
}

TEST(WhiskerEnv, HistoryOfTheNoFeedbackSetIsActionsOnly) {
  TaskConfig t;
  t.observation = ObservationSet::NoFeedback;
  t.history = 2;
  EXPECT_EQ(core::observation_dim(t), 2 + 2);
  t.observation = ObservationSet::Paper;
  EXPECT_EQ(core::observation_dim(t), 6 + 2 * 2);
  t.history = 50;  // 50 decisions per episode: at most 49 past ones
  EXPECT_THROW(WhiskerEnv(pool(), t), std::invalid_argument);
}

TEST(WhiskerEnv, OneChamberIgnoresSecondPressure) {
  TaskConfig t;
  WhiskerEnv env(pool(), t);
  env.set_episode({21, 5.0, 15.0, 0.0, 0.0});
  const Eigen::VectorXd o = env.reset(std::nullopt);
  EXPECT_NEAR(o[4], -1.0, 1e-12);  // p2 reported as 0 kPa
}

TEST(WhiskerEnv, FixedThetaTruncatesAtFiftyDecisionsAndLeavesTheBand) {
  TaskConfig t;
  WhiskerEnv env(pool(), t);
  std::string reason;
  const std::vector<double> r = episode(env, {21, 0.0, 0.0, 0.0, 0.0}, 0.0, &reason);
  EXPECT_EQ(reason, "time_limit");
  ASSERT_EQ(r.size(), 50u);
  double sum = 0.0;
  for (double x : r) {
    EXPECT_GE(x, 0.0);  // a = 0: no penalties
    EXPECT_LE(x, 1.0);
    sum += x;
  }
  EXPECT_LT(env.decisions_in_band(), 50);  // the plate's ±2 mm swing leaves the ±4 mN band
  EXPECT_LT(sum, 50.0);
}

TEST(WhiskerEnv, TurningAwayLosesContact) {
  TaskConfig t;
  WhiskerEnv env(pool(), t);
  std::string reason;
  const std::vector<double> r = episode(env, {21, 0.0, 0.0, 0.0, 0.0}, -1.0, &reason);
  EXPECT_EQ(reason, "lost_contact");
  EXPECT_LT(r.size(), 50u);
  // Full action every decision: r_smooth = 0.05 each, no flips.
  EXPECT_NEAR(r.back(), -0.05, 1e-12);
}

TEST(WhiskerEnv, FlipPenaltyOnSignChange) {
  TaskConfig t;
  WhiskerEnv env(pool(), t);
  env.set_episode({21, 0.0, 0.0, 0.0, 0.0});
  env.reset(std::nullopt);
  Eigen::VectorXd a(1);
  a[0] = 0.2;
  const rl::StepResult r1 = env.step(a);
  a[0] = -0.2;
  const rl::StepResult r2 = env.step(a);
  const fem::Sensors s = env.simulator().sensors();
  // r = r_f − 0.05·0.2 − 0.1 (flip).
  EXPECT_NEAR(r2.reward, core::force_reward(s.contact_force_mN, t) - 0.01 - 0.1, 1e-12);
  (void)r1;
}

TEST(WhiskerEnv, EpisodeDoesNotDependOnEarlierEpisodes) {
  TaskConfig t;
  t.observation = ObservationSet::Proprioceptive;
  const EpisodeSetup target{21, 3.0, 0.0, 1.0, 0.0};
  // Fresh pool: the first simulator ever built for j21.
  auto fresh = std::make_shared<core::SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  WhiskerEnv a(fresh, t);
  a.set_recording(true);
  const std::vector<double> ra = episode(a, target, 0.3);
  const std::vector<core::TraceRow> ta = a.trace();
  // The same simulator object after other episodes (another pressure, phase and actions).
  WhiskerEnv b(fresh, t);
  b.set_recording(true);
  episode(b, {21, 12.0, 0.0, 2.5, 0.0}, -0.2);
  episode(b, {21, 0.0, 0.0, 0.0, 0.0}, 0.7);
  const std::vector<double> rb = episode(b, target, 0.3);
  ASSERT_EQ(ra.size(), rb.size());
  for (std::size_t i = 0; i < ra.size(); ++i) EXPECT_EQ(ra[i], rb[i]) << "decision " << i;  // bit-identical
  ASSERT_EQ(ta.size(), b.trace().size());
  for (std::size_t i = 0; i < ta.size(); ++i) EXPECT_EQ(ta[i].force_mN, b.trace()[i].force_mN) << "step " << i;
  // The same setup again on `a`: restored from its settled snapshot instead of settling.
  EXPECT_EQ(episode(a, target, 0.3), ra);
}

}  // namespace

namespace {

// strain_offset = "inflated": the ε component is ε − ε₀ with ε₀ the strain of the same design at
// the same pressure out of contact, computed here independently with a bare simulator.
TEST(WhiskerEnv, InflatedStrainOffsetSubtractsTheFreeStrainAtThePressures) {
  TaskConfig t;
  t.strain_offset = core::StrainOffset::Inflated;
  WhiskerEnv env(pool(), t);
  const EpisodeSetup s{21, 8.0, 0.0, 0.3, 0.0};
  env.set_episode(s);
  const Eigen::VectorXd obs = env.reset(std::nullopt);

  fem::Simulator free(pool()->model(21), pool()->scene(), pool()->solver());
  free.set_pressures_kPa(8.0, 0.0);
  free.set_plate_mean_z(free.plate_touch_z() - 1000.0);
  ASSERT_TRUE(free.settle().ok());
  const double eps0 = free.sensors().axial_strain;
  // The settle is converged: more static steps move ε₀ by far less than the band, whose half
  // width is ±4 mN × 4.7e-6 per mN ≈ 1.9e-5 of strain (docs/codesign.md); 1 % of it is 1.9e-7.
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(free.static_step().ok());
  EXPECT_NEAR(free.sensors().axial_strain, eps0, 1.9e-7);
  EXPECT_GT(eps0, 1e-3) << "8 kPa inflates the chamber";

  const double eps = env.simulator().sensors().axial_strain;
  const double expected = 2.0 * (eps - eps0 - t.zeroed_strain_min) / (t.zeroed_strain_max - t.zeroed_strain_min) - 1.0;
  EXPECT_NEAR(obs[5], expected, 1e-12);
  // Contact at the settled state moves ε by a small amount only: |ε − ε₀| is under 1e-3 while
  // ε itself is above 1e-3 (the inflation), which is the point of zeroing.
  EXPECT_LT(std::abs(eps - eps0), 1e-3);
  EXPECT_NE(eps, eps0);

  // A second episode with the same design and pressure (another phase) reuses ε₀; one at another
  // pressure computes it again. Both observations match the by-hand value.
  env.set_episode({21, 8.0, 0.0, 2.0, 0.0});
  const Eigen::VectorXd obs2 = env.reset(std::nullopt);
  const double eps2 = env.simulator().sensors().axial_strain;
  EXPECT_NEAR(obs2[5], 2.0 * (eps2 - eps0 - t.zeroed_strain_min) / (t.zeroed_strain_max - t.zeroed_strain_min) - 1.0,
              1e-12);
}

// Zeroing happens on the environment's own simulator; the episode that follows must still not
// depend on it: the same setup on a fresh environment without the offset gives the same forces.
TEST(WhiskerEnv, InflatedStrainOffsetDoesNotChangeTheEpisode) {
  TaskConfig zeroed, raw;
  zeroed.strain_offset = core::StrainOffset::Inflated;
  raw.strain_offset = core::StrainOffset::None;
  WhiskerEnv a(pool(), zeroed);
  WhiskerEnv b(pool(), raw);
  const EpisodeSetup s{40, 5.0, 3.0, 1.1, 0.0};
  const std::vector<double> ra = episode(a, s, 0.02);
  const std::vector<double> rb = episode(b, s, 0.02);
  EXPECT_EQ(ra, rb);
}

}  // namespace
