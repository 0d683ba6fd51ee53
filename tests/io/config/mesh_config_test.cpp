#include <gtest/gtest.h>

#include <string>

#include "base/errors.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/mesh_config.hpp"
#include "io/config/toml_reader.hpp"

using namespace codesign;

namespace {

std::string error_of(const std::string& toml) {
  try {
    io::TableReader root = io::TableReader::from_string(toml, "run.toml");
    io::read_fem_tables(root);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MeshConfig, DefaultsWithoutTables) {
  io::TableReader root = io::TableReader::from_string("", "run.toml");
  const fem::WhiskerGeometry g = io::read_geometry(root);
  EXPECT_EQ(g.length_mm, 100.0);
  EXPECT_EQ(g.base_diameter_mm, 24.0);
  EXPECT_EQ(g.tip_diameter_mm, 4.0);
  const fem::MeshOptions o = io::read_mesh_options(root);
  EXPECT_EQ(o.max_size_mm, fem::MeshOptions{}.max_size_mm);
}

TEST(MeshConfig, ReadsValues) {
  io::TableReader root = io::TableReader::from_string(
      "[geometry]\nlength_mm = 120.0\nbase_diameter_mm = 26.0\n"
      "[mesh]\nmax_size_mm = 4.0\nmin_dihedral_deg = 6.0\n"
      "[fibres]\ncount = 4\npitch_mm = 2.5\n",
      "run.toml");
  EXPECT_EQ(io::read_geometry(root).length_mm, 120.0);
  const fem::MeshOptions o = io::read_mesh_options(root);
  EXPECT_EQ(o.max_size_mm, 4.0);
  EXPECT_EQ(o.quality.min_dihedral_deg, 6.0);
  const fem::FibreLayoutOptions f = io::read_fem_tables(root).spec.fibres;
  EXPECT_EQ(f.count, 4);
  EXPECT_EQ(f.pitch_mm, 2.5);
}

TEST(MeshConfig, RejectsBadInput) {
  const std::string unknown = error_of("[mesh]\nmax_size = 4.0\n");
  EXPECT_NE(unknown.find("run.toml"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("max_size"), std::string::npos) << unknown;
  const std::string range = error_of("[geometry]\nlength_mm = 5.0\n");
  EXPECT_NE(range.find("geometry.length_mm"), std::string::npos) << range;
  const std::string inset = error_of("[fibres]\nradial_inset_mm = 3.0\n");
  EXPECT_NE(inset.find("radial_inset_mm"), std::string::npos) << inset;
  // A geometry too slender for the longest chamber with the thickest wall.
  const std::string slender = error_of("[geometry]\nbase_diameter_mm = 10.0\n");
  EXPECT_NE(slender.find("cannot hold design"), std::string::npos) << slender;
}
