#pragma once
// Tetrahedral meshes of the whisker and of simple validation solids, generated with gmsh's
// OpenCASCADE kernel (the tool the paper used) and returned as TetMesh.
//
// Surface tags are not taken from gmsh's entity numbering; every boundary face of the tet mesh is
// classified geometrically (see whisker_mesh.cpp), so tags are robust to OCC's boolean output.
// Tets are positively oriented, tagged faces point out of the solid, and only used nodes are kept.
// gmsh has process-wide state: calls are serialised by an internal lock (thread-safe, but not
// parallel) and gmsh is initialised/finalised per call.
#include "fem/mesh.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/whisker_geometry.hpp"

namespace codesign::fem {

// Target element size h(x) along the whisker (all mm):
//   h(x) = min(max_size, radius_factor * R(x))              everywhere,
//   h(x) = min(h(x), wall_factor * w + grading * d(x))       where d(x) is the axial distance to
//                                                             the chamber region (0 inside it).
// With the defaults the default design j21 gets ~2.2k tets (the FEM step must stay ≤ 1 ms), and
// the size in the chamber region scales with w so every design is resolved alike relative to its
// wall. A conforming tet mesh always has ≥ 1 element through any wall.
struct MeshOptions {
  double max_size_mm = 6.0;
  double radius_factor = 0.6;  // ≥ 10 segments around any cross-section
  double wall_factor = 1.5;
  double grading = 0.5;          // growth of h per mm of axial distance from the chamber region
  // gmsh optimises every tet whose quality (gmsh's gamma, ~ radius ratio) is below this
  // (gmsh's default is 0.3).
  double optimise_threshold = 0.45;
  // A mesh with a tet outside these limits is regenerated with a slightly different size
  // (deterministic sequence of up to 7 tries); the best try is returned.
  QualityThresholds quality{};
};

TetMesh mesh_whisker(const WhiskerGeometry& g, const MeshOptions& opt = {});

// Solid cylinder of the given radius along +x from x = 0 (base_faces) to x = length (tip_faces),
// uniform target size. No chambers. Like mesh_whisker, a mesh with a sliver (default
// QualityThresholds) is regenerated with the size scaled by 0.96, 1.04, 0.92, … (≤ 7 tries).
TetMesh mesh_cylinder(double radius, double length, double size);
// Hollow cylinder r_in < r < r_out along +x; chamber_faces[0] is the inner surface, base/tip the
// annular end faces at x = 0 and x = length.
TetMesh mesh_hollow_cylinder(double r_in, double r_out, double length, double size);

}  // namespace codesign::fem
