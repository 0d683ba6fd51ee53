#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "fem/design.hpp"
#include "fem/whisker_mesh.hpp"
#include "io/formats/vtk.hpp"

using namespace codesign;

namespace {

// Numbers of the DataArray whose opening tag contains `open_tag_part` (e.g. Name="offsets"),
// or of the first DataArray inside the section `open_tag_part` (e.g. "<Points>").
std::vector<double> array_values(const std::string& xml, const std::string& open_tag_part) {
  auto at = xml.find(open_tag_part);
  EXPECT_NE(at, std::string::npos) << open_tag_part;
  if (open_tag_part.front() == '<') at = xml.find("<DataArray", at);  // the array inside a section
  const auto start = xml.find('>', at) + 1;
  const auto end = xml.find("</DataArray>", start);
  std::istringstream in(xml.substr(start, end - start));
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  EXPECT_TRUE(in.eof()) << "non-numeric content in " << open_tag_part;
  return v;
}

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(Vtk, UnstructuredGridIsWellFormed) {
  fem::WhiskerGeometry g;
  g.design = fem::design_from_index(63);
  const fem::TetMesh m = fem::mesh_whisker(g);
  io::VtkFields f;
  f.displacement.assign(m.nodes.size(), Eigen::Vector3d(0.5, 0, -1));
  f.cell_scalars.push_back({"strain", std::vector<double>(m.tets.size(), 0.25)});
  std::ostringstream out;
  io::write_vtu(out, m, f);
  const std::string xml = out.str();

  auto attribute = [&](const std::string& name) {
    const auto at = xml.find(name + "=\"");
    EXPECT_NE(at, std::string::npos) << name;
    return std::stoul(xml.substr(at + name.size() + 2));
  };
  EXPECT_EQ(attribute("NumberOfPoints"), m.nodes.size());
  EXPECT_EQ(attribute("NumberOfCells"), m.tets.size());
  // Every opened element is closed.
  for (const std::string tag : {"VTKFile", "UnstructuredGrid", "Piece", "Points", "Cells", "PointData", "CellData"}) {
    EXPECT_EQ(count(xml, "<" + tag + " ") + count(xml, "<" + tag + ">"), 1) << tag;
    EXPECT_EQ(count(xml, "</" + tag + ">"), 1) << tag;
  }
  EXPECT_EQ(count(xml, "<DataArray"), count(xml, "</DataArray>"));

  const auto pts = array_values(xml, "<Points>");
  ASSERT_EQ(pts.size(), 3 * m.nodes.size());
  EXPECT_NEAR(pts[0], m.nodes[0].x() + 0.5, 1e-6);  // drawn displaced
  EXPECT_NEAR(pts[2], m.nodes[0].z() - 1.0, 1e-6);
  const auto conn = array_values(xml, "Name=\"connectivity\"");
  ASSERT_EQ(conn.size(), 4 * m.tets.size());
  for (double c : conn) EXPECT_LT(c, static_cast<double>(m.nodes.size()));
  const auto offsets = array_values(xml, "Name=\"offsets\"");
  ASSERT_EQ(offsets.size(), m.tets.size());
  EXPECT_EQ(offsets.back(), 4.0 * m.tets.size());
  const auto types = array_values(xml, "Name=\"types\"");
  ASSERT_EQ(types.size(), m.tets.size());
  for (double t : types) EXPECT_EQ(t, 10.0);  // VTK_TETRA
  EXPECT_EQ(array_values(xml, "Name=\"displacement\"").size(), 3 * m.nodes.size());
  EXPECT_EQ(array_values(xml, "Name=\"strain\"").size(), m.tets.size());
}

TEST(Vtk, RejectsArraysOfTheWrongLength) {
  fem::TetMesh m;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  io::VtkFields f;
  f.cell_scalars.push_back({"stress", {1.0, 2.0}});
  std::ostringstream out;
  EXPECT_THROW(io::write_vtu(out, m, f), std::invalid_argument);
  f.cell_scalars.clear();
  f.displacement.assign(3, Eigen::Vector3d::Zero());
  EXPECT_THROW(io::write_vtu(out, m, f), std::invalid_argument);
}
