#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gmsh.h>

#include "base/errors.hpp"
#include "fem/design.hpp"
#include "fem/mesh_ops.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/whisker_mesh.hpp"
#include "io/formats/msh.hpp"
#include "test_util.hpp"

using namespace codesign;
using fem::TetMesh;

namespace {

TetMesh read_text(const std::string& text, const std::string& label = "t.msh") {
  std::istringstream in(text);
  return io::read_msh(in, label);
}

// The message of the InputError thrown while reading `text`, or "" if none was thrown.
std::string read_error(const std::string& text) {
  try {
    read_text(text, "bad.msh");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Two tets sharing a face (the second listed with negative orientation), written as gmsh would:
// point and curve entities, non-contiguous node tags spread over entity blocks, a line element
// block, the physical group of the tagged surface given through $Entities.
const char* kGmshStyle = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
2 11 "base"
2 12 "tip"
3 20 "whisker"
$EndPhysicalNames
$Entities
1 1 2 1
1 0 0 0 0
1 0 0 0 1 0 0 0 2 1 -1
1 0 0 0 1 1 0 1 11 0
2 0 0 0 1 1 1 1 12 0
1 0 0 0 1 1 1 1 20 2 1 2
$EndEntities
$Nodes
3 5 10 50
0 1 0 1
10
0 0 0
1 1 1 1
30
1 0 0 0.5
2 2 0 3
40
50
20
0 1 0
0 0 1
1 1 1
$EndNodes
$Elements
4 5 1 9
1 1 1 1
1 10 30
2 1 2 1
3 10 30 40
2 2 2 1
4 50 20 30
3 1 4 2
8 10 30 40 50
9 20 30 40 50
$EndElements
$Comments
anything
$EndComments
)";

}  // namespace

TEST(Msh, RoundTripIsExact) {
  for (int j : {21, 63}) {
    fem::WhiskerGeometry g;
    g.design = fem::design_from_index(j);
    const TetMesh m = fem::mesh_whisker(g);
    const auto path = (test::scratch_dir() / ("j" + std::to_string(j) + ".msh")).string();
    io::write_msh_file(path, m);
    const TetMesh r = io::read_msh_file(path);
    // %.17g prints every double exactly, so positions must come back bit for bit.
    ASSERT_EQ(r.nodes.size(), m.nodes.size());
    for (std::size_t i = 0; i < m.nodes.size(); ++i) EXPECT_EQ(r.nodes[i], m.nodes[i]);
    EXPECT_EQ(r.tets, m.tets);
    EXPECT_EQ(r.base_faces, m.base_faces);
    EXPECT_EQ(r.tip_faces, m.tip_faces);
    EXPECT_EQ(r.chamber_faces, m.chamber_faces);
    EXPECT_TRUE(fem::check_whisker_mesh(r, g).ok());
  }
}

TEST(Msh, ReadsGmshStyleText) {
  const TetMesh m = read_text(kGmshStyle);
  ASSERT_EQ(m.nodes.size(), 5u);
  ASSERT_EQ(m.tets.size(), 2u);
  for (int t = 0; t < 2; ++t) EXPECT_GT(fem::tet_volume(m, t), 0.0);  // 2nd tet was negative in the file
  // Corner tet of the unit cube (1/6) plus the tet (1,1,1) (1,0,0) (0,1,0) (0,0,1) (1/3).
  EXPECT_NEAR(fem::total_volume(m), 1.0 / 6 + 1.0 / 3, 1e-12);
  ASSERT_EQ(m.base_faces.size(), 1u);
  ASSERT_EQ(m.tip_faces.size(), 1u);
  EXPECT_TRUE(m.chamber_faces.empty());
  // Tagged faces re-oriented out of the solid: base (z = 0 plane) normal points to -z.
  EXPECT_LT(fem::vector_area(m, m.base_faces).z(), 0.0);
  for (int v : m.base_faces[0]) EXPECT_EQ(m.nodes[v].z(), 0.0);
  // The tip face (0,0,1) (1,1,1) (1,0,0) belongs to the second tet: its normal points away
  // from that tet's fourth node (0,1,0).
  const auto& tf = m.tip_faces[0];
  const Eigen::Vector3d centroid = (m.nodes[tf[0]] + m.nodes[tf[1]] + m.nodes[tf[2]]) / 3;
  EXPECT_GT(fem::vector_area(m, m.tip_faces).dot(centroid - Eigen::Vector3d(0, 1, 0)), 0.0);
}

TEST(Msh, ReadsAFileWrittenByGmsh) {
  // Let gmsh itself write a small tagged cylinder (its own entity layout and numbering).
  const auto path = (test::scratch_dir() / "gmsh_written.msh").string();
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::model::add("cyl");
  gmsh::model::occ::addCylinder(0, 0, 0, 10, 0, 0, 2);
  gmsh::model::occ::synchronize();
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {1}), "whisker");
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, tag] : surfaces) {
    double xa, ya, za, xb, yb, zb;
    gmsh::model::getBoundingBox(dim, tag, xa, ya, za, xb, yb, zb);
    if (xb - xa < 1e-3) gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {tag}), xa < 5 ? "base" : "tip");
  }
  gmsh::option::setNumber("Mesh.MeshSizeMax", 1.5);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::model::mesh::generate(3);
  gmsh::write(path);
  gmsh::finalize();

  const TetMesh m = io::read_msh_file(path);
  const fem::QualityReport r = fem::check_mesh(m);
  EXPECT_TRUE(r.ok()) << fem::summary(r);
  const double v = std::numbers::pi * 4 * 10;
  EXPECT_LE(std::abs(r.total_volume - v), fem::faceting_volume_bound(m, fem::boundary_faces(m)));
  EXPECT_LT(fem::vector_area(m, m.base_faces).x(), 0.0);
  EXPECT_GT(fem::vector_area(m, m.tip_faces).x(), 0.0);
  const auto [lo, hi] = test::disc_area_bounds(m, m.base_faces, 2.0);
  EXPECT_GE(fem::surface_area(m, m.base_faces), lo);
  EXPECT_LE(fem::surface_area(m, m.base_faces), hi);
}

TEST(Msh, MalformedFilesNameFileAndLine) {
  const std::string good = kGmshStyle;
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  EXPECT_EQ(read_error(replaced("4.1 0 8", "2.2 0 8")), "bad.msh:2: expected 4.1 in $MeshFormat, got '2.2'");
  EXPECT_NE(read_error(replaced("4.1 0 8", "4.1 1 8")).find("bad.msh:2: expected file type 0"), std::string::npos);
  // A coordinate that is not a number (line 22 holds node 10's coordinates).
  EXPECT_EQ(read_error(replaced("0 0 0\n1 1 1 1", "0 x 0\n1 1 1 1")),
            "bad.msh:22: expected node coordinate, got 'x'");
  // An element that refers to an unknown node (line 44: second tet).
  EXPECT_EQ(read_error(replaced("9 20 30 40 50", "9 20 30 40 99")),
            "bad.msh:44: expected a node tag listed in $Nodes, got 99");
  // Second-order tetrahedra are rejected.
  EXPECT_NE(read_error(replaced("3 1 4 2", "3 1 11 2")).find("bad.msh:42: expected element type 4"), std::string::npos);
  // Truncated file.
  EXPECT_NE(read_error(good.substr(0, good.find("$EndNodes"))).find("got end of file"), std::string::npos);
  // Not a mesh at all.
  EXPECT_EQ(read_error("hello\n"), "bad.msh:1: expected a section header such as $Nodes, got 'hello'");
  EXPECT_EQ(read_error(""), "bad.msh:1: expected $MeshFormat section, got none");
  // Missing file.
  EXPECT_THROW(io::read_msh_file("/nonexistent/none.msh"), InputError);
}

TEST(Msh, TaggedFaceThatIsNotOnTheBoundaryIsRejected) {
  // Tag the shared interior face (10 30 40) as base.
  std::string s = kGmshStyle;
  s.replace(s.find("3 10 30 40\n"), 10, "3 30 40 50");
  const std::string err = read_error(s);
  EXPECT_NE(err.find("bad.msh: tagged face of 'base'"), std::string::npos) << err;
}
