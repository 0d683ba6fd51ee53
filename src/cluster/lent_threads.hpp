#pragma once
// Ranks on one machine lend each other their threads at the end of a whole rollout.
//
// With whole rollouts (core/run_ahead.hpp) the ranks meet once per iteration, and a split fixed
// for the whole rollout cannot foresee what each environment's episodes will cost: the rank done
// first idles until the last one is done (docs/journal/cluster.md, "Each design meshed once
// across the ranks": about 1.6-2.3 % of two ranks' collection). Ranks that share a machine share its cores, so
// a rank that has run its share sends a short note to the other ranks on its machine and waits
// without holding a core (mpi_wait.hpp); each rank still stepping takes up, from the next environment
// its calling thread steps, its own threads plus those of every finished rank, up to its pool's size. A rank's pool
// therefore holds more threads than it uses at first (pool_threads): they sleep until lent. Results
// do not change: they never depend on how many threads step the environments (env_pool.hpp).
#include <cstddef>
#include <vector>

namespace codesign::cluster {

struct Lending {
  std::size_t own_threads = 0;  // the rank's own threads (--threads); 0: none lent (it uses its whole pool)
  std::vector<int> peers;       // world ranks of the job's other ranks on this rank's machine
};

// The threads of a rank's pool: its `own` threads and room for those of the other ranks on its
// machine (`ranks_here` ranks there, itself included), but no more than its share's environments
// (`envs`: a thread more would have nothing to step) or the cores the process may run on (`cpus`,
// 0: unknown, no limit), and never fewer than `own`. own == 0 (every core already): 0.
std::size_t pool_threads(std::size_t own, std::size_t ranks_here, std::size_t envs, std::size_t cpus);

// The threads a rank steps with once `finished` other ranks of its machine are done:
// own · (1 + finished), at most `pool` (own == 0: the pool).
std::size_t threads_in_use(std::size_t own, std::size_t finished, std::size_t pool);

// The cores this process may run on (its CPU affinity mask; mpirun's --bind-to core leaves one),
// 0 if unknown.
std::size_t cpus_of_this_process();

}  // namespace codesign::cluster
