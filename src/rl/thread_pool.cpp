#include "rl/thread_pool.hpp"

#include <algorithm>

namespace codesign::rl {

ThreadPool::ThreadPool(std::size_t n_threads) {
  if (n_threads == 0) n_threads = std::max(1u, std::thread::hardware_concurrency());
  workers_.reserve(n_threads - 1);
  for (std::size_t i = 1; i < n_threads; ++i) workers_.emplace_back([this] { worker_loop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

std::size_t ThreadPool::workers_for(std::size_t max_threads) const {
  return max_threads == 0 ? workers_.size() : std::min(workers_.size(), max_threads - 1);
}

// Claims indices one at a time until none are left; called with mutex_ NOT held. The caller's
// thread passes `recount` (workers pass null): after each call it may let more workers in.
void ThreadPool::run_chunk(const std::function<std::size_t()>* recount) {
  for (;;) {
    std::size_t i;
    {
      std::lock_guard lock(mutex_);
      if (next_index_ >= job_size_) return;
      i = next_index_++;
      if (job_order_) i = (*job_order_)[i];
    }
    try {
      (*job_)(i);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    if (recount && *recount) {
      std::size_t allowed = 0;
      try {
        allowed = workers_for((*recount)());
      } catch (...) {  // rethrown by run_job once the calls still running are done
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
        recount = nullptr;
        continue;
      }
      bool more = false;
      {
        std::lock_guard lock(mutex_);
        if (allowed > job_workers_) {
          job_workers_ = allowed;
          more = next_index_ < job_size_;
        }
      }
      if (more) wake_.notify_all();
    }
  }
}

void ThreadPool::worker_loop() {
  std::size_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      // A worker joins a job it has not joined yet while the job has indices left and room for it.
      wake_.wait(lock, [&] {
        return stop_ || (job_ != nullptr && generation_ != seen && busy_ < job_workers_ && next_index_ < job_size_);
      });
      if (stop_) return;
      seen = generation_;
      ++busy_;
    }
    run_chunk(nullptr);
    {
      std::lock_guard lock(mutex_);
      --busy_;
    }
    done_.notify_all();
  }
}

void ThreadPool::parallel_for(std::size_t n, const std::function<void(std::size_t)>& fn) {
  run_job(n, nullptr, fn, 0, nullptr);
}

void ThreadPool::parallel_for_ordered(const std::vector<std::size_t>& order,
                                      const std::function<void(std::size_t)>& fn, std::size_t max_threads,
                                      const std::function<std::size_t()>& recount) {
  run_job(order.size(), &order, fn, max_threads, recount ? &recount : nullptr);
}

void ThreadPool::run_job(std::size_t n, const std::vector<std::size_t>* order,
                         const std::function<void(std::size_t)>& fn, std::size_t max_threads,
                         const std::function<std::size_t()>* recount) {
  if (n == 0) return;
  if (workers_.empty() || n == 1 || (max_threads == 1 && !recount)) {
    for (std::size_t i = 0; i < n; ++i) fn(order ? (*order)[i] : i);
    return;
  }
  std::size_t workers = 0;
  {
    std::lock_guard lock(mutex_);
    job_ = &fn;
    job_order_ = order;
    job_size_ = n;
    next_index_ = 0;
    job_workers_ = workers = workers_for(max_threads);
    error_ = nullptr;
    ++generation_;
  }
  if (workers > 0) wake_.notify_all();
  run_chunk(recount);
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    // All indices are claimed once run_chunk returns; wait for the calls still running.
    done_.wait(lock, [&] { return busy_ == 0; });
    job_ = nullptr;
    job_order_ = nullptr;
    job_size_ = 0;
    error = error_;
    error_ = nullptr;
  }
  if (error) std::rethrow_exception(error);
}

void run_pair(ThreadPool* pool, const std::function<void()>& a, const std::function<void()>& b) {
  if (pool == nullptr || pool->size() < 2) {
    a();
    b();
    return;
  }
  pool->parallel_for(2, [&](std::size_t i) { i == 0 ? a() : b(); });
}

}  // namespace codesign::rl
