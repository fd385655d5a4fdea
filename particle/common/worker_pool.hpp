#pragma once
// A fixed set of worker threads for the parallel loops of one simulation step (the DEM's integration and
// pair forces), kept alive between steps so that a step does not pay for thread creation. run(jobs, job)
// calls job(k) for k = 0..jobs−1 spread over the workers and the calling thread, and returns when every job
// is done. Which thread runs a job is not fixed: callers make each job's result independent of that (each
// job writes only its own outputs) and combine the jobs' outputs in job order.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace aggkit {

class WorkerPool {
 public:
  explicit WorkerPool(std::size_t threads);  // threads >= 1, the caller counted: threads − 1 workers
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::size_t threads() const { return workers_.size() + 1; }
  void run(std::size_t jobs, const std::function<void(std::size_t)>& job);

 private:
  void work();
  void drain();  // takes jobs until none is left

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, finished_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t jobs_ = 0, next_ = 0, done_ = 0;
  std::uint64_t generation_ = 0;
  bool stop_ = false;
};

}  // namespace aggkit
