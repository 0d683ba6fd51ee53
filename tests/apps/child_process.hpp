#pragma once
// The built `codesign` binary as a child process the test can signal: started with fork + exec
// (nothing else runs in the child between the two), its stdout and stderr into a file.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace codesign::test {

class Child {
 public:
  Child(const std::vector<std::string>& args, const std::filesystem::path& log) : log_(log) {
    std::vector<char*> argv{const_cast<char*>(CODESIGN_BINARY)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out, 1);
      ::dup2(out, 2);
      ::execv(CODESIGN_BINARY, argv.data());
      ::_exit(127);
    }
    ::close(out);
  }
  ~Child() {
    if (pid_ > 0 && !done_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status_, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int signo) const { ::kill(pid_, signo); }
  // SIGSTOP, and back only once the process has stopped (kill alone may return before).
  bool pause() {
    ::kill(pid_, SIGSTOP);
    int st = 0;
    return ::waitpid(pid_, &st, WUNTRACED) == pid_ && WIFSTOPPED(st);
  }

  // True once the process has ended (reaped).
  bool finished() {
    if (!done_ && ::waitpid(pid_, &status_, WNOHANG) == pid_) done_ = true;
    return done_;
  }
  // Waits until `ready` holds or the process ended, at most `timeout`; true if `ready` held.
  bool wait_until(const std::function<bool()>& ready, std::chrono::seconds timeout = std::chrono::seconds(240)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      if (ready()) return true;
      if (finished()) return ready();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  // Waits for the end (at most `timeout`, then SIGKILL); the raw wait status.
  int wait(std::chrono::seconds timeout = std::chrono::seconds(600)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!finished() && std::chrono::steady_clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!done_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status_, 0);
      done_ = true;
    }
    return status_;
  }
  std::string output() const {
    std::ifstream in(log_);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  std::filesystem::path log_;
  pid_t pid_ = -1;
  int status_ = 0;
  bool done_ = false;
};

}  // namespace codesign::test
