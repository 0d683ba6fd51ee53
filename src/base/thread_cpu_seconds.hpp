#pragma once
// CPU time of the calling thread [s]: the benches' split of the rollouts' work (settles, FEM steps,
// simulator builds) then does not count time the scheduler gave to other threads or processes.
#include <ctime>

namespace codesign {

inline double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// CPU time of the whole process, all its threads [s]: what a command cost, also when other
// processes shared the cores (their time is not counted; this process's threads waiting are not).
inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace codesign
