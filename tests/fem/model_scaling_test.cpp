// A body with scaled constants (fem/model_scaling.hpp) against known answers on a hand-built bar:
// the static equilibrium under gravity depends on mass and modulus only through m g / E (both
// sides of K(x) u = m g scale alike), and for the small sag of this bar the deflection is linear
// in 1/E.
#include <gtest/gtest.h>

#include <cmath>

#include "fem/box_mesh.hpp"
#include "fem/model_scaling.hpp"
#include "fem/simulator.hpp"

namespace codesign::fem {
namespace {

// 40 × 8 × 8 mm bar, 2 g, no plate in reach: gravity sag ≈ w L⁴ / (8 E I) ≈ 0.9 mm.
std::shared_ptr<const Model> bar_model() {
  ModelOptions o;
  o.material.total_mass_g = 2.0;
  o.tip_region_mm = 4.0;
  return build_model(make_box_mesh(40.0, 8.0, 8.0, 10, 2, 2), o);
}

// The tip's z after static steps to equilibrium with the plate out of reach.
double static_tip_z(const std::shared_ptr<const Model>& model) {
  SceneConfig sc;
  sc.plate_amplitude_mm = 0.0;
  SolverConfig so;
  so.method = StepMethod::Exact;
  Simulator sim(model, sc, so);
  sim.set_plate_mean_z(sim.plate_touch_z() - 100.0);
  for (int i = 0; i < 40; ++i) EXPECT_TRUE(sim.static_step().ok());
  return sim.sensors().tip_position_mm[2];
}

TEST(ModelScaling, OnlyTheRatioOfMassToModulusSetsTheStaticSag) {
  const auto nominal = bar_model();
  const double z1 = static_tip_z(nominal);
  const double z2 = static_tip_z(scaled_model(*nominal, {.youngs_modulus = 2.0, .mass = 2.0}));
  // The same equations times 2: equal to the static solve's convergence (the test above in
  // simulator_test.cpp bounds its residual at 1e-6 of the load, so 1e-6 mm of a ~1 mm sag).
  EXPECT_NEAR(z1, z2, 1e-6);
}

TEST(ModelScaling, SagIsInverselyProportionalToTheModulus) {
  const auto nominal = bar_model();
  ModelOptions weightless;
  weightless.material.total_mass_g = 2.0;
  weightless.material.gravity_mm_s2 = 0.0;
  weightless.tip_region_mm = 4.0;
  const double z_rest = static_tip_z(build_model(make_box_mesh(40.0, 8.0, 8.0, 10, 2, 2), weightless));
  const double sag1 = z_rest - static_tip_z(nominal);
  const double sag08 = z_rest - static_tip_z(scaled_model(*nominal, {.youngs_modulus = 0.8}));
  ASSERT_GT(sag1, 0.1);
  // Linear elasticity: sag ∝ 1/E. The co-rotational model departs from it by the geometric
  // nonlinearity, of order (sag / L)² ≈ (1 / 40)² < 0.1 %; 1 % leaves room for the 10 × 2 × 2
  // mesh's discretisation, which is the same at both moduli.
  EXPECT_NEAR(sag08 / sag1, 1.0 / 0.8, 0.01 * 1.25);
}

TEST(ModelScaling, ScalesOnlyWhatItNames) {
  const auto nominal = bar_model();
  const auto s = scaled_model(*nominal, {.youngs_modulus = 1.2, .mass = 0.9, .damping = 1.1, .fibre_stiffness = 0.8});
  EXPECT_DOUBLE_EQ(s->material.youngs_modulus_Pa, 1.2 * nominal->material.youngs_modulus_Pa);
  EXPECT_DOUBLE_EQ(s->material.total_mass_g, 0.9 * nominal->material.total_mass_g);
  EXPECT_DOUBLE_EQ(s->lumped_mass.sum(), 0.9 * nominal->lumped_mass.sum());
  EXPECT_DOUBLE_EQ(s->material.rayleigh_mass_per_s, 1.1 * nominal->material.rayleigh_mass_per_s);
  EXPECT_DOUBLE_EQ(s->material.rayleigh_stiffness_s, 1.1 * nominal->material.rayleigh_stiffness_s);
  EXPECT_EQ(s->material.poisson_ratio, nominal->material.poisson_ratio);
  EXPECT_EQ(s->rest_positions, nominal->rest_positions);
  EXPECT_EQ(s->contact_nodes, nominal->contact_nodes);
  EXPECT_THROW(scaled_model(*nominal, {.youngs_modulus = 0.0}), std::invalid_argument);
  EXPECT_THROW(scaled_model(*nominal, {.mass = NAN}), std::invalid_argument);
}

}  // namespace
}  // namespace codesign::fem
