#pragma once
// A fixed pool of worker threads running one blocking parallel_for at a time.
//
// parallel_for(n, fn) calls fn(i) once for every i in [0, n), spread over the workers and the
// calling thread, and returns when all calls are done. With one thread (or n == 1) everything runs
// inline on the caller. The first exception thrown by fn is rethrown in the caller after the
// remaining calls have finished. Which thread runs which index is not fixed, so fn(i) must only
// touch data owned by index i for results to be independent of the thread count.
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace codesign::rl {

class ThreadPool {
 public:
  // n_threads counts the calling thread: n_threads - 1 workers are started. 0 means
  // std::thread::hardware_concurrency().
  explicit ThreadPool(std::size_t n_threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  std::size_t size() const { return workers_.size() + 1; }
  void parallel_for(std::size_t n, const std::function<void(std::size_t)>& fn);
  // fn(order[0]), fn(order[1]), ...: the same calls, claimed in this order. With the costliest
  // indices first the threads finish closer together (longest-processing-time-first scheduling);
  // the results are those of parallel_for, as fn(i) touches only data of index i.
  // max_threads > 0: at most that many threads (the caller included) take part in this call; the
  // others sleep through it. `recount`, if set, is called on the calling thread after each of its
  // calls of fn and gives the threads that may take part from then on (0: all); a larger figure
  // wakes more workers into the call still running (a smaller one sends none away). For a pool
  // whose spare threads are lent to it now and then (an MPI rank's: cluster/lent_threads.hpp).
  void parallel_for_ordered(const std::vector<std::size_t>& order, const std::function<void(std::size_t)>& fn,
                            std::size_t max_threads = 0, const std::function<std::size_t()>& recount = {});

 private:
  void worker_loop();
  void run_chunk(const std::function<std::size_t()>* recount);
  void run_job(std::size_t n, const std::vector<std::size_t>* order, const std::function<void(std::size_t)>& fn,
               std::size_t max_threads, const std::function<std::size_t()>* recount);
  std::size_t workers_for(std::size_t max_threads) const;  // 0 (all) or max_threads - 1, at most workers_.size()

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  const std::vector<std::size_t>* job_order_ = nullptr;  // null: indices in increasing order
  std::size_t job_size_ = 0;
  std::size_t next_index_ = 0;
  std::size_t busy_ = 0;         // workers currently inside the job
  std::size_t job_workers_ = 0;  // how many workers may be inside it
  std::size_t generation_ = 0;   // bumped per job so each worker joins it once
  std::exception_ptr error_;
  bool stop_ = false;
};

// a() and b() side by side on two threads of `pool`, or a() then b() on the caller when pool is
// null or has one thread. They must touch disjoint data (e.g. the actor's and the critic's passes
// of a PPO minibatch), so the results are the same either way. An exception of either is
// rethrown after both have finished.
void run_pair(ThreadPool* pool, const std::function<void()>& a, const std::function<void()>& b);

}  // namespace codesign::rl
