#pragma once
// VTK XML UnstructuredGrid (.vtu, ASCII) output for ParaView: nodes (optionally displaced),
// linear tetrahedra (VTK cell type 10), optional point vectors and cell scalars.
#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fem/mesh.hpp"

namespace codesign::io {

struct VtkPointVectors {
  std::string name;                       // e.g. "displacement"
  std::vector<Eigen::Vector3d> values;    // one per node
};
struct VtkCellScalars {
  std::string name;                       // e.g. "strain"
  std::vector<double> values;             // one per tet
};

struct VtkFields {
  // If non-empty: the grid is drawn at rest position + displacement (one per node).
  std::vector<Eigen::Vector3d> displacement;
  // If true and `displacement` is given, it is also written as point data "displacement".
  bool write_displacement = true;
  std::vector<VtkPointVectors> point_vectors;
  std::vector<VtkCellScalars> cell_scalars;
};

// Throws std::invalid_argument if an array has the wrong length or a name is empty.
void write_vtu(std::ostream& out, const fem::TetMesh& m, const VtkFields& fields = {});
// Atomic (temporary file + rename); throws std::runtime_error if the file cannot be written.
void write_vtu_file(const std::string& path, const fem::TetMesh& m, const VtkFields& fields = {});

}  // namespace codesign::io
