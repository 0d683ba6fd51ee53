#include "cluster/lent_threads.hpp"

#include <sched.h>

#include <algorithm>

namespace codesign::cluster {

std::size_t pool_threads(std::size_t own, std::size_t ranks_here, std::size_t envs, std::size_t cpus) {
  if (own == 0) return 0;
  std::size_t n = own * std::max<std::size_t>(ranks_here, 1);
  n = std::min(n, std::max<std::size_t>(envs, 1));
  if (cpus > 0) n = std::min(n, cpus);
  return std::max(n, own);
}

std::size_t threads_in_use(std::size_t own, std::size_t finished, std::size_t pool) {
  if (own == 0) return pool;
  return std::min(own * (1 + finished), pool);
}

std::size_t cpus_of_this_process() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 0;
  return static_cast<std::size_t>(CPU_COUNT(&set));
}

}  // namespace codesign::cluster
