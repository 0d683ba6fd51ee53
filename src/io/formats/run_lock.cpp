#include "io/formats/run_lock.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/errors.hpp"

namespace codesign::io {

namespace {

std::string errno_text(int e) { return std::strerror(e); }

// The holder a lock file names ("pid 123 on host h"), or "" for an empty or unreadable file.
std::string holder_of(int fd) {
  std::string text;
  char buf[256];
  off_t at = 0;
  for (;;) {
    const ssize_t n = ::pread(fd, buf, sizeof buf, at);
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
    at += n;
    if (text.size() > 4096) break;
  }
  std::istringstream in(text);
  std::string key, value, pid, host;
  while (in >> key >> value) {
    if (key == "pid") pid = value;
    if (key == "host") host = value;
  }
  if (pid.empty()) return "";
  return "pid " + pid + " on host " + (host.empty() ? "?" : host);
}

std::string this_host() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "?";
  return name;
}

}  // namespace

RunLock::RunLock(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the run folder: " + ec.message());
  path_ = (std::filesystem::path(dir) / ".lock").string();
  // A few rounds at most: a round fails only if the holder removed the file between our open
  // and our flock, i.e. it has just finished.
  for (int round = 0; round < 100; ++round) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw InputError(path_ + ": cannot open the run folder's lock file: " + errno_text(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      const std::string holder = holder_of(fd);
      ::close(fd);
      if (e == EWOULDBLOCK)
        throw InputError(dir + ": another codesign process (" +
                         (holder.empty() ? std::string("one that has not written its pid yet") : holder) +
                         ") is writing this run folder and holds " + path_ +
                         "; wait until it ends, or stop it first (SIGTERM checkpoints and stops a run)");
      throw InputError(path_ + ": cannot lock the run folder: " + errno_text(e));
    }
    struct stat held {}, named {};
    if (::fstat(fd, &held) != 0 || ::stat(path_.c_str(), &named) != 0 || held.st_ino != named.st_ino ||
        held.st_dev != named.st_dev) {
      ::close(fd);  // the file we locked was removed by its holder meanwhile: take the new one
      continue;
    }
    stale_ = holder_of(fd);
    std::ostringstream text;
    text << "pid " << ::getpid() << "\nhost " << this_host() << "\n";
    const std::string s = text.str();
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, s.data(), s.size(), 0) != static_cast<ssize_t>(s.size())) {
      const int e = errno;
      ::unlink(path_.c_str());
      ::close(fd);
      throw InputError(path_ + ": cannot write the run folder's lock file: " + errno_text(e));
    }
    fd_ = fd;
    return;
  }
  throw InputError(path_ + ": cannot lock the run folder: its lock file keeps being replaced");
}

RunLock::~RunLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still holding it: a process waiting on this inode sees it gone
  ::close(fd_);
}

}  // namespace codesign::io
