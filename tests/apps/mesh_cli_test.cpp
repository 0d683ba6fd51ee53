#include <gtest/gtest.h>

#include <string>

#include "fem/mesh_quality.hpp"
#include "io/formats/msh.hpp"
#include "test_util.hpp"
#include "run_binary.hpp"

using namespace codesign;

namespace {

using Result = test::RunResult;

// CMake builds the `codesign` binary before test_apps, so a missing binary is a failure.
#define REQUIRE_BINARY() ASSERT_TRUE(std::filesystem::exists(CODESIGN_BINARY)) << CODESIGN_BINARY

}  // namespace

TEST(CmdMesh, WritesMshThatReadsBack) {
  REQUIRE_BINARY();
  const auto dir = test::scratch_dir();
  const std::string msh = (dir / "j21.msh").string(), vtu = (dir / "j21.vtu").string();
  const Result r = test::run_codesign("mesh --design 21 -o " + msh + " --vtk " + vtu + " --check");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("j21 {n=1, l=28 mm, w=2.5 mm}"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("PASS"), std::string::npos) << r.output;
  const fem::TetMesh m = io::read_msh_file(msh);
  fem::WhiskerGeometry g;
  g.design = fem::design_from_index(21);
  EXPECT_TRUE(fem::check_whisker_mesh(m, g).ok());
  EXPECT_TRUE(std::filesystem::exists(vtu));
  EXPECT_FALSE(std::filesystem::exists(msh + ".tmp"));
}

TEST(CmdMesh, BadDesignIndexIsAnInputError) {
  REQUIRE_BINARY();
  const Result r = test::run_codesign("mesh --design 110 -o x.msh");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--design 110: allowed range 0..109"), std::string::npos) << r.output;
  EXPECT_EQ(test::run_codesign("mesh --design -1").status, 2);
  EXPECT_EQ(test::run_codesign("mesh").status, 2);
}
