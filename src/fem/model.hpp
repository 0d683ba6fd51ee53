#pragma once
// The discretised whisker body: mesh, per-element rest data, lumped masses, fibre springs,
// boundary node sets and the sensing region. Immutable once built; shared by simulators.
//
// Mass: lumped (row-sum of the consistent mass of linear tets = V_e/4 per node), density chosen
// so that the total is material.total_mass_g.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "fem/corotational_tet.hpp"
#include "fem/fibre_springs.hpp"
#include "fem/material.hpp"
#include "fem/mesh.hpp"

namespace codesign::fem {

struct ModelOptions {
  Material material{};
  // Contact candidates: surface nodes with rest x ≥ L − tip_region_mm (L = max rest x).
  double tip_region_mm = 6.0;
  // Fibres (optional): polylines in the rest frame (embedded by embed_point), and/or chains of
  // already embedded points (e.g. from fem/fibre_layout.hpp); both become spring chains with
  // the fibre EA [µN] (force per unit strain), spring k = EA / rest length.
  std::vector<std::vector<Eigen::Vector3d>> fibre_polylines{};
  std::vector<std::vector<EmbeddedPoint>> fibre_chains{};
  double fibre_axial_stiffness_uN = 5.0e7;  // 50 N per unit strain
  // Bilateral springs (default, as SOFA's spring chains: the thread is held by the matrix around
  // it and resists shortening too) or tension-only (a free thread that goes slack).
  bool fibres_tension_only = false;
};

struct Model {
  TetMesh mesh;
  Material material;
  // Per tet. The rest stiffness is not stored: it would be four fifths of the model's memory,
  // and rest_stiffness() rebuilds it, to the same bits, for the few passes that need it
  // (assembling a system to factorise, the static tangent).
  std::vector<TetRest> rest;
  Eigen::VectorXd rest_positions;     // 3N, node-major, whisker frame
  Eigen::VectorXd lumped_mass;        // N [g]
  double volume_mm3 = 0.0;
  double length_mm = 0.0;             // max rest x
  std::vector<int> base_nodes;        // nodes of base_faces (clamped), sorted
  std::vector<int> tip_nodes;         // nodes of tip_faces, sorted (tip position = their mean)
  std::vector<int> contact_nodes;     // candidates for plate contact, sorted
  std::vector<char> is_base;          // N flags
  std::vector<FibreSpring> fibres;
  bool fibres_tension_only = false;
  // Sensing region for ε: tets whose rest centroid lies in [chamber_x0, chamber_x1], the axial
  // span of all chamber faces (whole body when the mesh has no chamber).
  double chamber_x0 = 0.0, chamber_x1 = 0.0;
  std::vector<int> chamber_tets;
  double chamber_volume_mm3 = 0.0;    // sum of rest volumes of chamber_tets

  int node_count() const { return static_cast<int>(mesh.nodes.size()); }
  int chamber_count() const { return static_cast<int>(mesh.chamber_faces.size()); }
};

// Builds the model; throws std::invalid_argument for an unusable mesh (no tets, inverted tet,
// no base faces, no tip faces).
std::shared_ptr<const Model> build_model(TetMesh mesh, const ModelOptions& options);

}  // namespace codesign::fem
