#include "run/stop_signals.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include <signal.h>

#include "run/run_folder.hpp"

namespace codesign::run {

namespace {

// Process-global by necessity (see the header): written by the handler, read by the run loop.
// A lock-free atomic int is safe to store from a signal handler.
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

struct sigaction g_previous_term, g_previous_int;

extern "C" void on_stop_signal(int signo) {
  int none = 0;
  const bool first = g_stop_signal.compare_exchange_strong(none, signo);
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(SIGTERM, &dfl, nullptr);
  sigaction(SIGINT, &dfl, nullptr);
  // Two signals sent back to back can reach two threads at once, both before either handler
  // has restored the default action: the one that finds a signal already recorded is the
  // second, and ends the process with the default action (raise() leaves it pending, blocked by
  // sa_mask, until this handler returns).
  if (!first) raise(signo);
}

}  // namespace

StopSignals::StopSignals() {
  g_stop_signal.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  // Both signals blocked while the handler runs: a second signal arriving meanwhile is delivered
  // after it, under the default action, instead of re-entering it.
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGTERM);
  sigaddset(&sa.sa_mask, SIGINT);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGTERM, &sa, &g_previous_term);
  sigaction(SIGINT, &sa, &g_previous_int);
}

StopSignals::~StopSignals() {
  sigaction(SIGTERM, &g_previous_term, nullptr);
  sigaction(SIGINT, &g_previous_int, nullptr);
}

int stop_signal() { return g_stop_signal.load(); }

std::string signal_name(int signo) {
  if (signo == SIGTERM) return "SIGTERM";
  if (signo == SIGINT) return "SIGINT";
  return "signal " + std::to_string(signo);
}

void print_run_stopped(int signo, const std::string& where, std::int64_t t, std::int64_t total,
                       const std::string& dir) {
  std::fprintf(stderr, "codesign: %s: %s; checkpoint.bin holds t = %lld of %lld; continue with: "
               "codesign --config %s -o %s --resume\n",
               signal_name(signo).c_str(), where.c_str(), static_cast<long long>(t), static_cast<long long>(total),
               (std::filesystem::path(dir) / run_file::kConfig).string().c_str(),
               std::filesystem::path(dir).string().c_str());
}

int stop_after_run(const std::string& dir, bool frames_left, bool figures_left) {
  const int sig = stop_signal();
  if (sig == 0 || (!frames_left && !figures_left)) return 0;
  std::string what, how;
  if (frames_left) {
    what = "its frames";
    how = "`codesign render --run " + dir + " -o " + (std::filesystem::path(dir) / run_file::kFramesDir / "best").string() + "`";
  }
  if (figures_left) {
    what += what.empty() ? "its figures" : " and figures";
    how += (how.empty() ? "" : " and ") + ("`codesign figures --run " + dir + "`");
  }
  std::fprintf(stderr, "codesign: %s: the run in %s is complete (result.toml); %s skipped: draw them with %s\n",
               signal_name(sig).c_str(), dir.c_str(), what.c_str(), how.c_str());
  return 128 + sig;
}

}  // namespace codesign::run
