#include "base/file_write.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

#include "base/errors.hpp"

namespace codesign {

std::string file_error_text(const std::string& path, const std::string& what, int error) {
  return path + ": " + what + ": " + std::strerror(error);
}

void write_bytes_atomically(const std::string& path, std::string_view bytes) {
  const std::string tmp = path + ".tmp";
  auto fail = [&](const std::string& what, int error, int fd) {
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw FileError(file_error_text(tmp, what, error) + " (" + path + " left as it was)");
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail("cannot create", errno, -1);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot write", n < 0 ? errno : ENOSPC, fd);
    done += static_cast<std::size_t>(n);
  }
  // close() reports late write errors of some file systems (NFS quota, for one).
  if (::close(fd) != 0) fail("cannot write", errno, -1);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    ::unlink(tmp.c_str());
    throw FileError(file_error_text(path, "cannot rename " + tmp + " to it", e) + " (" + path + " left as it was)");
  }
}

}  // namespace codesign
