// Pendulum-v1 against values worked out by hand from Gymnasium's formulas
// (g = 10, m = l = 1, dt = 0.05, so 3g/(2l) = 15 and 3/(m l^2) = 3):
//   cost    = angle_normalize(th)^2 + 0.1 thdot^2 + 0.001 u^2   (state before the step)
//   thdot'  = clip(thdot + (15 sin th + 3 u) * 0.05, -8, 8),   th' = th + 0.05 thdot'
// The implementation evaluates the same expressions in float64; rounding differs from the
// hand values by a few ulp of quantities of order 10, hence the 1e-12 tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rl/pendulum.hpp"

namespace codesign::rl {
namespace {

constexpr double kTol = 1e-12;
constexpr double kPi = std::numbers::pi;

Eigen::VectorXd torque(double u) { return Eigen::VectorXd::Constant(1, u); }

TEST(Pendulum, ThreeStepsMatchHandComputation) {
  Pendulum p;
  p.set_state(0.5, 0.3);

  // Step 1: th = 0.5, thdot = 0.3, u = 1.
  //   cost   = 0.25 + 0.1*0.09 + 0.001*1 = 0.26
  //   sin 0.5 = 0.479425538604203; 15 sin = 7.191383079063045; (7.191383079063045 + 3)*0.05
  //          = 0.509569153953152; thdot' = 0.809569153953152 (|.| < 8, no clip)
  //   th'    = 0.5 + 0.05*0.809569153953152 = 0.540478457697658
  StepResult r = p.step(torque(1.0));
  EXPECT_NEAR(r.reward, -0.26, kTol);
  EXPECT_NEAR(p.theta(), 0.5404784576976576, kTol);
  EXPECT_NEAR(p.theta_dot(), 0.8095691539531522, kTol);
  ASSERT_EQ(r.obs.size(), 3);
  EXPECT_NEAR(r.obs(0), 0.8574625908762682, kTol);  // cos 0.540478457697658
  EXPECT_NEAR(r.obs(1), 0.5145463101099429, kTol);  // sin 0.540478457697658
  EXPECT_NEAR(r.obs(2), 0.8095691539531522, kTol);
  EXPECT_FALSE(r.terminated);
  EXPECT_FALSE(r.truncated);

  // Step 2: th = 0.540478457697658 (already in [-pi, pi)), thdot = 0.809569153953152, u = 1.
  //   cost   = 0.292116963235239 + 0.065540221503242 + 0.001 = 0.358657184738481
  //   15 sin th = 15*0.514546310109943 = 7.718194651649143; (.. + 3)*0.05 = 0.535909732582457
  //   thdot' = 1.345478886535609; th' = 0.540478457697658 + 0.067273944326780 = 0.607752402024438
  r = p.step(torque(1.0));
  EXPECT_NEAR(r.reward, -0.3586571847384811, kTol);
  EXPECT_NEAR(p.theta(), 0.607752402024438, kTol);
  EXPECT_NEAR(p.theta_dot(), 1.3454788865356093, kTol);

  // Step 3: cost = 0.369362982166474 + 0.181031343411310 + 0.001 = 0.551394325577785
  //   15 sin th = 15*0.571023775450262 = 8.56535663175393; (.. + 3)*0.05 = 0.578267831587697
  //   thdot' = 1.923746718123306; th' = 0.607752402024438 + 0.096187335906165 = 0.703939737930603
  r = p.step(torque(1.0));
  EXPECT_NEAR(r.reward, -0.5513943255777848, kTol);
  EXPECT_NEAR(p.theta(), 0.7039397379306034, kTol);
  EXPECT_NEAR(r.obs(0), 0.7622982092375457, kTol);
  EXPECT_NEAR(r.obs(1), 0.6472259576015404, kTol);
  EXPECT_NEAR(r.obs(2), 1.9237467181233059, kTol);
}

TEST(Pendulum, ActionIsClippedToMaxTorque) {
  // th = pi (hanging), thdot = 0, u = 5 -> 2.
  //   cost = angle_normalize(pi)^2 + 0 + 0.001*4 = pi^2 + 0.004 = 9.873604401089358
  //   thdot' = (15 sin pi + 3*2)*0.05 = 0.3 (sin pi = 1.2e-16 in float64, negligible)
  Pendulum p;
  p.set_state(kPi, 0.0);
  StepResult r = p.step(torque(5.0));
  EXPECT_NEAR(r.reward, -9.873604401089358, kTol);
  EXPECT_NEAR(p.theta_dot(), 0.3, kTol);
  EXPECT_NEAR(p.theta(), kPi + 0.015, kTol);

  // The negative side: u = -7 -> -2, same cost, thdot' = -0.3.
  p.set_state(kPi, 0.0);
  r = p.step(torque(-7.0));
  EXPECT_NEAR(r.reward, -9.873604401089358, kTol);
  EXPECT_NEAR(p.theta_dot(), -0.3, kTol);
}

TEST(Pendulum, SpeedIsClippedAndCostUsesOldState) {
  // th = pi/2, thdot = 7.9, u = 2: thdot' = 7.9 + (15 + 6)*0.05 = 8.95 -> 8; th' = pi/2 + 0.4.
  //   cost = (pi/2)^2 + 0.1*62.41 + 0.004 = 2.467401100272340 + 6.241 + 0.004 = 8.712401100272340
  //   (computed from thdot = 7.9, not from the clipped 8).
  Pendulum p;
  p.set_state(kPi / 2, 7.9);
  StepResult r = p.step(torque(2.0));
  EXPECT_NEAR(r.reward, -8.71240110027234, kTol);
  EXPECT_DOUBLE_EQ(p.theta_dot(), 8.0);
  EXPECT_NEAR(p.theta(), kPi / 2 + 0.4, kTol);

  p.set_state(-kPi / 2, -7.9);
  p.step(torque(-2.0));
  EXPECT_DOUBLE_EQ(p.theta_dot(), -8.0);
}

TEST(Pendulum, UnwrappedAngleEntersCostNormalisedAndDynamicsRaw) {
  // th = 7 (> pi), thdot = -2, u = -0.5.
  //   angle_normalize(7) = 7 - 2 pi = 0.716814692820414; squared = 0.513823303843224
  //   cost = 0.513823303843224 + 0.1*4 + 0.001*0.25 = 0.914073303843224
  //   15 sin 7 = 15*0.656986598718789 = 9.854798980781837
  //   thdot' = -2 + (9.854798980781837 - 1.5)*0.05 = -1.582260050960908
  //   th' = 7 - 0.079113002548045 = 6.920886997451954 (not wrapped)
  Pendulum p;
  p.set_state(7.0, -2.0);
  StepResult r = p.step(torque(-0.5));
  EXPECT_NEAR(r.reward, -0.9140733038432242, kTol);
  EXPECT_NEAR(p.theta_dot(), -1.5822600509609082, kTol);
  EXPECT_NEAR(p.theta(), 6.920886997451954, kTol);
}

TEST(Pendulum, AngleNormalizeIsPythonFloorModulo) {
  EXPECT_DOUBLE_EQ(angle_normalize(0.0), 0.0);
  EXPECT_NEAR(angle_normalize(0.1 + 2 * kPi), 0.1, kTol);
  EXPECT_NEAR(angle_normalize(0.1 - 4 * kPi), 0.1, kTol);
  EXPECT_NEAR(angle_normalize(1.5 * kPi), -0.5 * kPi, kTol);
  EXPECT_NEAR(angle_normalize(-1.5 * kPi), 0.5 * kPi, kTol);
  // (pi + pi) % 2pi = 0, so pi maps to -pi; the range is [-pi, pi).
  EXPECT_DOUBLE_EQ(angle_normalize(kPi), -kPi);
  EXPECT_DOUBLE_EQ(angle_normalize(-kPi), -kPi);
  for (double x = -20.0; x <= 20.0; x += 0.37) {
    const double a = angle_normalize(x);
    EXPECT_GE(a, -kPi);
    EXPECT_LT(a, kPi);
    EXPECT_NEAR(std::remainder(a - x, 2 * kPi), 0.0, 1e-12);
  }
}

TEST(Pendulum, TruncatedAtStep200AndNeverTerminated) {
  std::unique_ptr<Env> env = make_pendulum();
  env->reset(3);
  for (int t = 1; t <= 200; ++t) {
    StepResult r = env->step(torque(t % 2 ? 2.0 : -2.0));
    EXPECT_FALSE(r.terminated) << "step " << t;
    EXPECT_EQ(r.truncated, t == 200) << "step " << t;
    if (t == 200) {
      EXPECT_EQ(r.reason, "time_limit");
    }
  }
  // A reset restarts the count.
  env->reset(std::nullopt);
  for (int t = 1; t < 200; ++t) ASSERT_FALSE(env->step(torque(0.0)).done());
  EXPECT_TRUE(env->step(torque(0.0)).truncated);
}

TEST(Pendulum, ResetDistributionBoundsAndSeeding) {
  Pendulum p;
  double th_min = 10, th_max = -10, w_min = 10, w_max = -10;
  p.reset(123);
  for (int i = 0; i < 2000; ++i) {
    Eigen::VectorXd obs = p.reset(std::nullopt);
    th_min = std::min(th_min, p.theta());
    th_max = std::max(th_max, p.theta());
    w_min = std::min(w_min, p.theta_dot());
    w_max = std::max(w_max, p.theta_dot());
    EXPECT_DOUBLE_EQ(obs(0), std::cos(p.theta()));
    EXPECT_DOUBLE_EQ(obs(1), std::sin(p.theta()));
    EXPECT_DOUBLE_EQ(obs(2), p.theta_dot());
  }
  EXPECT_GE(th_min, -kPi);
  EXPECT_LT(th_max, kPi);
  EXPECT_GE(w_min, -1.0);
  EXPECT_LT(w_max, 1.0);
  // The draws fill the intervals: P(no draw within 0.05 of an end) = (1 - 0.05/(2pi))^2000 ~ 1e-7
  // for theta and (1 - 0.05/2)^2000 ~ 1e-22 for thdot.
  EXPECT_LT(th_min, -kPi + 0.05);
  EXPECT_GT(th_max, kPi - 0.05);
  EXPECT_LT(w_min, -0.95);
  EXPECT_GT(w_max, 0.95);

  // Same seed, same start; different seeds, different starts.
  Pendulum a, b;
  EXPECT_EQ(a.reset(7), b.reset(7));
  EXPECT_NE(a.reset(7), b.reset(8));
}

TEST(Pendulum, SpecMatchesGymnasium) {
  Pendulum p;
  const EnvSpec& s = p.spec();
  ASSERT_EQ(s.observation.dim(), 3u);
  ASSERT_EQ(s.action.dim(), 1u);
  EXPECT_EQ(s.observation.high, Eigen::Vector3d(1, 1, 8));
  EXPECT_EQ(s.observation.low, Eigen::Vector3d(-1, -1, -8));
  EXPECT_EQ(s.action.low(0), -2.0);
  EXPECT_EQ(s.action.high(0), 2.0);
}

}  // namespace
}  // namespace codesign::rl
