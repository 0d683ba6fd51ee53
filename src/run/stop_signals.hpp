#pragma once
// SIGTERM and SIGINT during a co-design run: the first one asks the run to stop after the
// iteration it is in (run.cpp checks stop_signal() between iterations, writes the checkpoint
// --resume reads, and returns); a second one, of either kind, ends the process at once by the
// signal's default action.
//
// The handler stores the signal number in one process-wide flag and puts both signals back to
// their default action (sigaction is async-signal-safe); it does nothing else. That flag is the
// one piece of process-global state here, and it has to be: a signal handler cannot reach any
// object of the run.
#include <cstdint>
#include <string>

namespace codesign::run {

// Installs the handlers for its lifetime (clearing the flag); the destructor restores the
// actions that were there before. Only one may exist at a time.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

// 0, or the signal (SIGTERM, SIGINT) that asked the process to stop.
int stop_signal();
// "SIGTERM", "SIGINT", or "signal N".
std::string signal_name(int signo);

// The line on stderr when a signal stopped a run in DIR: the signal, where the run stopped
// (`where`), the timestep t of total that checkpoint.bin holds and the command that continues it.
void print_run_stopped(int signo, const std::string& where, std::int64_t t, std::int64_t total,
                       const std::string& dir);

// After a completed run, before drawing its frames and/or figures (the flags say which are
// still to come): if a signal asked to stop, prints one line saying that the run is complete,
// what is skipped and the commands that draw it, and returns 128 + signal; otherwise (or with
// nothing left to skip) returns 0.
int stop_after_run(const std::string& dir, bool frames_left, bool figures_left);

}  // namespace codesign::run
