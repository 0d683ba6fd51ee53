// `codesign sim --config run.toml [-o DIR] [--vtk-every N] [--force]`
//
// Runs the open-loop scenario of [sim]: design j, chamber pressures, a θ schedule and the
// plate motion of [scene], for [sim].steps steps after the quasi-static settling. Writes
//   DIR/trace.csv   t, theta (rad), F_mN, eps, tip_x, tip_y, tip_z (mm, world), plate_z, status
//   DIR/frame_NNNNNN.vtu  ParaView frames of the deformed body (world positions, axial strain
//                         per tet) every N steps (N > 0), and after settling (000000)
// A numerical failure ends the scenario early: its row carries the status and the reason is
// printed; the exit code is then 3. Existing results in DIR are kept unless --force.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>

#include "run/run_config.hpp"
#include "commands.hpp"
#include "base/errors.hpp"
#include "io/csv_writer.hpp"
#include "io/vtk.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct SimOptions {
  std::string config;
  std::string out = "runs/sim";
  int vtk_every = -1;  // -1: from the config
  bool force = false;
};

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

int run_sim(const SimOptions& opt) {
  const run::RunConfig setup = run::read_run_config(opt.config);
  const io::SimScenario& sc = setup.scenario;
  const int vtk_every = opt.vtk_every >= 0 ? opt.vtk_every : sc.vtk_every;
  const fs::path dir(opt.out);
  std::error_code ec;
  if (fs::exists(dir / "trace.csv", ec) && !opt.force)
    throw InputError(dir.string() + ": already holds trace.csv of an earlier run; choose another -o or pass --force");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());

  const auto t0 = std::chrono::steady_clock::now();
  const auto model = fem::build_whisker_model(sc.design, setup.spec);
  std::printf("sim: design %d: %d nodes, %zu tets, %zu contact candidates, %zu fibre springs\n", sc.design,
              model->node_count(), model->mesh.tets.size(), model->contact_nodes.size(), model->fibres.size());
  fem::Simulator sim(model, setup.scene, setup.solver);
  sim.set_pressures_kPa(sc.pressures_kPa[0], sc.pressures_kPa[1]);
  io::CsvWriter csv((dir / "trace.csv").string(),
                    {"t", "theta", "F_mN", "eps", "tip_x", "tip_y", "tip_z", "plate_z", "status"});
  auto record = [&](const fem::StepResult& r) {
    const fem::Sensors s = sim.sensors();
    csv.row({s.time_s, s.theta_rad, s.contact_force_mN, s.axial_strain, s.tip_position_mm.x(), s.tip_position_mm.y(),
             s.tip_position_mm.z(), s.plate_z_mm},
            fem::to_string(r.status));
  };
  fem::StepResult r = sim.settle();
  record(r);
  int frame = 0;
  if (vtk_every > 0 && r.ok()) write_vtk_frame(dir / "frame_000000.vtu", sim);
  int k = 0;
  for (; k < sc.steps && r.ok(); ++k) {
    if (k % sc.theta_hold_steps == 0) {
      const std::size_t i = std::min<std::size_t>(k / sc.theta_hold_steps, sc.theta_deg.size() - 1);
      sim.set_base_angle_target(sc.theta_deg[i] * std::numbers::pi / 180.0, sc.theta_hold_steps);
    }
    r = sim.step();
    record(r);
    if (vtk_every > 0 && r.ok() && (k + 1) % vtk_every == 0) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.vtu", ++frame);
      write_vtk_frame(dir / name, sim);
    }
  }
  csv.close();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const fem::Sensors s = sim.sensors();
  std::printf("sim: %d steps in %.2f s; final F = %.3f mN, eps = %.4g, theta = %.4f rad -> %s\n", k, wall,
              s.contact_force_mN, s.axial_strain, s.theta_rad, (dir / "trace.csv").string().c_str());
  if (!r.ok()) {
    std::fprintf(stderr, "sim: episode ended at step %d: %s (%s)\n", k, fem::to_string(r.status), r.reason.c_str());
    return 3;
  }
  return 0;
}

}  // namespace

void add_sim_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<SimOptions>();
  CLI::App* cmd = root.add_subcommand("sim", "Run an open-loop simulation scenario and write a CSV trace");
  cmd->add_option("--config", opt->config, "run config (TOML); tables [material] [scene] [solver] [fibres] [sim]")
      ->required();
  cmd->add_option("-o,--out", opt->out, "output directory (default runs/sim)");
  cmd->add_option("--vtk-every", opt->vtk_every, "write a VTK frame every N steps (0: none; default [sim].vtk_every)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--force", opt->force, "overwrite the results of an earlier run in the output directory");
  cmd->callback([opt, &run] { run = [opt] { return run_sim(*opt); }; });
}

}  // namespace codesign::app
