// [randomize]'s draws (core/physics_randomization.hpp): nominal when off, a pure function of
// (seed, k, env), inside their ranges and spread over them, and one range's width never moves
// another parameter's draw.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/physics_randomization.hpp"

namespace codesign::core {
namespace {

RandomizeConfig quarter() {
  RandomizeConfig c;
  c.youngs_modulus = 0.25;
  c.plate_height_mm = 1.0;
  c.strain_noise = 1e-4;
  return c;
}

TEST(PhysicsRandomization, OffIsNominalForEveryEnvironment) {
  const RandomizeConfig off;
  EXPECT_FALSE(off.enabled());
  for (std::size_t env = 0; env < 5; ++env) EXPECT_EQ(draw_physics(off, 7, 3, env), PhysicsDraw{});
  EXPECT_EQ(PhysicsDraw{}.simulation_part(), PhysicsDraw{});
}

TEST(PhysicsRandomization, APureFunctionOfSeedIterationAndEnvironment) {
  const RandomizeConfig c = quarter();
  EXPECT_EQ(draw_physics(c, 1, 10, 3), draw_physics(c, 1, 10, 3));
  EXPECT_NE(draw_physics(c, 1, 10, 3).youngs_scale, draw_physics(c, 1, 10, 4).youngs_scale);
  EXPECT_NE(draw_physics(c, 1, 10, 3).youngs_scale, draw_physics(c, 1, 11, 3).youngs_scale);
  EXPECT_NE(draw_physics(c, 1, 10, 3).youngs_scale, draw_physics(c, 2, 10, 3).youngs_scale);
  EXPECT_NE(draw_physics(c, 1, 10, 3).noise_seed, draw_physics(c, 1, 10, 4).noise_seed);
}

TEST(PhysicsRandomization, DrawsFillTheirRangesUniformly) {
  const RandomizeConfig c = quarter();
  const int n = 4000;
  double lo = 2.0, hi = 0.0, sum = 0.0, h_lo = 9.0, h_hi = -9.0;
  for (int i = 0; i < n; ++i) {
    const PhysicsDraw d = draw_physics(c, 5, i / 40, static_cast<std::size_t>(i % 40));
    ASSERT_GE(d.youngs_scale, 0.75);
    ASSERT_LE(d.youngs_scale, 1.25);
    ASSERT_LE(std::abs(d.plate_height_offset_mm), 1.0);
    EXPECT_EQ(d.fibre_scale, 1.0);  // zero ranges stay nominal exactly
    EXPECT_EQ(d.strain_offset, 0.0);
    EXPECT_EQ(d.strain_noise, 1e-4);
    EXPECT_NE(d.simulation_part(), PhysicsDraw{});
    lo = std::min(lo, d.youngs_scale);
    hi = std::max(hi, d.youngs_scale);
    h_lo = std::min(h_lo, d.plate_height_offset_mm);
    h_hi = std::max(h_hi, d.plate_height_offset_mm);
    sum += d.youngs_scale;
  }
  // U[0.75, 1.25] has standard deviation 0.25/√3; the mean of n draws is within 5 of its
  // standard errors of 1 unless the draws are biased (a 5σ miss: p < 1e-6).
  EXPECT_NEAR(sum / n, 1.0, 5.0 * 0.25 / std::sqrt(3.0 * n));
  // Both ends are reached to within 1 % of the width: missing one has probability (1 − 0.01)^n.
  EXPECT_LT(lo, 0.75 + 0.005);
  EXPECT_GT(hi, 1.25 - 0.005);
  EXPECT_LT(h_lo, -1.0 + 0.02);
  EXPECT_GT(h_hi, 1.0 - 0.02);
}

TEST(PhysicsRandomization, WideningOneRangeLeavesTheOthersDraws) {
  RandomizeConfig a = quarter(), b = quarter();
  b.mass = 0.1;
  for (std::size_t env = 0; env < 8; ++env) {
    const PhysicsDraw da = draw_physics(a, 3, 2, env), db = draw_physics(b, 3, 2, env);
    EXPECT_EQ(da.youngs_scale, db.youngs_scale);
    EXPECT_EQ(da.plate_height_offset_mm, db.plate_height_offset_mm);
    EXPECT_EQ(da.noise_seed, db.noise_seed);
    EXPECT_EQ(da.mass_scale, 1.0);
    EXPECT_NE(db.mass_scale, 1.0);
  }
}

TEST(PhysicsRandomization, WallLevelsAreThreeEquallyLikelyAndDrawnLast) {
  RandomizeConfig a = quarter(), b = quarter();
  b.wall_mm = 0.2;
  int count[3] = {0, 0, 0};
  const int n = 3000;
  for (int i = 0; i < n; ++i) {
    const auto env = static_cast<std::size_t>(i % 30);
    const PhysicsDraw da = draw_physics(a, 9, i / 30, env), db = draw_physics(b, 9, i / 30, env);
    EXPECT_EQ(da.wall_offset_mm, 0.0);
    // The table's other draws, the noise stream among them, are those of a run without walls.
    PhysicsDraw without = db;
    without.wall_offset_mm = 0.0;
    ASSERT_EQ(without, da);
    ASSERT_TRUE(db.wall_offset_mm == -0.2 || db.wall_offset_mm == 0.0 || db.wall_offset_mm == 0.2);
    ++count[db.wall_offset_mm < 0 ? 0 : db.wall_offset_mm == 0 ? 1 : 2];
    EXPECT_EQ(db.simulation_part().wall_offset_mm, db.wall_offset_mm);  // keys the caches
  }
  // Each level has probability 1/3: a count within 5 binomial standard deviations, √(n·⅓·⅔).
  for (const int c : count) EXPECT_NEAR(c, n / 3.0, 5.0 * std::sqrt(n * 2.0 / 9.0));
}

}  // namespace
}  // namespace codesign::core
