// `codesign check`'s rules that need no simulator (run/file_check.hpp, run/file_fit.hpp): the
// surfaces a whisker mesh must carry, and files that are not one codesign reads.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "base/errors.hpp"
#include "run/file_check.hpp"
#include "run/file_fit.hpp"
#include "test_files.hpp"

namespace codesign::run {
namespace {

namespace fs = std::filesystem;

std::string mesh_message(const fem::TetMesh& m) {
  try {
    check_whisker_mesh(m, "w.msh");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FileCheck, AWhiskerMeshNeedsBaseTipAndOneOrTwoChambers) {
  const fem::Tri tri{0, 1, 2};
  fem::TetMesh m;
  EXPECT_EQ(mesh_message(m).rfind("w.msh: physical group \"base\": no triangles", 0), 0u) << mesh_message(m);
  m.base_faces = {tri};
  EXPECT_EQ(mesh_message(m).rfind("w.msh: physical group \"tip\": no triangles", 0), 0u) << mesh_message(m);
  m.tip_faces = {tri};
  EXPECT_EQ(mesh_message(m).rfind("w.msh: physical group \"chamber_1\": no triangles", 0), 0u);
  m.chamber_faces = {{}, {tri}};  // chamber_2 without chamber_1
  EXPECT_EQ(mesh_message(m).rfind("w.msh: physical group \"chamber_1\": no triangles", 0), 0u);
  m.chamber_faces = {{tri}};
  EXPECT_EQ(mesh_message(m), "(no error)");
  m.chamber_faces = {{tri}, {tri}};
  EXPECT_EQ(mesh_message(m), "(no error)");
  m.chamber_faces = {{tri}, {tri}, {tri}};
  EXPECT_EQ(mesh_message(m), "w.msh: physical group \"chamber_3\": at most 2 chambers (chamber_1, chamber_2) are "
                             "allowed");
}

TEST(FileCheck, NamesWhatItCannotRead) {
  const fs::path dir = test_files::fresh_dir("file_check");
  fs::create_directories(dir);
  auto message = [](const std::string& file) -> std::string {
    try {
      check_file(file, "");
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(message((dir / "missing.bin").string()), (dir / "missing.bin").string() + ": cannot open");
  std::ofstream(dir / "notes.txt") << "not a mesh, policy or checkpoint\n";
  EXPECT_EQ(message((dir / "notes.txt").string()).find((dir / "notes.txt").string() + ": not a file codesign reads"),
            0u);
  // A checkpoint's magic without --config: the config is required.
  std::ofstream(dir / "c.bin", std::ios::binary) << "CDSCKPT1 and then nothing";
  EXPECT_EQ(message((dir / "c.bin").string()).find("checkpoint " + (dir / "c.bin").string() + ": --config is required"),
            0u);
}

}  // namespace
}  // namespace codesign::run
