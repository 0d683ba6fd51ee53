// `codesign mesh --design J [-o FILE.msh] [--vtk FILE.vtu] [--config run.toml] [--check]`
// `codesign mesh --all [--check] [--config run.toml]`
//
// Meshes design J (0..109) with the [geometry] and [mesh] tables of the config (defaults without
// one), runs the quality checks and prints one summary line; writes gmsh MSH 4.1 and/or VTK .vtu
// atomically. --all meshes the 110 designs and prints one row each. With --check a design that
// fails the quality checks stops the command with exit status 1 (nothing is written for it).
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "base/errors.hpp"
#include "fem/design.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/whisker_mesh.hpp"
#include "io/mesh_config.hpp"
#include "io/msh.hpp"
#include "io/toml_reader.hpp"
#include "io/vtk.hpp"

namespace codesign::app {
namespace {

struct MeshCommand {
  int design = -1;
  bool all = false;
  bool check = false;
  std::string out, vtk, config;
};

struct MeshSettings {
  fem::WhiskerGeometry geometry{};
  fem::MeshOptions options{};
};

MeshSettings read_settings(const std::string& config) {
  MeshSettings s;
  if (config.empty()) return s;
  io::TableReader root = io::TableReader::from_file(config);
  s.geometry = io::read_geometry(root);
  s.options = io::read_mesh_options(root);
  return s;  // other tables of the config belong to other commands: no root.finish() here
}

struct Meshed {
  fem::TetMesh mesh;
  fem::QualityReport report;
  double seconds;
};

Meshed mesh_design(const MeshSettings& s, int j) {
  fem::WhiskerGeometry g = s.geometry;
  g.design = fem::design_from_index(j);
  const auto t0 = std::chrono::steady_clock::now();
  Meshed r{fem::mesh_whisker(g, s.options), {}, 0};
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.report = fem::check_whisker_mesh(r.mesh, g, s.options.quality);
  return r;
}

template <class F>
void write_output(const std::string& flag, const std::string& path, F&& write) {
  try {
    write();
  } catch (const std::runtime_error& e) {
    throw InputError(flag + " " + path + ": cannot write the file (" + e.what() + ")");
  }
}

int run_one(const MeshCommand& c, const MeshSettings& s) {
  const Meshed m = mesh_design(s, c.design);
  const fem::Design d = fem::design_from_index(c.design);
  std::printf("j%d {n=%d, l=%g mm, w=%g mm}: %s (%.2f s)\n", c.design, d.n, d.chamber_length_mm, d.wall_mm,
              fem::summary(m.report).c_str(), m.seconds);
  if (c.check && !m.report.ok()) return 1;
  if (!c.out.empty()) write_output("-o", c.out, [&] { io::write_msh_file(c.out, m.mesh); });
  if (!c.vtk.empty()) write_output("--vtk", c.vtk, [&] { io::write_vtu_file(c.vtk, m.mesh); });
  return 0;
}

int run_all(const MeshCommand& c, const MeshSettings& s) {
  std::printf("%4s %2s %5s %5s %6s %6s %9s %9s %8s %7s %6s\n", "j", "n", "l_mm", "w_mm", "nodes", "tets",
              "vol_err%", "bound%", "min_dih", "min_rr", "time_s");
  double total = 0;
  int failed = 0;
  for (int j = 0; j < fem::kDesignCount; ++j) {
    const Meshed m = mesh_design(s, j);
    const fem::Design d = fem::design_from_index(j);
    const auto& r = m.report;
    total += m.seconds;
    std::printf("%4d %2d %5g %5g %6d %6d %+9.3f %9.3f %8.2f %7.3f %6.2f %s\n", j, d.n, d.chamber_length_mm, d.wall_mm,
                r.nodes, r.tets, 100.0 * r.volume_error / r.reference_volume,
                100.0 * r.volume_tolerance / r.reference_volume, r.min_dihedral_deg, r.min_radius_ratio, m.seconds,
                r.ok() ? "PASS" : "FAIL");
    if (!r.ok()) {
      ++failed;
      std::printf("     %s\n", fem::summary(r).c_str());
      if (c.check) return 1;
    }
  }
  std::printf("%d of %d designs pass; meshing took %.1f s in total\n", fem::kDesignCount - failed,
              fem::kDesignCount, total);
  return failed == 0 ? 0 : 1;
}

}  // namespace

void add_mesh_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<MeshCommand>();
  CLI::App* cmd = root.add_subcommand("mesh", "Mesh a whisker design (gmsh .msh 4.1 / VTK .vtu) and check its quality");
  CLI::Option* design = cmd->add_option("--design", opt->design, "Design index j, 0..109 (j = (n-1)*55 + (l-20)/2*5 + (w-2)/0.5)");
  cmd->add_flag("--all", opt->all, "Mesh all 110 designs and print a table");
  cmd->add_option("-o,--output", opt->out, "Write the mesh as gmsh MSH 4.1 ASCII");
  cmd->add_option("--vtk", opt->vtk, "Write the mesh as VTK XML unstructured grid (.vtu)");
  cmd->add_option("--config", opt->config, "TOML config with [geometry] and [mesh] tables");
  cmd->add_flag("--check", opt->check, "Exit with status 1 if a mesh fails the quality checks");
  cmd->callback([opt, design, &run] {
    const bool has_design = design->count() > 0;
    run = [opt, has_design]() -> int {
      const MeshCommand& c = *opt;
      if (c.all) {
        if (has_design || !c.out.empty() || !c.vtk.empty()) {
          throw InputError("--all: cannot be combined with --design, -o or --vtk");
        }
      } else if (!has_design || c.design < 0 || c.design >= fem::kDesignCount) {
        throw InputError("--design " + (has_design ? std::to_string(c.design) : std::string("missing")) +
                             ": allowed range 0.." + std::to_string(fem::kDesignCount - 1) + " (or pass --all)");
      }
      const MeshSettings s = read_settings(c.config);
      return c.all ? run_all(c, s) : run_one(c, s);
    };
  });
}

}  // namespace codesign::app
