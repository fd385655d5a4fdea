#include "particle/common/worker_pool.hpp"

namespace aggkit {

namespace {

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

std::uint32_t generation_of(std::uint64_t ticket) { return std::uint32_t(ticket >> 32); }

}  // namespace

WorkerPool::WorkerPool(std::size_t threads) {
  for (std::size_t t = 1; t < threads; ++t) workers_.emplace_back([this, t] { work(t); });
}

WorkerPool::~WorkerPool() {
  stop_.store(true);
  wake_.value.fetch_add(1);
  wake_.value.notify_all();
  for (std::thread& t : workers_) t.join();
}

std::size_t WorkerPool::drain(std::uint32_t generation) {
  std::size_t ran = 0;
  std::uint64_t t = ticket_.value.load(std::memory_order_acquire);
  while (generation_of(t) == generation && std::uint32_t(t) != 0 && (std::uint32_t(t) & pinned_run) == 0) {
    if (!ticket_.value.compare_exchange_weak(t, t - 1, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
    // Claimed: the run cannot finish before this job is done, so its fields stay put until then.
    run_job(jobs_ - std::uint32_t(t));
    ++ran;
    t = ticket_.value.load(std::memory_order_acquire);
  }
  return ran;
}

void WorkerPool::run_job(std::size_t k) {
  const std::uint32_t jobs = jobs_;  // read before this job counts as done: the caller may then start the next run
  try {
    invoke_(context_, k);
  } catch (...) {
    // Kept for the caller (the first one), which rethrows it once every job of the run is done.
    std::lock_guard lock(error_mutex_);
    if (!error_) error_ = std::current_exception();
  }
  if (done_.value.fetch_add(1) + 1 == jobs && caller_sleeps_.value.load()) done_.value.notify_all();
}

void WorkerPool::work(std::size_t index) {
  std::uint32_t seen = 0;
  for (;;) {
    std::uint64_t t = ticket_.value.load(std::memory_order_acquire);
    auto since = std::chrono::steady_clock::now();
    for (unsigned polls = 1; generation_of(t) == seen && !stop_.load(std::memory_order_relaxed); ++polls) {
      relax();
      t = ticket_.value.load(std::memory_order_acquire);
      if (polls % 64 != 0 || std::chrono::steady_clock::now() - since < spin_time) continue;
      // Block. The sleeper count is raised before the last look at the ticket and the caller bumps wake_
      // after publishing, then reads the count (all sequentially consistent): either this thread sees the
      // new run or the caller sees a sleeper and notifies.
      const std::uint32_t woken = wake_.value.load();
      sleepers_.value.fetch_add(1);
      t = ticket_.value.load();
      if (generation_of(t) == seen && !stop_.load()) wake_.value.wait(woken);
      sleepers_.value.fetch_sub(1);
      t = ticket_.value.load(std::memory_order_acquire);
      since = std::chrono::steady_clock::now();
    }
    if (stop_.load()) return;
    seen = generation_of(t);
    // The run cannot finish before this thread's job is done, so the fields stay put until then.
    if ((std::uint32_t(t) & pinned_run) != 0) {
      run_job(index);
      continue;
    }
    drain(seen);
  }
}

void WorkerPool::dispatch(std::size_t jobs, Invoke invoke, void* context, bool pinned) {
  invoke_ = invoke;
  context_ = context;
  jobs_ = std::uint32_t(jobs);
  done_.value.store(0, std::memory_order_relaxed);
  ++generation_;
  // Publishes the fields above; a pinned run leaves nothing to claim (each worker runs its own job).
  ticket_.value.store((std::uint64_t(generation_) << 32) | (pinned ? pinned_run : jobs_));
  wake_.value.fetch_add(1);
  if (sleepers_.value.load() > 0) wake_.value.notify_all();
  if (pinned) run_job(0);
  else drain(generation_);
  // Wait for the jobs the workers claimed: poll, then block (the same handshake as the workers' with
  // caller_sleeps_ in place of the sleeper count).
  const auto since = std::chrono::steady_clock::now();
  for (unsigned polls = 1; done_.value.load(std::memory_order_acquire) != jobs_; ++polls) {
    relax();
    if (polls % 64 != 0 || std::chrono::steady_clock::now() - since < spin_time) continue;
    caller_sleeps_.value.store(1);
    for (std::uint32_t d = done_.value.load(); d != jobs_; d = done_.value.load()) done_.value.wait(d);
    caller_sleeps_.value.store(0);
  }
  if (error_) {  // every job has finished: no worker touches error_ now
    std::exception_ptr error = std::move(error_);
    error_ = nullptr;
    std::rethrow_exception(error);
  }
}

}  // namespace aggkit
