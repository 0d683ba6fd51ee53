/* LD_PRELOAD shim of scripts/kill_campaign.sh: holds a process inside a checkpoint write so a
 * kill -9 lands there for certain. Not part of codesign; the binary runs unchanged.
 *
 * It watches write(), writev() and rename() of files whose name ends in KILL_WINDOW_FILE
 * (default "checkpoint.bin.tmp"). After KILL_WINDOW_SKIP (default 0) checkpoint writes have
 * gone through untouched, the next one is held:
 *   KILL_WINDOW_AT=write   (default) half of the bytes of the first write to the file are
 *                          written, then the thread stops: the .tmp file is truncated;
 *   KILL_WINDOW_AT=rename  the .tmp file is complete, the thread stops before rename().
 * Stopping means: create the file KILL_WINDOW_MARKER (so the script knows the window is open)
 * and sleep 120 s, long enough for the script's kill -9; if nobody kills the process it then
 * carries on as if nothing happened. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static int ends_with(const char* s, const char* suffix) {
  const size_t n = strlen(s), m = strlen(suffix);
  return n >= m && strcmp(s + n - m, suffix) == 0;
}

static const char* watched(void) {
  const char* f = getenv("KILL_WINDOW_FILE");
  return f && *f ? f : "checkpoint.bin.tmp";
}

static int fd_is_watched(int fd) {
  char link[64], path[4096];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, path, sizeof path - 1);
  if (n <= 0) return 0;
  path[n] = '\0';
  return ends_with(path, watched());
}

static int mode_is(const char* m) {
  const char* at = getenv("KILL_WINDOW_AT");
  return strcmp(at && *at ? at : "write", m) == 0;
}

/* Counts checkpoint writes; should_hold() is 1 when the current one is to be held. Only the main thread writes
 * checkpoints, so plain statics suffice here (this is the test shim, not the product). */
static int writes_seen = 0;
static int should_hold(void) {
  const char* skip = getenv("KILL_WINDOW_SKIP");
  return writes_seen == (skip ? atoi(skip) : 0) + 1;
}

static void hold(void) {
  const char* marker = getenv("KILL_WINDOW_MARKER");
  if (marker) {
    const int fd = open(marker, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) close(fd);
  }
  sleep(120);
}

/* A write at offset 0 of the watched file starts a new checkpoint write. */
static void note(int fd) {
  if (lseek(fd, 0, SEEK_CUR) == 0) ++writes_seen;
}

ssize_t write(int fd, const void* buf, size_t count) {
  static ssize_t (*real)(int, const void*, size_t);
  if (!real) real = (ssize_t(*)(int, const void*, size_t))dlsym(RTLD_NEXT, "write");
  if (count > 1 && mode_is("write") && fd_is_watched(fd)) {
    note(fd);
    if (should_hold()) {
      const ssize_t w = real(fd, buf, count / 2);
      hold();
      return w;
    }
  }
  return real(fd, buf, count);
}

ssize_t writev(int fd, const struct iovec* iov, int iovcnt) {
  static ssize_t (*real)(int, const struct iovec*, int);
  static ssize_t (*real_write)(int, const void*, size_t);
  if (!real) real = (ssize_t(*)(int, const struct iovec*, int))dlsym(RTLD_NEXT, "writev");
  if (!real_write) real_write = (ssize_t(*)(int, const void*, size_t))dlsym(RTLD_NEXT, "write");
  if (iovcnt > 0 && mode_is("write") && fd_is_watched(fd)) {
    note(fd);
    if (should_hold()) {
      /* half of the first non-empty buffer: the file is left truncated */
      for (int i = 0; i < iovcnt; ++i) {
        if (iov[i].iov_len > 1) {
          const ssize_t w = real_write(fd, iov[i].iov_base, iov[i].iov_len / 2);
          hold();
          return w;
        }
      }
    }
  }
  return real(fd, iov, iovcnt);
}

int rename(const char* from, const char* to) {
  static int (*real)(const char*, const char*);
  if (!real) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  if (mode_is("rename") && ends_with(from, watched())) {
    ++writes_seen;
    if (should_hold()) hold();
  }
  return real(from, to);
}
