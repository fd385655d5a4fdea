#pragma once
// A fixed set of worker threads for the parallel loops of one simulation step (the DEM's integration and
// pair forces), kept alive between steps so that a step does not pay for thread creation. run(jobs, job)
// calls job(k) for k = 0..jobs−1 spread over the workers and the calling thread, and returns when every job
// is done. A job that throws does not stop the others: run() rethrows the first exception once all have
// finished. Which thread runs a job is not fixed: callers make each job's result independent of that (each
// job writes only its own outputs) and combine the jobs' outputs in job order.
//
// A step has several parallel phases of 0.1–1 ms, so starting one must cost far less than a futex wake-up:
// an idle worker spins on the job word for a bounded time (`spin_time`) before it blocks, a run publishes its
// jobs by one atomic store, and jobs are claimed by compare-and-swap on that word, which holds the run's
// generation with the count of jobs not yet claimed (a worker late for one run cannot claim a job of the
// next). The job is passed as a pointer to the caller's callable (no allocation per run). Blocking uses
// C++20 atomic wait/notify, and a notify is issued only when some thread sleeps.
//
// run_each(job) calls job(t) once on each thread t (the caller is thread 0, worker k thread k): loops that
// split the same arrays the same way phase after phase then find their part in the cache of the core that
// wrote it last. With claimed jobs the part would change hands at random, and every phase would pull it
// across from the other core.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace aggkit {

class WorkerPool {
 public:
  // How long an idle thread polls before it blocks: longer than the serial gaps between the phases of a
  // step, short beside a time slice (a loaded machine loses little to the polling).
  static constexpr std::chrono::microseconds spin_time{200};

  explicit WorkerPool(std::size_t threads);  // threads >= 1, the caller counted: threads − 1 workers
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::size_t threads() const { return workers_.size() + 1; }

  // job(k) for k < jobs, job callable as job(std::size_t). jobs < 2^31.
  template <class Job>
  void run(std::size_t jobs, Job&& job) {
    using Callable = std::remove_reference_t<Job>;
    if (workers_.empty() || jobs <= 1) {  // on the calling thread, with the same rule for exceptions
      std::exception_ptr error;
      for (std::size_t k = 0; k < jobs; ++k) {
        try {
          job(k);
        } catch (...) {
          if (!error) error = std::current_exception();
        }
      }
      if (error) std::rethrow_exception(error);
      return;
    }
    dispatch(jobs, [](void* context, std::size_t k) { (*static_cast<Callable*>(context))(k); },
             const_cast<void*>(static_cast<const void*>(&job)), false);
  }
  // job(t) for t < threads(), job t on thread t; exceptions as run().
  template <class Job>
  void run_each(Job&& job) {
    using Callable = std::remove_reference_t<Job>;
    if (workers_.empty()) return run(1, job);
    dispatch(threads(), [](void* context, std::size_t k) { (*static_cast<Callable*>(context))(k); },
             const_cast<void*>(static_cast<const void*>(&job)), true);
  }

 private:
  using Invoke = void (*)(void*, std::size_t);
  void dispatch(std::size_t jobs, Invoke invoke, void* context, bool pinned);
  void work(std::size_t index);
  // Runs job k of the current run (an exception is kept for the caller), counts it done and wakes a
  // sleeping caller at the last.
  void run_job(std::size_t k);
  // Claims and runs jobs of generation `generation` until none is left; returns how many it ran.
  std::size_t drain(std::uint32_t generation);

  std::vector<std::thread> workers_;
  // Each on its own cache line: the job word (polled by idle workers), the count of jobs done (polled by the
  // caller), and the wake-up words.
  struct alignas(64) Word64 { std::atomic<std::uint64_t> value{0}; };
  struct alignas(64) Word32 { std::atomic<std::uint32_t> value{0}; };
  // (generation << 32) | jobs not yet claimed, or | pinned_run for a run_each (nothing to claim): a worker
  // tells the kind of a run from the word it saw the run in, never from a field the next run may rewrite.
  static constexpr std::uint32_t pinned_run = 0x80000000u;
  Word64 ticket_;
  Word32 done_;        // jobs of the current run finished
  Word32 wake_;        // bumped by each run and at shutdown: what blocked workers wait on
  Word32 sleepers_;    // workers blocked (or about to block) on wake_
  Word32 caller_sleeps_;  // 1 while the caller blocks on done_
  // Written by the caller before it publishes a run (release) and read by workers after they claim (acquire).
  Invoke invoke_ = nullptr;
  void* context_ = nullptr;
  std::uint32_t jobs_ = 0, generation_ = 0;
  std::atomic<bool> stop_{false};
  std::mutex error_mutex_;  // taken only when a job throws
  std::exception_ptr error_;
};

}  // namespace aggkit
