// The PID controller by hand, the PID tuner on a plant with an analytic optimum, bad gains and
// bounds, and the sign convention on the real whisker (F rises with the base angle).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "core/pid_tuning.hpp"
#include "core/simulator_pool.hpp"
#include "core/whisker_env.hpp"

namespace codesign::core {
namespace {

TEST(PidController, StepsByHand) {
  // e = 0.2, 0.1, -0.1 with Kp 0.5, Ki 0.25, Kd 1:
  //   k=0: I = 0.2,  u = 0.1 + 0.05 + 0 (no derivative kick)      = 0.15
  //   k=1: I = 0.3,  u = 0.05 + 0.075 + 1·(0.1 − 0.2)              = 0.025
  //   k=2: I = 0.2,  u = −0.05 + 0.05 + 1·(−0.1 − 0.1)              = −0.2
  PidController c({0.5, 0.25, 1.0});
  EXPECT_NEAR(c.act(0.2), 0.15, 1e-15);
  EXPECT_NEAR(c.act(0.1), 0.025, 1e-15);
  EXPECT_NEAR(c.act(-0.1), -0.2, 1e-15);
  EXPECT_NEAR(c.integral(), 0.2, 1e-15);
  c.reset();
  EXPECT_EQ(c.integral(), 0.0);
  EXPECT_NEAR(c.act(0.2), 0.15, 1e-15);
}

TEST(PidController, ClipsAndDoesNotWindUp) {
  // Kp 0, Ki 1, constant error 3: the first step integrates (the output with I = 0 is not
  // saturated) and is clipped to 1; from then on the output with the old integral (3) is
  // saturated in the error's direction, so the integral stays at 3 instead of growing by 3 a
  // step. When the error turns (−0.5), it integrates again: I = 2.5, output still clipped at 1.
  PidController c({0.0, 1.0, 0.0});
  EXPECT_EQ(c.act(3.0), 1.0);
  EXPECT_EQ(c.act(3.0), 1.0);
  EXPECT_EQ(c.act(3.0), 1.0);
  EXPECT_EQ(c.integral(), 3.0);
  EXPECT_EQ(c.act(-0.5), 1.0);
  EXPECT_EQ(c.integral(), 2.5);
  EXPECT_EQ(c.act(NAN), 0.0);  // a failed reading: no action, state unchanged
  EXPECT_EQ(c.integral(), 2.5);
}

TEST(PidController, InvalidGainsAreClearErrors) {
  try {
    PidController c({0.1, -0.2, 0.0});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "PID gain ki = -0.200000 is invalid: gains must be finite and >= 0");
  }
  EXPECT_THROW(PidController({NAN, 0, 0}), std::invalid_argument);
  EXPECT_THROW(PidController({0, 0, INFINITY}), std::invalid_argument);
  PidBox b;
  b.kp = {0.5, 0.1};
  try {
    b.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "PID bounds: kp range [0.500000, 0.100000] has its lower bound above its upper bound");
  }
  b = PidBox{};
  b.kd = {-1.0, 1.0};
  EXPECT_THROW(b.validate(), std::invalid_argument);
  b = PidBox{};
  b.offset = {0.0, NAN};
  EXPECT_THROW(b.validate(), std::invalid_argument);
  EXPECT_THROW(tune_pid([](const PidGains&, double) { return 0.0; }, PidBox{}, SearchOptions{}, {-0.1, 0, 0}),
               std::invalid_argument);
}

// The plant: an integrator with gain b and a sensor bias d,
//   y_{k+1} = y_k + b·u_k,  measured m_k = y_k + d,  the PID sees e_k = (r + offset) − m_k,
// tracking r = 0 from starting errors y_0 ∈ {0.5, −0.3, 0.8}, return −Σ_{k=1..N} y_k².
// Analytic optimum: with offset = d the PID sees the true error ε_k = −y_k, which evolves as
// ε_{k+1} = ε_k − b·u_k. Since I_0 = ε_0 and there is no derivative kick,
//   ε_1 = ε_0(1 − b(Kp + Ki))            → zero for every ε_0 iff Kp + Ki = 1/b,
//   ε_2 = ε_1 − b(Kp ε_1 + Ki(ε_0 + ε_1) + Kd(ε_1 − ε_0)) = −b ε_0 (Ki − Kd) when ε_1 = 0
//                                          → zero iff Ki = Kd,
//   ε_3 = −b Ki ε_0 when ε_1 = ε_2 = 0    → zero iff Ki = 0 = Kd.
// So the return reaches its maximum 0 only at (Kp, Ki, Kd, offset) = (1/b, 0, 0, d); any other
// offset leaves a steady error (the integrator plant with a P term settles where e = 0, i.e.
// at y = offset − d). With b = 2, d = 0.3: (0.5, 0, 0, 0.3). There the actions
// |u_0| = 0.5·|y_0| ≤ 0.4 stay inside ±1, so clipping plays no part at the optimum.
double integrator_return(const PidGains& g, double offset) {
  constexpr double b = 2.0, d = 0.3;
  double ret = 0.0;
  for (double y0 : {0.5, -0.3, 0.8}) {
    PidController c(g);
    double y = y0;
    for (int k = 0; k < 12; ++k) {
      y += b * c.act(offset - (y + d));
      ret -= y * y;
    }
  }
  return ret;
}

TEST(PidTuning, RecoversTheDeadBeatGainsAndTheSensorBias) {
  EXPECT_EQ(integrator_return({0.5, 0.0, 0.0}, 0.3), 0.0);
  PidBox box{{0.0, 2.0}, {0.0, 1.0}, {0.0, 1.0}, {-1.0, 1.0}};
  SearchOptions o;
  o.starts = 3;
  o.max_evals = 900;
  o.xtol_rel = 1e-9;
  o.ftol_abs = 1e-16;
  const PidSearch s = tune_pid(integrator_return, box, o, {0.1, 0.1, 0.1}, 0.0);
  // Near the optimum the return is a quadratic form in the deviations whose smallest curvature
  // is of order b²·Σy_0² ≈ 4; with ftol 1e-16 a deviation δ of the gains costs ≥ ~4δ², so the
  // search can stop no farther than δ ~ 1e-8 from it. We allow 1e-4.
  EXPECT_NEAR(s.gains.kp, 0.5, 1e-4);
  EXPECT_NEAR(s.gains.ki, 0.0, 1e-4);
  EXPECT_NEAR(s.gains.kd, 0.0, 1e-4);
  EXPECT_NEAR(s.offset, 0.3, 1e-4);
  EXPECT_GE(s.value, -1e-7);
  EXPECT_LE(s.evaluations, 900);
}

TEST(PidTuning, ForceRisesWithTheBaseAngle) {
  // pid_controller.hpp's sign convention: a larger base angle presses the tip harder on the
  // plate. docs/codesign.md: 1° moves the tip ≈ 1.5 mm, with a tip compliance of 0.214 mm/mN
  // ≈ 7 mN; we check the sign and the size within a factor of two.
  auto sims = std::make_shared<SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  TaskConfig task;
  auto settled_force = [&](double theta0) {
    WhiskerEnv env(sims, task);
    env.set_episode({21, 0.0, 0.0, 0.0, theta0});
    env.reset(std::nullopt);
    return env.simulator().sensors().contact_force_mN;
  };
  const double f0 = settled_force(0.0), f1 = settled_force(std::numbers::pi / 180.0);
  EXPECT_GT(f1 - f0, 3.5) << f0 << " -> " << f1;
  EXPECT_LT(f1 - f0, 14.0) << f0 << " -> " << f1;
  // The force PID's error is positive below the target and one at the band's lower edge.
  WhiskerPid pid;
  pid.setpoint = task.target_force_mN;
  fem::Sensors s;
  s.contact_force_mN = task.target_force_mN * (1.0 - task.tolerance_fraction);
  EXPECT_NEAR(pid_error(pid, s, task), 1.0, 1e-12);
}

}  // namespace
}  // namespace codesign::core
