#pragma once
// Memory figures for the benches, printed beside their times.
#include <malloc.h>
#include <sys/resource.h>

namespace codesign {

// The calling process's peak resident memory so far [MiB] (getrusage's ru_maxrss, the figure
// `/usr/bin/time -v` prints as "Maximum resident set size").
inline double peak_resident_mib() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports kibibytes
}

// Heap bytes the process has allocated and not freed [MiB] (glibc's mallinfo2: small blocks in
// use plus mmap'd large ones): the difference across a step is what that step keeps allocated.
inline double heap_in_use_mib() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

}  // namespace codesign
