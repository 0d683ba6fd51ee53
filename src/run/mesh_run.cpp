#include "run/mesh_run.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "base/errors.hpp"
#include "fem/design.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/whisker_mesh.hpp"
#include "io/config/mesh_config.hpp"
#include "io/formats/msh.hpp"
#include "io/config/toml_reader.hpp"
#include "io/formats/vtk.hpp"

namespace codesign::run {

namespace {

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

int mesh_one(const MeshRunOptions& c, const MeshSettings& s) {
  const Meshed m = mesh_design(s, c.design);
  const fem::Design d = fem::design_from_index(c.design);
  std::printf("j%d {n=%d, l=%g mm, w=%g mm}: %s (%.2f s)\n", c.design, d.n, d.chamber_length_mm, d.wall_mm,
              fem::summary(m.report).c_str(), m.seconds);
  if (c.check && !m.report.ok()) return 1;
  if (!c.out.empty()) write_output("-o", c.out, [&] { io::write_msh_file(c.out, m.mesh); });
  if (!c.vtk.empty()) write_output("--vtk", c.vtk, [&] { io::write_vtu_file(c.vtk, m.mesh); });
  return 0;
}

int mesh_all(const MeshRunOptions& c, const MeshSettings& s) {
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

int mesh_designs(const MeshRunOptions& c, bool has_design) {
  if (c.all) {
    if (has_design || !c.out.empty() || !c.vtk.empty()) {
      throw InputError("--all: cannot be combined with --design, -o or --vtk");
    }
  } else if (!has_design || c.design < 0 || c.design >= fem::kDesignCount) {
    throw InputError("--design " + (has_design ? std::to_string(c.design) : std::string("missing")) +
                         ": allowed range 0.." + std::to_string(fem::kDesignCount - 1) + " (or pass --all)");
  }
  const MeshSettings s = read_settings(c.config);
  return c.all ? mesh_all(c, s) : mesh_one(c, s);
}

}  // namespace codesign::run
