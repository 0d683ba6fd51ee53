#pragma once
// A linear tetrahedral mesh with the tagged surfaces the whisker simulator needs.
//
// Frame ("whisker frame"): the whisker axis runs along +x from the centre of the clamped
// proximal face (x = 0) to the distal tip (x = L). For two-chamber designs the septum is the
// plane z = 0: chamber 0 lies at z > 0, chamber 1 at z < 0, so the bending plane is x–z.
// Units: millimetres.
#include <array>
#include <vector>

#include <Eigen/Core>

namespace codesign::fem {

using Tet = std::array<int, 4>;
using Tri = std::array<int, 3>;

struct TetMesh {
  std::vector<Eigen::Vector3d> nodes;             // rest positions [mm]
  std::vector<Tet> tets;                          // positively oriented: det[x1-x0, x2-x0, x3-x0] > 0
  std::vector<Tri> base_faces;                    // clamped proximal surface, normals out of the solid
  std::vector<Tri> tip_faces;                     // distal tip surface, normals out of the solid
  std::vector<std::vector<Tri>> chamber_faces;    // per chamber: cavity wall, normals out of the solid (into the cavity)
};

}  // namespace codesign::fem
