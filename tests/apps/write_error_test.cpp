// The binary on a full disk: a checkpoint or a PNG frame that cannot be written stops the command
// with one message naming the file and "No space left on device", exit status 2 (not "internal
// error"), and the files written before stay. The full disk is /dev/full behind the writer's
// temporary file (PATH.tmp as a symbolic link to it), which needs no root and no tmpfs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;

TEST(WriteErrorCli, FullDiskAtACheckpointIsOneMessageNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path d = codesign::test::scratch_dir("codesign_writeerr_", "ckpt");
  std::ofstream(d / "tiny.toml") << codesign::test::TinyRun::minimal().toml();
  const fs::path run = d / "run";
  fs::create_directories(run);
  fs::create_symlink("/dev/full", run / "checkpoint.bin.tmp");
  const auto r = run_codesign("--config " + (d / "tiny.toml").string() + " -o " + run.string() + " --quiet");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "codesign: error: " + (run / "checkpoint.bin.tmp").string() +
                          ": cannot write: No space left on device (" + (run / "checkpoint.bin").string() +
                          " left as it was)\n");
  // The files written before the checkpoint are there; nothing half-written is left.
  for (const char* f : {"config.toml", "config.input.toml", "episodes.csv"}) EXPECT_TRUE(fs::exists(run / f)) << f;
  EXPECT_FALSE(fs::exists(run / "checkpoint.bin"));
  EXPECT_FALSE(fs::is_symlink(run / "checkpoint.bin.tmp"));
  EXPECT_FALSE(fs::exists(run / ".lock"));
  if (!HasFailure()) fs::remove_all(d);
}

TEST(WriteErrorCli, FullDiskWhileRenderingNamesTheFrame) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path d = codesign::test::scratch_dir("codesign_writeerr_", "png");
  codesign::test::TinyRun tiny = codesign::test::TinyRun::minimal();
  tiny.tables =
      "[sim]\ndesign = 21\ntheta_deg = [0.0, -2.0]\ntheta_hold_steps = 5\nsteps = 20\n"
      "[render]\nwidth = 128\nheight = 96\nevery_steps = 5\n";
  std::ofstream(d / "tiny.toml") << tiny.toml();
  const fs::path out = d / "frames";
  fs::create_directories(out);
  fs::create_symlink("/dev/full", out / "frame_0002.png.tmp");
  const auto r = run_codesign("render --config " + (d / "tiny.toml").string() + " --sim -o " + out.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "codesign: error: " + (out / "frame_0002.png.tmp").string() +
                          ": cannot write: No space left on device (" + (out / "frame_0002.png").string() +
                          " left as it was)\n");
  EXPECT_TRUE(fs::exists(out / "frame_0000.png"));
  EXPECT_TRUE(fs::exists(out / "frame_0001.png"));
  EXPECT_FALSE(fs::exists(out / "frame_0002.png"));
  if (!HasFailure()) fs::remove_all(d);
}

}  // namespace
