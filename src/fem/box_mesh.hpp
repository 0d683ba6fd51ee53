#pragma once
// A structured tetrahedral box (a "bar"), for tests and quick experiments.
// x ∈ [0, length], y ∈ [−width/2, width/2], z ∈ [−height/2, height/2]; each of nx·ny·nz cells is
// split into 6 tets (Kuhn split, conforming). base_faces: the x = 0 side, tip_faces: x = length,
// both with outward normals; no chambers.
#include "fem/mesh.hpp"

namespace codesign::fem {

TetMesh make_box_mesh(double length, double width, double height, int nx, int ny, int nz);

}  // namespace codesign::fem
