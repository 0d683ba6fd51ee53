// `codesign mesh --design J [-o FILE.msh] [--vtk FILE.vtu] [--config run.toml] [--check]`
// `codesign mesh --all [--check] [--config run.toml]`
//
// Meshes one design or all 110 and checks their quality (run/mesh_run.hpp). With --check a design
// that fails the quality checks stops the command with exit status 1.
#include <memory>

#include "commands.hpp"
#include "run/mesh_run.hpp"

namespace codesign::app {

void add_mesh_command(CLI::App& root, Runner& run) {
  auto opt = std::make_shared<run::MeshRunOptions>();
  CLI::App* cmd = root.add_subcommand("mesh", "Mesh a whisker design (gmsh .msh 4.1 / VTK .vtu) and check its quality");
  CLI::Option* design = cmd->add_option("--design", opt->design, "Design index j, 0..109 (j = (n-1)*55 + (l-20)/2*5 + (w-2)/0.5)");
  cmd->add_flag("--all", opt->all, "Mesh all 110 designs and print a table");
  cmd->add_option("-o,--output", opt->out, "Write the mesh as gmsh MSH 4.1 ASCII");
  cmd->add_option("--vtk", opt->vtk, "Write the mesh as VTK XML unstructured grid (.vtu)");
  cmd->add_option("--config", opt->config, "TOML config with [geometry] and [mesh] tables");
  cmd->add_flag("--check", opt->check, "Exit with status 1 if a mesh fails the quality checks");
  cmd->callback([opt, design, &run] {
    const bool has_design = design->count() > 0;
    run = [opt, has_design] { return run::mesh_designs(*opt, has_design); };
  });
}

}  // namespace codesign::app
