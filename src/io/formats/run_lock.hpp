#pragma once
// One writer per run folder: DIR/.lock, held with flock(LOCK_EX) by the process that writes the
// folder, for as long as it writes it.
//
// Why flock: the kernel releases the lock when its holder dies for any reason (kill -9, a
// crash, an OOM kill), so a lock left by a dead process is never mistaken for a live one and
// needs no pid probing or timeouts; a lock file created with O_EXCL would stay behind after
// kill -9 and need exactly that guesswork. flock works on local disks and, on Linux, on NFS
// (where the kernel maps it to POSIX byte-range locks); the pid and host written into the file
// are for the message only, never to decide who holds the lock.
//
// The file holds "pid N\nhost H\n". A process that cannot take the lock reads it to name the
// holder, and changes nothing: the file is opened without truncating, and written only by the
// process that holds the lock. The holder removes the file before it lets the lock go, so a
// finished run folder holds no .lock; a process that locked a file that was removed meanwhile
// (its inode is no longer DIR/.lock) lets it go and tries again. The descriptor is close-on-exec,
// so a child program (gnuplot) does not keep the lock alive.
#include <string>

namespace codesign::io {

class RunLock {
 public:
  // Creates DIR if missing and takes DIR/.lock. Throws codesign::InputError if another process
  // holds it (naming DIR, that process's pid and host) or if the lock cannot be taken.
  explicit RunLock(const std::string& dir);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

  const std::string& path() const { return path_; }
  // The holder a lock file named when this process took it over, e.g. "pid 123 on host h",
  // i.e. a process that ended without releasing it (killed); "" if the file was new.
  const std::string& stale_holder() const { return stale_; }

 private:
  std::string path_;
  std::string stale_;
  int fd_ = -1;
};

}  // namespace codesign::io
