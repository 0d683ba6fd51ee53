// `codesign sim` end to end: a short run writes the trace with the documented columns, and
// bad input (unknown key, out-of-range value) stops with exit status 2 and no trace.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "run_binary.hpp"

namespace {

namespace fs = std::filesystem;

int run(const std::string& args) {
  const std::string cmd = std::string(CODESIGN_BINARY) + " " + args + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

fs::path scratch(const std::string& name) {
  return codesign::test::scratch_dir("codesign_sim_test_", name);
}

TEST(SimCommand, WritesTrace) {
  const fs::path d = scratch("ok");
  std::ofstream(d / "run.toml") << "[sim]\nsteps = 5\npressures_kPa = [5.0]\n[scene]\nsettle_steps = 3\n";
  ASSERT_EQ(run("sim --config " + (d / "run.toml").string() + " -o " + (d / "out").string() + " --vtk-every 5"), 0);
  std::ifstream in(d / "out" / "trace.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t,theta,F_mN,eps,tip_x,tip_y,tip_z,plate_z,status");
  int rows = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_NE(line.find(",ok"), std::string::npos) << line;
  }
  EXPECT_EQ(rows, 6);  // settled state + 5 steps
  EXPECT_TRUE(fs::exists(d / "out" / "frame_000001.vtu"));
  // A second run into the same directory refuses without --force.
  EXPECT_EQ(run("sim --config " + (d / "run.toml").string() + " -o " + (d / "out").string()), 2);
  fs::remove_all(d);
}

TEST(SimCommand, RejectsBadInput) {
  const fs::path d = scratch("bad");
  std::ofstream(d / "typo.toml") << "[scene]\npreload_nm = 1.0\n";
  EXPECT_EQ(run("sim --config " + (d / "typo.toml").string() + " -o " + (d / "o1").string()), 2);
  EXPECT_FALSE(fs::exists(d / "o1" / "trace.csv"));
  std::ofstream(d / "range.toml") << "[sim]\npressures_kPa = [25.0]\n";
  EXPECT_EQ(run("sim --config " + (d / "range.toml").string() + " -o " + (d / "o2").string()), 2);
  std::ofstream(d / "method.toml") << "[solver]\nmethod = \"magic\"\n";
  EXPECT_EQ(run("sim --config " + (d / "method.toml").string() + " -o " + (d / "o3").string()), 2);
  fs::remove_all(d);
}

}  // namespace
