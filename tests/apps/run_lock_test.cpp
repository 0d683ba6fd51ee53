// One writer per run folder (DIR/.lock, io/formats/run_lock.hpp): while a run writes DIR, another run,
// `--resume`, `--force`, `figures`, `refine` and a `render` into DIR stop with one message naming
// DIR and the holder's pid and host, exit status 2, and change nothing; a lock left by a run
// killed with SIGKILL is taken over.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <unistd.h>

#include "child_process.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::Child;
using codesign::test::run_codesign;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

std::string host() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

TEST(RunLock, LiveFolderRefusesEveryOtherWriterAndAStaleLockIsTakenOver) {
  const fs::path d = codesign::test::scratch_dir("codesign_runlock_", "live");
  codesign::test::TinyRun tiny = codesign::test::TinyRun::minimal();
  tiny.total_timesteps = 1000000;  // runs until this test kills it
  tiny.checkpoint_every = 8;
  std::ofstream(d / "tiny.toml") << tiny.toml();
  const std::string cfg = (d / "tiny.toml").string();
  const fs::path run = d / "run";
  const std::string runs = run.string();
  Child live({"--config", cfg, "-o", runs, "--quiet", "--threads", "1", "--no-figures"}, d / "live.log");
  ASSERT_TRUE(live.wait_until([&] { return fs::exists(run / "checkpoint.bin") && fs::exists(run / ".lock"); }))
      << live.output();
  // Hold the live run still, so that its folder does not change while the others try.
  ASSERT_TRUE(live.pause());
  const auto before = snapshot(run);
  const std::string holder = "pid " + std::to_string(live.pid()) + " on host " + host();
  for (const std::string& args :
       {"--config " + cfg + " -o " + runs + " --quiet", "--config " + cfg + " -o " + runs + " --resume --quiet",
        "--config " + cfg + " -o " + runs + " --force --quiet", "figures --run " + runs, "refine --run " + runs,
        "render --run " + runs + " -o " + runs + "/frames/best"}) {
    const auto r = run_codesign(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find("codesign: error: " + runs + ": another codesign process (" + holder + ")"),
              std::string::npos)
        << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    EXPECT_EQ(snapshot(run), before) << args;
  }
  live.signal(SIGCONT);
  // kill -9 leaves DIR/.lock behind, naming a process that no longer holds it.
  live.signal(SIGKILL);
  live.wait();
  ASSERT_NE(slurp(run / ".lock").find("pid " + std::to_string(live.pid())), std::string::npos);
  const auto r = run_codesign("--config " + cfg + " -o " + runs + " --resume --quiet --stop-after 0");
  EXPECT_EQ(r.status, 4) << r.output;
  EXPECT_NE(r.output.find(runs + "/.lock was left by " + holder + ", which no longer runs"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(run / ".lock"));
  if (!HasFailure()) fs::remove_all(d);
}

}  // namespace
