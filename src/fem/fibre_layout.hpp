#pragma once
// Helical inextensible-fibre paths around the chamber region and their barycentric embedding.
//
// Fibre k (0-based) is the helix
//   x ∈ [x0, x1] (the chamber region of WhiskerGeometry),  r(x) = R(x) - radial_inset_mm,
//   φ_k(x) = 2π k / count + s_k 2π (x - x0) / pitch_mm,  s_k = +1 for even k, -1 for odd k,
// so with the default count = 2 one right- and one left-handed helix cross each other, as in
// fibre-reinforced soft actuators (the crossing pair cancels the twist a single helix would
// cause under pressure). The helix runs just inside the outer skin: the inset must exceed the
// faceting sagitta of the mesh's outer surface (≤ ~0.45 mm for the default mesh options) so
// every point lies inside a tet; 1 mm sits in the middle of the thinnest wall (2 mm).
// Points are spaced evenly in x, `points_per_turn` per turn; consecutive points are joined by
// the FEM's stiff springs (fem/fibre_springs.hpp).
#include <vector>

#include <Eigen/Core>

#include "fem/fibre_springs.hpp"
#include "fem/mesh.hpp"
#include "fem/whisker_geometry.hpp"

namespace codesign::fem {

struct FibreLayoutOptions {
  int count = 2;                  // number of helices (0: no fibres)
  double pitch_mm = 3.0;          // axial advance per turn
  double points_per_turn = 12.0;  // spring nodes per turn
  double radial_inset_mm = 1.0;   // depth below the outer surface
};

struct FibreChain {
  std::vector<EmbeddedPoint> points;  // consecutive points are joined by springs
};

// The helices as polylines in the rest configuration (throws std::invalid_argument for bad
// options: count < 0, pitch or points_per_turn ≤ 0, inset outside (0, w)).
std::vector<std::vector<Eigen::Vector3d>> fibre_polylines(const WhiskerGeometry& g,
                                                          const FibreLayoutOptions& opt = {});

// The polylines located in `m`: every point gets its containing tet and barycentric weights
// (each ≥ -1e-9, summing to 1). Throws std::runtime_error if a point lies outside the mesh.
std::vector<FibreChain> embed_polylines(const TetMesh& m,
                                        const std::vector<std::vector<Eigen::Vector3d>>& lines);

// fibre_polylines + embed_polylines.
std::vector<FibreChain> layout_fibres(const TetMesh& m, const WhiskerGeometry& g,
                                      const FibreLayoutOptions& opt = {});

}  // namespace codesign::fem
