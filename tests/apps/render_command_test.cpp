// `codesign render` and the frames at the end of `codesign run`.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/formats/png_file.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;

const std::string kTiny = [] {
  codesign::test::TinyRun r;
  r.total_timesteps = 80;
  r.exploration_end = 20;
  r.exploitation_start = 40;
  r.eval_episodes = 2;
  r.seed = 3;
  r.tables =
      "[sim]\ndesign = 21\ntheta_deg = [0.0, -2.0]\ntheta_hold_steps = 5\nsteps = 10\n"
      "[render]\nwidth = 256\nheight = 144\nevery_steps = 5\n";
  return r.toml();
}();

fs::path scratch(const std::string& name) {
  const fs::path d = codesign::test::scratch_dir("codesign_rendercmd_", name);
  std::ofstream(d / "tiny.toml") << kTiny;
  return d;
}

// Column `name` of a CSV file.
std::vector<std::string> column(const fs::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ',');) head.push_back(c);
  }
  const auto at = std::find(head.begin(), head.end(), name) - head.begin();
  std::vector<std::string> out;
  while (std::getline(in, line)) {
    std::istringstream r(line);
    std::string c;
    for (long k = 0; k <= at; ++k) std::getline(r, c, ',');
    out.push_back(c);
  }
  return out;
}

int png_count(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ".png";
  return n;
}

}  // namespace

TEST(RenderCommand, SimScenarioSideBySideAndErrors) {
  const fs::path d = scratch("sim");
  const std::string cfg = (d / "tiny.toml").string(), out = (d / "frames").string();
  auto r = run_codesign("render --config " + cfg + " --sim -o " + out + " --compare 63 --width 320 --height 160");
  ASSERT_EQ(r.status, 0) << r.output;
  // 10 steps, a frame every 5: settled, 5, 10.
  EXPECT_EQ(png_count(out), 3);
  const codesign::io::RgbImage img = codesign::io::read_png((fs::path(out) / "frame_0002.png").string());
  EXPECT_EQ(img.width, 320);
  EXPECT_EQ(img.height, 160);
  EXPECT_EQ(column(fs::path(out) / "frames.csv", "panel"), (std::vector<std::string>{"0", "1", "0", "1", "0", "1"}));
  // An earlier render is not overwritten.
  const auto before = fs::last_write_time(fs::path(out) / "frame_0000.png");
  r = run_codesign("render --config " + cfg + " --sim -o " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("frame_0000.png"), std::string::npos) << r.output;
  EXPECT_EQ(fs::last_write_time(fs::path(out) / "frame_0000.png"), before);
  // Bad sizes and pressures name the option and the range.
  r = run_codesign("render --config " + cfg + " -o " + (d / "x").string() + " --width 20");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("render.width"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[64, 4096]"), std::string::npos) << r.output;
  r = run_codesign("render --config " + cfg + " -o " + (d / "x").string() + " --pressures 5,30");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--pressures"), std::string::npos) << r.output;
  std::ofstream(d / "bad.toml") << "[render]\nheight = 5000\n";
  r = run_codesign("render --config " + (d / "bad.toml").string() + " -o " + (d / "x").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("render.height"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "x"));
  fs::remove_all(d);
}

TEST(RenderCommand, RunEndsWithFramesOfItsEvaluationEpisodes) {
  const fs::path d = scratch("run");
  const fs::path run = d / "run";
  auto r = run_codesign("--config " + (d / "tiny.toml").string() + " -o " + run.string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* which : {"best", "runner_up"}) {
    const fs::path dir = run / "frames" / which;
    // 25 steps, a frame every 5 steps: 6 frames (fewer if the episode ended early).
    const std::vector<std::string> t = column(dir / "frames.csv", "t_s");
    ASSERT_GE(t.size(), 1u) << which;
    EXPECT_EQ(png_count(dir), static_cast<int>(t.size())) << which;
    // The frames show the first evaluation episode: their forces are rows of its trace.
    const std::vector<std::string> trace = column(run / "eval" / (std::string(which) + "_trace.csv"), "F_mN");
    const std::vector<std::string> f = column(dir / "frames.csv", "F_mN");
    const std::vector<std::string> step = column(dir / "frames.csv", "step");
    for (std::size_t k = 0; k < f.size(); ++k) {
      const auto s = static_cast<std::size_t>(std::stoi(step[k]));
      ASSERT_LT(s, trace.size());
      EXPECT_EQ(f[k], trace[s]) << which << " frame " << k;
    }
  }
  // `codesign render --run` renders both side by side again.
  r = run_codesign("render --run " + run.string() + " --which both -o " + (d / "both").string() +
                   " --width 200 --height 100 --every 5");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(png_count(d / "both"), png_count(run / "frames" / "best") > png_count(run / "frames" / "runner_up")
                                       ? png_count(run / "frames" / "best")
                                       : png_count(run / "frames" / "runner_up"));
  fs::remove_all(d);
}
