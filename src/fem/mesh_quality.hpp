#pragma once
// Mesh quality checks for the whisker FEM.
#include <string>
#include <vector>

#include "fem/mesh.hpp"
#include "fem/whisker_geometry.hpp"

namespace codesign::fem {

// Acceptance thresholds. Why these values:
//  * Linear tets lose accuracy and the stiffness matrix loses conditioning as a tet flattens:
//    the condition number of an element stiffness grows like 1/ρ, ρ the radius ratio
//    (ρ = 3 r_in / r_circ, 1 for the regular tet, 0 for a flat one). Slivers have every edge of
//    similar length but ρ → 0 and a dihedral angle → 0°, so both measures are checked.
//  * min dihedral ≥ 5°, radius ratio ≥ 0.1: a tet at these limits still has an element condition
//    number within ~10–20× of a regular tet (ρ = 0.1 → 1/ρ = 10), which keeps the implicit
//    solve well conditioned at dt = 0.01 s; the default meshes stay far above (see the report of
//    `codesign mesh --all --check`).
//  * max dihedral ≤ 175°: a "cap" tet near 180° has a badly conditioned gradient too.
struct QualityThresholds {
  double min_dihedral_deg = 5.0;
  double max_dihedral_deg = 175.0;
  double min_radius_ratio = 0.1;
};

struct QualityReport {
  int nodes = 0;
  int tets = 0;
  double min_volume = 0, max_volume = 0, total_volume = 0;  // mm³
  int inverted = 0;                                         // tets with volume ≤ 0
  double min_dihedral_deg = 0, max_dihedral_deg = 0;
  double min_radius_ratio = 0;
  double max_edge_ratio = 0;  // longest / shortest edge of one tet, worst tet
  int components = 0;         // face-connected components of the tets
  int overshared_faces = 0;   // faces shared by > 2 tets
  int boundary_open_edges = 0;
  int base_faces = 0, tip_faces = 0;
  std::vector<int> chamber_faces;       // per chamber
  std::vector<int> chamber_open_edges;  // per chamber, 0 = watertight
  bool has_reference = false;           // CAD volume known
  double reference_volume = 0, volume_error = 0, volume_tolerance = 0;  // mm³
  std::vector<std::string> problems;    // empty ⇔ passes

  bool ok() const { return problems.empty(); }
};

// Element quality, topology and tags of any mesh (base and tip must be non-empty, chambers may be
// absent; a chamber surface that exists is not required to be closed).
QualityReport check_mesh(const TetMesh& m, const QualityThresholds& th = {});

// check_mesh plus the whisker's own requirements: design.n chamber surfaces, each non-empty and
// watertight, and the mesh volume within faceting_volume_bound() of the CAD volume.
QualityReport check_whisker_mesh(const TetMesh& m, const WhiskerGeometry& g,
                                 const QualityThresholds& th = {});

// Upper bound of |V_mesh - V_CAD| due to replacing surfaces of revolution about the x axis by flat
// triangles whose nodes lie on the surface. A face whose nodes span the angle φ about the axis
// lies within the chord of that arc, so it deviates from the surface by at most the sagitta
// s = r (1 - cos(φ/2)) ≈ r φ² / 8 (r: largest node radius, which over-estimates s); the volume
// between face and surface is then ≤ area · s. Faces whose normal is along x or z (the planar
// base, tip, cavity ends and septum) contribute nothing. The true error is smaller (the mean
// deviation of a chord from its arc is 2/3 of the sagitta, and cone facets are inclined).
double faceting_volume_bound(const TetMesh& m, const std::vector<Tri>& boundary);

// One line: nodes, tets, volume error, min dihedral, min radius ratio, and PASS/FAIL.
std::string summary(const QualityReport& r);

}  // namespace codesign::fem
