#include "run/sim_run.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "core/open_loop_scenario.hpp"
#include "fem/whisker_model.hpp"
#include "io/formats/csv_writer.hpp"
#include "io/formats/vtk.hpp"
#include "run/output_dir.hpp"

namespace codesign::run {

namespace {

namespace fs = std::filesystem;

// One ParaView frame: the body at its world positions (rest + displacement), with the axial
// strain per tet.
void write_vtk_frame(const fs::path& file, const fem::Simulator& sim) {
  const fem::Model& m = sim.model();
  io::VtkFields fields;
  fields.displacement.resize(m.node_count());
  for (int i = 0; i < m.node_count(); ++i)
    fields.displacement[i] = sim.positions().segment<3>(3 * i) - m.rest_positions.segment<3>(3 * i);
  fields.cell_scalars.push_back({"axial_strain", sim.element_axial_strain()});
  io::write_vtu_file(file.string(), m.mesh, fields);
}

}  // namespace

int run_sim(const RunConfig& setup, const SimRunOptions& opt) {
  const fem::SimScenario& sc = setup.scenario;
  const int vtk_every = opt.vtk_every >= 0 ? opt.vtk_every : sc.vtk_every;
  const fs::path dir(opt.out);
  prepare_output_dir(dir, "trace.csv", "run", opt.force);

  const auto t0 = std::chrono::steady_clock::now();
  const auto model = fem::build_whisker_model(sc.design, setup.spec);
  std::printf("sim: design %d: %d nodes, %zu tets, %zu contact candidates, %zu fibre springs\n", sc.design,
              model->node_count(), model->mesh.tets.size(), model->contact_nodes.size(), model->fibres.size());
  fem::Simulator sim(model, setup.scene, setup.solver);
  io::CsvWriter csv((dir / "trace.csv").string(),
                    {"t", "theta", "F_mN", "eps", "tip_x", "tip_y", "tip_z", "plate_z", "status"});
  const core::ScenarioEnd end =
      core::run_open_loop_scenario(sim, sc, [&](int step, int, const fem::StepResult& r) {
        const fem::Sensors s = sim.sensors();
        csv.row({s.time_s, s.theta_rad, s.contact_force_mN, s.axial_strain, s.tip_position_mm.x(),
                 s.tip_position_mm.y(), s.tip_position_mm.z(), s.plate_z_mm},
                fem::to_string(r.status));
        if (vtk_every > 0 && r.ok() && step % vtk_every == 0) {
          char name[32];
          std::snprintf(name, sizeof name, "frame_%06d.vtu", step / vtk_every);
          write_vtk_frame(dir / name, sim);
        }
      });
  csv.close();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const fem::Sensors s = sim.sensors();
  std::printf("sim: %d steps in %.2f s; final F = %.3f mN, eps = %.4g, theta = %.4f rad -> %s\n", end.steps, wall,
              s.contact_force_mN, s.axial_strain, s.theta_rad, (dir / "trace.csv").string().c_str());
  if (!end.last.ok()) {
    std::fprintf(stderr, "sim: episode ended at step %d: %s (%s)\n", end.steps, fem::to_string(end.last.status),
                 end.last.reason.c_str());
    return 3;
  }
  return 0;
}

}  // namespace codesign::run
