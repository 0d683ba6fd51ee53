// Episodes under drawn physics (EpisodeSetup::physics, core/physics_randomization.hpp) against
// known answers: with no chamber pressure, E, mass and fibre stiffness scaled by one factor s
// scale every force of the equations of motion (elastic, fibre, inertial, Rayleigh and gravity
// alike), so the body moves exactly as the nominal one and every contact force is s times the
// nominal; the gauge's gain scales the tared strain the policy sees; a delayed actuation turns the
// base one decision late; the inflation cue is the gauge's two-point reading, offset-free; a wall cast
// 0.5 mm thicker is the grid's next wall.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "core/whisker_env.hpp"

namespace codesign::core {
namespace {

std::shared_ptr<SimulatorPool> pool() {
  static auto p = std::make_shared<SimulatorPool>(fem::WhiskerModelSpec{}, fem::SceneConfig{}, fem::SolverConfig{});
  return p;
}

struct Reading {
  double force_mN, strain, theta_rad;
  Eigen::VectorXd obs;
};

// Ten decisions with a constant action; the state after each.
std::vector<Reading> run(const EpisodeSetup& setup, double action, const TaskConfig& task = {}) {
  WhiskerEnv env(pool(), task);
  env.set_episode(setup);
  Eigen::VectorXd obs = env.reset(std::nullopt);
  std::vector<Reading> out;
  Eigen::VectorXd a(1);
  a[0] = action;
  for (int k = 0; k < 10; ++k) {
    const rl::StepResult r = env.step(a);
    const fem::Sensors s = env.simulator().sensors();
    out.push_back({s.contact_force_mN, s.axial_strain, s.theta_rad, r.obs});
    if (r.done()) break;
  }
  return out;
}

TEST(WhiskerEnvPhysics, ScalingModulusMassAndFibresTogetherScalesEveryForce) {
  EpisodeSetup nominal{21, 0.0, 0.0, 1.0, 0.0};
  EpisodeSetup stiff = nominal;
  stiff.physics.youngs_scale = stiff.physics.mass_scale = stiff.physics.fibre_scale = 1.2;
  const std::vector<Reading> a = run(nominal, 0.3), b = run(stiff, 0.3);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.back().force_mN, 1.0);
  for (std::size_t k = 0; k < a.size(); ++k) {
    // The same equations times 1.2, solved by the same iterations: equal up to the solvers'
    // tolerances (CG to 1e-8 relative, the LCP's), far below the 20 % a wrong scaling would show.
    EXPECT_NEAR(b[k].force_mN, 1.2 * a[k].force_mN, 1e-4 * a[k].force_mN + 1e-6) << "decision " << k;
    EXPECT_NEAR(b[k].strain, a[k].strain, 1e-6 * std::abs(a[k].strain) + 1e-12) << "decision " << k;
  }
}

TEST(WhiskerEnvPhysics, GainScalesTheTaredStrainAndTheOffsetCancels) {
  TaskConfig task;  // strain_offset = "inflated": the policy sees g (ε − ε₀) + b − b
  EpisodeSetup nominal{21, 10.0, 0.0, 1.0, 0.0};
  EpisodeSetup gauge = nominal;
  gauge.physics.strain_gain = 1.1;
  gauge.physics.strain_offset = 0.003;
  const std::vector<Reading> a = run(nominal, 0.0, task), b = run(gauge, 0.0, task);
  ASSERT_EQ(a.size(), b.size());
  const double width = task.zeroed_strain_max - task.zeroed_strain_min;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].force_mN, b[k].force_mN);  // the sensors do not touch the simulation
    // obs[5] = 2 (x − min) / width − 1: the gain scales x = ε − ε₀ exactly; round-off of the
    // offset's addition and subtraction is of order 1e-16 · 0.003 / width.
    const double xa = (a[k].obs[5] + 1.0) * width / 2.0 + task.zeroed_strain_min;
    const double xb = (b[k].obs[5] + 1.0) * width / 2.0 + task.zeroed_strain_min;
    EXPECT_NEAR(xb, 1.1 * xa, 1e-12) << "decision " << k;
  }
}

TEST(WhiskerEnvPhysics, DelayedActuationTurnsTheBaseOneDecisionLate) {
  EpisodeSetup delayed{21, 0.0, 0.0, 1.0, 0.0};
  delayed.physics.actuation_delay = true;
  const TaskConfig task;
  const std::vector<Reading> a = run(delayed, 0.5, task);
  ASSERT_GE(a.size(), 3u);
  EXPECT_EQ(a[0].theta_rad, 0.0);  // the first command is still on its way
  EXPECT_NEAR(a[1].theta_rad, 0.5 * task.theta_max_rad, 1e-12);
  EXPECT_NEAR(a[2].theta_rad, 2 * 0.5 * task.theta_max_rad, 1e-12);
}

// The inflation cue (TaskConfig::stiffness_cue = "inflation"), last component, unscaled back to
// the reading g (ε(p) − ε(0)).
double inflation_reading(const Reading& r, const TaskConfig& task) {
  return (r.obs[r.obs.size() - 1] + 1.0) * task.strain_max / 2.0;
}

TEST(WhiskerEnvPhysics, InflationCueIsTheGaugesTwoPointReadingAndTracksStiffness) {
  TaskConfig task;
  task.stiffness_cue = StiffnessCue::Inflation;
  EXPECT_EQ(observation_dim(task), observation_dim(TaskConfig{}) + 1);
  const EpisodeSetup nominal{21, 10.0, 0.0, 1.0, 0.0};
  const std::vector<Reading> a = run(nominal, 0.2, task);
  ASSERT_GE(a.size(), 2u);
  const double reading = inflation_reading(a[0], task);
  EXPECT_GT(reading, 0.0);  // inflating lengthens the chamber
  EXPECT_EQ(a.back().obs[a.back().obs.size() - 1], a[0].obs[a[0].obs.size() - 1]);  // constant in an episode

  // The gauge's offset cancels and its gain scales the reading (round-off of 1e-16 · 0.003).
  EpisodeSetup gauge = nominal;
  gauge.physics.strain_gain = 1.1;
  gauge.physics.strain_offset = 0.003;
  EXPECT_NEAR(inflation_reading(run(gauge, 0.2, task)[0], task), 1.1 * reading, 1e-12);

  // E, mass and fibres ×1.2 at 12 kPa are the nominal equations at 10 kPa times 1.2 (every force
  // scales, gravity too): the same strains, so the same reading up to the solvers' tolerances
  // (CG to 1e-8 relative). At 10 kPa the stiffer body reads less.
  EpisodeSetup stiff = nominal;
  stiff.physics.youngs_scale = stiff.physics.mass_scale = stiff.physics.fibre_scale = 1.2;
  EXPECT_LT(inflation_reading(run(stiff, 0.2, task)[0], task), reading);
  stiff.p1_kPa = 12.0;
  EXPECT_NEAR(inflation_reading(run(stiff, 0.2, task)[0], task), reading, 1e-6 * reading);
}

TEST(WhiskerEnvPhysics, TrueModulusCueIsTheDrawnScaleOnTheRandomizedRange) {
  TaskConfig task;
  task.stiffness_cue = StiffnessCue::TrueModulus;
  task.randomize.youngs_modulus = 0.25;
  EpisodeSetup soft{21, 10.0, 0.0, 1.0, 0.0};
  soft.physics.youngs_scale = 0.8;
  const std::vector<Reading> a = run(soft, 0.2, task);
  // 0.8 on [0.75, 1.25] → 2 (0.8 − 0.75) / 0.5 − 1 = −0.8.
  EXPECT_NEAR(a[0].obs[a[0].obs.size() - 1], -0.8, 1e-12);
}

TEST(WhiskerEnvPhysics, ACastWallHalfAMillimetreThickerIsTheNextWallOfTheGrid) {
  // j21 = {1, 28 mm, 2.5 mm} cast 0.5 mm thicker is j22 = {1, 28 mm, 3.0 mm}: the same geometry,
  // meshed the same deterministic way, so the same episode to the bit.
  EpisodeSetup cast{21, 10.0, 0.0, 1.0, 0.0};
  cast.physics.wall_offset_mm = 0.5;
  const EpisodeSetup grid{22, 10.0, 0.0, 1.0, 0.0};
  const std::vector<Reading> a = run(cast, 0.3), b = run(grid, 0.3);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].force_mN, b[k].force_mN) << "decision " << k;
    EXPECT_EQ(a[k].strain, b[k].strain) << "decision " << k;
  }
}

TEST(WhiskerEnvPhysics, TheExtremeWallLevelsMeshAndAThickerWallInflatesLess) {
  // The thinnest and the thickest bodies of the grid at the widest level, [randomize] wall_mm
  // 0.25: both must mesh and settle, or a run that draws them would stop.
  TaskConfig task;
  task.stiffness_cue = StiffnessCue::Inflation;
  for (const auto& [design, offset] : {std::pair{55, -0.25}, std::pair{109, 0.25}, std::pair{0, -0.25}, std::pair{54, 0.25}}) {
    EpisodeSetup s{design, 10.0, 10.0, 1.0, 0.0};
    s.physics.wall_offset_mm = offset;
    const std::vector<Reading> r = run(s, 0.0, task);
    ASSERT_FALSE(r.empty()) << "j" << design;
    EXPECT_TRUE(std::isfinite(r[0].force_mN)) << "j" << design;
  }
  EpisodeSetup thin{21, 10.0, 0.0, 1.0, 0.0}, thick = thin;
  thin.physics.wall_offset_mm = -0.25;
  thick.physics.wall_offset_mm = 0.25;
  EXPECT_GT(inflation_reading(run(thin, 0.0, task)[0], task), inflation_reading(run(thick, 0.0, task)[0], task));
}

}  // namespace
}  // namespace codesign::core
