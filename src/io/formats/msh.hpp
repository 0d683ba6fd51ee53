#pragma once
// gmsh MSH 4.1 (ASCII) reading and writing, our own code (gmsh is not called for I/O).
//
// Written files carry the physical groups: volume "whisker" (all tets), surfaces "base", "tip",
// "chamber_1", "chamber_2", … (chamber_k = TetMesh::chamber_faces[k-1]); empty surfaces are left
// out. The reader accepts files written by gmsh itself: any number of entity blocks, node tags
// that are not contiguous, parametric node coordinates, element types 4 (tet) and 2 (triangle);
// points, lines, quads, … are skipped; higher-order or non-tet volume elements are rejected.
// Triangles are mapped to tags by the physical names above (via $Entities), re-oriented out of
// the solid; tets are made positive; unused nodes dropped. Any problem throws InputError
// "file:line: expected …, got …".
#include <iosfwd>
#include <string>

#include "fem/mesh.hpp"
#include "base/errors.hpp"

namespace codesign::io {

void write_msh(std::ostream& out, const fem::TetMesh& m);
// Writes to `path` atomically (a temporary file in the same folder, then rename).
// Throws std::runtime_error if the file cannot be written.
void write_msh_file(const std::string& path, const fem::TetMesh& m);

// `label` names the source in error messages.
fem::TetMesh read_msh(std::istream& in, const std::string& label);
fem::TetMesh read_msh_file(const std::string& path);

}  // namespace codesign::io
