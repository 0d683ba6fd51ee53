// The figures that docs/physics.md and docs/validation.md quote for the default design j21, as
// printed `[figures]` lines (scripts/fem_figures.sh runs these tests and collects the lines):
//  * tip compliance: clamped base, dead 100 µN traction on the tip face along z, gravity off,
//    no fibres (fem::solve_static has none), area-weighted mean tip displacement / load;
//  * the two lowest natural frequencies about the rest state: K0, lumped mass, clamped base, no
//    fibres;
//  * ε (chamber elongation sensor) at 10 and 20 kPa, and the tip displacement at 10 kPa, with and
//    without the default fibres: exact static steps to rest, gravity off, plate out of reach.
// On the default mesh they run in ctest with bounds wide enough to catch only a broken set-up;
// the refined meshes (`DISABLED_`, ~minutes) run from the script.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "fem/design.hpp"
#include "fem/mesh_ops.hpp"
#include "fem/modal.hpp"
#include "fem/simulator.hpp"
#include "fem/static_solve.hpp"
#include "fem/whisker_mesh.hpp"
#include "fem/whisker_model.hpp"

namespace codesign::fem {
namespace {

struct MeshCase {
  const char* name;
  MeshOptions options;
};

MeshCase default_mesh() { return {"default", MeshOptions{}}; }
MeshCase refined_mesh(double radius_factor, double wall_factor, const char* name) {
  MeshCase c{name, MeshOptions{}};
  c.options.radius_factor = radius_factor;
  c.options.wall_factor = wall_factor;
  return c;
}

double face_area(const Model& m, const Tri& f) {
  const auto& n = m.mesh.nodes;
  return 0.5 * (n[f[1]] - n[f[0]]).cross(n[f[2]] - n[f[0]]).norm();
}

// Compliance [mm/mN] and mesh size of j21 under a 100 µN tip load along z.
double tip_compliance(const MeshCase& c, std::size_t* tets) {
  WhiskerGeometry g;
  g.design = design_from_index(21);
  ModelOptions opt;
  opt.material.gravity_mm_s2 = 0.0;
  const auto model = build_model(mesh_whisker(g, c.options), opt);
  *tets = model->mesh.tets.size();
  const double load_uN = 100.0;
  StaticLoads loads;
  loads.dead = Eigen::VectorXd::Zero(3 * model->node_count());
  const double area = surface_area(model->mesh, model->mesh.tip_faces);
  for (const Tri& t : model->mesh.tip_faces)
    for (int k : t) loads.dead[3 * k + 2] += load_uN * face_area(*model, t) / area / 3.0;
  const StaticResult r = solve_static(*model, loads, clamped_base_dofs(*model));
  EXPECT_TRUE(r.converged);
  double uz = 0.0, w = 0.0;
  for (const Tri& t : model->mesh.tip_faces) {
    const double a = face_area(*model, t) / 3.0;
    for (int k : t) {
      uz += a * (r.positions[3 * k + 2] - model->rest_positions[3 * k + 2]);
      w += a;
    }
  }
  const double compliance = (uz / w) / (load_uN * 1e-3);
  std::printf("[figures] tip compliance j21 mesh=%s tets=%zu: %.4f mm/mN (no fibres, no gravity)\n",
              c.name, *tets, compliance);
  return compliance;
}

// Lowest two frequencies [Hz] of j21 without fibres.
void frequencies(const MeshCase& c, double* f1, double* f2) {
  WhiskerGeometry g;
  g.design = design_from_index(21);
  const auto model = build_model(mesh_whisker(g, c.options), ModelOptions{});
  ModalOptions mo;
  mo.count = 2;
  const ModalResult r =
      lowest_modes(tangent_stiffness(*model, model->rest_positions, StaticTangent::Corotational),
                   lumped_mass_matrix(*model), clamped_base_dofs(*model), mo);
  EXPECT_TRUE(r.converged);
  *f1 = r.omega[0] / (2 * std::numbers::pi);
  *f2 = r.omega[1] / (2 * std::numbers::pi);
  std::printf("[figures] modal j21 mesh=%s tets=%zu: f1 = %.3f Hz, f2 = %.3f Hz (K0, lumped mass, "
              "no fibres)\n",
              c.name, model->mesh.tets.size(), *f1, *f2);
}

void relax(Simulator& sim) {
  for (int i = 0; i < 400; ++i) {
    const Eigen::VectorXd x0 = sim.positions();
    const StepResult r = sim.static_step();
    ASSERT_TRUE(r.ok()) << r.reason;
    if ((sim.positions() - x0).cwiseAbs().maxCoeff() < 1e-7) return;
  }
  FAIL() << "static solve did not converge";
}

struct PressureFigures {
  double eps10 = 0, eps20 = 0;
  Eigen::Vector3d tip10 = Eigen::Vector3d::Zero();  // world-frame tip displacement at 10 kPa
};

PressureFigures pressure_figures(const MeshCase& c, bool fibres) {
  WhiskerModelSpec spec;
  spec.mesh = c.options;
  spec.model.material.gravity_mm_s2 = 0.0;
  if (!fibres) spec.fibres.count = 0;
  const auto model = build_whisker_model(21, spec);
  SolverConfig solver;
  solver.method = StepMethod::Exact;
  Simulator sim(model, SceneConfig{}, solver);
  sim.set_plate_mean_z(sim.plate_touch_z() - 50.0);  // no contact
  PressureFigures out;
  relax(sim);
  const Eigen::Vector3d tip0 = sim.sensors().tip_position_mm;
  sim.set_pressures_kPa(10.0, 0.0);
  relax(sim);
  out.eps10 = sim.sensors().axial_strain;
  out.tip10 = sim.sensors().tip_position_mm - tip0;
  sim.set_pressures_kPa(20.0, 0.0);
  relax(sim);
  out.eps20 = sim.sensors().axial_strain;
  std::printf("[figures] pressure j21 mesh=%s tets=%zu fibres=%s: eps(10 kPa) = %.5f, "
              "eps(20 kPa) = %.5f; tip displacement at 10 kPa (world x, y sideways, z) = "
              "(%.4f, %.4f, %.4f) mm\n",
              c.name, model->mesh.tets.size(), fibres ? "yes" : "no", out.eps10, out.eps20,
              out.tip10.x(), out.tip10.y(), out.tip10.z());
  return out;
}

TEST(WhiskerFigures, DefaultMeshTipCompliance) {
  std::size_t tets = 0;
  const double c = tip_compliance(default_mesh(), &tets);
  // Linear tets are stiff: well below the ~0.26 mm/mN h -> 0 estimate, but of its order.
  EXPECT_GT(c, 0.1);
  EXPECT_LT(c, 0.3);
}

TEST(WhiskerFigures, DefaultMeshFrequencies) {
  double f1 = 0, f2 = 0;
  frequencies(default_mesh(), &f1, &f2);
  EXPECT_GT(f1, 3.0);
  EXPECT_LT(f1, 40.0);
  EXPECT_GE(f2, f1);
}

TEST(WhiskerFigures, DefaultMeshPressure) {
  for (bool fibres : {true, false}) {
    const PressureFigures p = pressure_figures(default_mesh(), fibres);
    EXPECT_GT(p.eps20, p.eps10);
    EXPECT_GT(p.eps10, 0.0);
  }
}

// Refinements of the default mesh (radius_factor / wall_factor): run by scripts/fem_figures.sh.
TEST(WhiskerFigures, DISABLED_RefinedMeshes) {
  for (const MeshCase& c : {refined_mesh(0.4, 0.6, "r0.4/w0.6"),
                          refined_mesh(0.25, 0.4, "r0.25/w0.4")}) {
    std::size_t tets = 0;
    tip_compliance(c, &tets);
    double f1 = 0, f2 = 0;
    frequencies(c, &f1, &f2);
    pressure_figures(c, true);
    pressure_figures(c, false);
  }
}

}  // namespace
}  // namespace codesign::fem
