#include "io/formats/vtk.hpp"

#include "io/formats/atomic_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <stdexcept>

namespace codesign::io {
namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("write_vtu: " + what);
}

void put3(std::ostream& out, const Eigen::Vector3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g\n", v.x(), v.y(), v.z());
  out << buf;
}

void vectors(std::ostream& out, const std::string& name, const std::vector<Eigen::Vector3d>& v) {
  out << "        <DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& x : v) put3(out, x);
  out << "        </DataArray>\n";
}

}  // namespace

void write_vtu(std::ostream& out, const fem::TetMesh& m, const VtkFields& f) {
  const std::size_t nn = m.nodes.size(), nt = m.tets.size();
  check(f.displacement.empty() || f.displacement.size() == nn, "displacement needs one vector per node");
  for (const auto& p : f.point_vectors) check(!p.name.empty() && p.values.size() == nn, "point array '" + p.name + "' needs one vector per node");
  for (const auto& c : f.cell_scalars) check(!c.name.empty() && c.values.size() == nt, "cell array '" + c.name + "' needs one value per tet");

  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << nn << "\" NumberOfCells=\"" << nt << "\">\n";
  out << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < nn; ++i) put3(out, f.displacement.empty() ? m.nodes[i] : Eigen::Vector3d(m.nodes[i] + f.displacement[i]));
  out << "        </DataArray>\n      </Points>\n";
  out << "      <Cells>\n        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : m.tets) out << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  out << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < nt; ++c) out << 4 * (c + 1) << '\n';
  out << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < nt; ++c) out << "10\n";
  out << "        </DataArray>\n      </Cells>\n";

  const bool disp = !f.displacement.empty() && f.write_displacement;
  if (disp || !f.point_vectors.empty()) {
    out << "      <PointData>\n";
    if (disp) vectors(out, "displacement", f.displacement);
    for (const auto& p : f.point_vectors) vectors(out, p.name, p.values);
    out << "      </PointData>\n";
  }
  if (!f.cell_scalars.empty()) {
    out << "      <CellData>\n";
    char buf[40];
    for (const auto& c : f.cell_scalars) {
      out << "        <DataArray type=\"Float64\" Name=\"" << c.name << "\" format=\"ascii\">\n";
      for (double v : c.values) {
        std::snprintf(buf, sizeof buf, "%.9g\n", v);
        out << buf;
      }
      out << "        </DataArray>\n";
    }
    out << "      </CellData>\n";
  }
  out << "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

void write_vtu_file(const std::string& path, const fem::TetMesh& m, const VtkFields& fields) {
  write_file_atomically(path, [&](std::ostream& out) { write_vtu(out, m, fields); });
}

}  // namespace codesign::io
