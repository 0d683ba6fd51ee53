// SIGTERM / SIGINT handling (run/stop_signals.hpp) and a run that a signal stops.
#include "run/stop_signals.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <string>

#include <signal.h>
#include <unistd.h>

#include "run/run.hpp"
#include "test_setup.hpp"

namespace {

namespace fs = std::filesystem;
using namespace codesign::core;
using namespace codesign::run;

void (*handler_of(int signo))(int) {
  struct sigaction now {};
  sigaction(signo, nullptr, &now);
  return now.sa_handler;
}

TEST(StopSignals, FirstSignalSetsTheFlagAndLeavesTheDefaultActionForASecond) {
  // What was installed before comes back afterwards (here: SIGTERM ignored).
  struct sigaction ignore {}, before {};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGTERM, &ignore, &before);
  {
    const StopSignals signals;
    EXPECT_EQ(stop_signal(), 0);
    EXPECT_NE(handler_of(SIGTERM), SIG_IGN);
    EXPECT_NE(handler_of(SIGINT), SIG_DFL);
    std::raise(SIGTERM);  // delivered to this thread before raise returns
    EXPECT_EQ(stop_signal(), SIGTERM);
    // A second SIGTERM or SIGINT would now end the process by the default action.
    EXPECT_EQ(handler_of(SIGTERM), SIG_DFL);
    EXPECT_EQ(handler_of(SIGINT), SIG_DFL);
    EXPECT_EQ(signal_name(stop_signal()), "SIGTERM");
  }
  EXPECT_EQ(handler_of(SIGTERM), SIG_IGN);
  sigaction(SIGTERM, &before, nullptr);
  const StopSignals again;  // a new scope starts with the flag clear
  EXPECT_EQ(stop_signal(), 0);
}

TEST(StopSignals, RunStopsAfterTheIterationWithACheckpoint) {
  const fs::path d = fs::path(::testing::TempDir()) / ("codesign_stopsig_" + std::to_string(::getpid()));
  fs::remove_all(d);
  RunOptions o;
  o.dir = d.string();
  o.threads = 2;
  o.progress = false;
  const StopSignals signals;
  std::raise(SIGINT);  // before the first iteration: the run stops at its end
  const RunResult r = run_codesign(test::tiny_run(), o);
  EXPECT_FALSE(r.completed);
  EXPECT_EQ(r.stop_signal, SIGINT);
  EXPECT_GT(r.timesteps, 0);
  EXPECT_TRUE(fs::exists(d / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(d / "result.toml"));
  EXPECT_FALSE(fs::exists(d / ".lock"));
  fs::remove_all(d);
}

}  // namespace
