#include "particle/common/worker_pool.hpp"

namespace aggkit {

WorkerPool::WorkerPool(std::size_t threads) {
  for (std::size_t t = 1; t < threads; ++t) workers_.emplace_back([this] { work(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::drain() {
  std::unique_lock lock(mutex_);
  while (next_ < jobs_) {
    const std::size_t k = next_++;
    lock.unlock();
    (*job_)(k);
    lock.lock();
    if (++done_ == jobs_) finished_.notify_all();
  }
}

void WorkerPool::work() {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    drain();
  }
}

void WorkerPool::run(std::size_t jobs, const std::function<void(std::size_t)>& job) {
  if (workers_.empty() || jobs <= 1) {
    for (std::size_t k = 0; k < jobs; ++k) job(k);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    job_ = &job;
    jobs_ = jobs;
    next_ = done_ = 0;
    ++generation_;
  }
  start_.notify_all();
  drain();
  std::unique_lock lock(mutex_);
  finished_.wait(lock, [&] { return done_ == jobs_; });
  job_ = nullptr;
  jobs_ = 0;
}

}  // namespace aggkit
