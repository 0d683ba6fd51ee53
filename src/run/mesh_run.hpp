#pragma once
// `codesign mesh` (fem/whisker_mesh.hpp, fem/mesh_quality.hpp): meshes design J (0..109) with the [geometry] and [mesh]
// tables of a config (defaults without one), runs the quality checks and prints one summary
// line; writes gmsh MSH 4.1 and/or VTK .vtu atomically. `all` meshes the 110 designs and prints
// one row each. With `check` a design that fails the quality checks stops with status 1
// (nothing is written for it).
#include <string>

namespace codesign::run {

struct MeshRunOptions {
  int design = -1;          // 0..109 unless `all`
  bool all = false;         // every design, a table row each (no files)
  bool check = false;       // status 1 at the first design that fails the quality checks
  std::string out;          // MSH 4.1 file ("" = none)
  std::string vtk;          // VTK .vtu file ("" = none)
  std::string config;       // run config whose [geometry] and [mesh] are used ("" = defaults)
};

// Returns the exit status: 0, or 1 when a design fails the quality checks. Bad options (a design
// out of range, `all` with a design or files) and unwritable files are InputErrors naming the
// flag.
int mesh_designs(const MeshRunOptions& options, bool design_given);

}  // namespace codesign::run
