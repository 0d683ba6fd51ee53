// Static force balance of the whole scene at rest: base reaction + contact + weight (+ net
// pressure force) = 0 for the default whisker resting on the plate under gravity.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fem/design.hpp"
#include "fem/pressure.hpp"
#include "fem/simulator.hpp"
#include "fem/static_solve.hpp"
#include "fem/whisker_mesh.hpp"

namespace {

using namespace codesign::fem;

// Identity behind the tolerance: the elastic forces of the body sum to zero (translation
// invariance), so base_reaction + F ẑ + m g + P_net = Σ_{free nodes} r_i, where
// r = f_el + m_i g + f_p + contact is the out-of-balance force of the static iteration. Hence
// |imbalance| ≤ Σ_free |r_i|, computed here independently of the simulator (own force assembly
// with the SVD polar factor). The simulator is iterated with static steps until Σ_free |r_i| is
// ≤ 1e-4 of the weight (rest); the balance must then hold to that bound, and the simulator's own
// reaction must agree with the independent one to round-off (1e-9 of the weight).
TEST(ValidationForceBalance, BaseReactionPlusContactPlusWeightVanishAtRest) {
  WhiskerGeometry g;
  g.design = design_from_index(21);
  const auto model = build_model(mesh_whisker(g), ModelOptions{});
  SceneConfig scene;
  scene.plate_amplitude_mm = 0.0;
  SolverConfig solver;
  solver.method = StepMethod::Exact;
  Simulator sim(model, scene, solver);
  sim.reset();
  sim.set_pressures_kPa(10.0, 0.0);  // chamber pressurised: the pressure force must cancel (closed cavity)
  ASSERT_TRUE(sim.settle().ok());

  const double weight = model->material.total_mass_g * model->material.gravity_mm_s2;  // µN
  const Eigen::Vector3d gvec(0.0, 0.0, -model->material.gravity_mm_s2);
  const auto residual_sum = [&](Eigen::Vector3d* net) {
    const Eigen::VectorXd& x = sim.positions();
    Eigen::VectorXd r = elastic_forces(*model, x);
    for (int i = 0; i < model->node_count(); ++i) r.segment<3>(3 * i) += model->lumped_mass[i] * gvec;
    add_pressure_forces(model->mesh, x, {1e4, 0.0}, r);
    for (const auto& [node, lambda] : sim.contact_forces()) r[3 * node + 2] += lambda;
    double abs_sum = 0.0;
    net->setZero();
    for (int i = 0; i < model->node_count(); ++i)
      if (!model->is_base[static_cast<std::size_t>(i)]) {
        abs_sum += r.segment<3>(3 * i).norm();
        *net += r.segment<3>(3 * i);
      }
    return abs_sum;
  };
  Eigen::Vector3d net;
  double rsum = residual_sum(&net);
  int steps = 0;
  for (; steps < 300 && rsum > 1e-4 * weight; ++steps) {
    ASSERT_TRUE(sim.static_step().ok());
    rsum = residual_sum(&net);
  }
  const Sensors s = sim.sensors();
  const double F = 1e3 * s.contact_force_mN;  // µN
  const Eigen::Vector3d imbalance =
      sim.base_reaction() + Eigen::Vector3d(0.0, 0.0, F) + Eigen::Vector3d(0.0, 0.0, -weight) + sim.pressure_force();
  std::printf("[balance] static steps %d, F = %.4f mN, weight = %.4f mN, base reaction = (%.4f, %.4f, %.4f) mN, "
              "net pressure = %.2e mN, |imbalance| = %.3e mN, sum|r_free| = %.3e mN, |net r_free| = %.3e mN\n",
              steps, s.contact_force_mN, 1e-3 * weight, 1e-3 * sim.base_reaction().x(), 1e-3 * sim.base_reaction().y(),
              1e-3 * sim.base_reaction().z(), 1e-3 * sim.pressure_force().norm(), 1e-3 * imbalance.norm(), 1e-3 * rsum,
              1e-3 * net.norm());
  EXPECT_LE(rsum, 1e-4 * weight) << "not at rest after " << steps << " static steps";
  EXPECT_GT(F, 0.0);                                  // it does rest on the plate
  EXPECT_LE(imbalance.norm(), rsum + 1e-9 * weight);  // the derived bound
  EXPECT_NEAR((imbalance - net).norm(), 0.0, 1e-9 * weight);
  EXPECT_LT(sim.pressure_force().norm(), 1e-9 * weight);  // closed cavity
}

}  // namespace
