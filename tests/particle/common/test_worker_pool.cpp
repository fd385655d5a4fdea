// The worker pool (particle/common/worker_pool.hpp): every job of every run is called exactly once and the
// run returns only when all are done, whether the workers are polling (runs back to back) or blocked (runs
// spaced by more than the polling time), for 1–4 threads; a pool is destroyed with its workers blocked.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "particle/common/worker_pool.hpp"

using namespace aggkit;

namespace {

// Runs with 0..40 jobs, each job adding its index + 1 to its own slot; checks each slot after the run
// (a job run twice, never, or still running at the return shows as a wrong count).
void check_runs(WorkerPool& pool, std::size_t runs, std::chrono::microseconds gap) {
  std::vector<std::atomic<std::size_t>> hits(40);
  for (std::size_t r = 0; r < runs; ++r) {
    const std::size_t jobs = (r * 7) % 41;
    for (auto& h : hits) h.store(0);
    pool.run(jobs, [&](std::size_t k) {
      if (k % 5 == 0) std::this_thread::yield();  // uneven jobs
      hits[k].fetch_add(k + 1);
    });
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < hits.size(); ++k) wrong += hits[k].load() != (k < jobs ? k + 1 : 0) ? 1 : 0;
    REQUIRE(wrong == 0);
    if (gap.count() > 0) std::this_thread::sleep_for(gap);
  }
}

}  // namespace

TEST_CASE("worker pool: each job runs once, polling or blocked workers", "[common][worker_pool]") {
  for (std::size_t threads : {1u, 2u, 3u, 4u}) {
    WorkerPool pool(threads);
    CHECK(pool.threads() == threads);
    check_runs(pool, 1000, std::chrono::microseconds(0));  // back to back: the workers poll
    // Gaps of several polling times: the workers block between runs and are woken.
    check_runs(pool, 40, 5 * WorkerPool::spin_time);
  }
}

TEST_CASE("worker pool: jobs run on several threads and write their own outputs", "[common][worker_pool]") {
  WorkerPool pool(3);
  std::vector<double> out(1000);
  pool.run(out.size(), [&](std::size_t k) { out[k] = double(k) * 0.5; });
  std::vector<double> expected(1000);
  for (std::size_t k = 0; k < expected.size(); ++k) expected[k] = double(k) * 0.5;
  CHECK(out == expected);
  // Jobs that wait for each other finish only if at least two threads run them at once.
  std::atomic<int> arrived{0};
  pool.run(2, [&](std::size_t) {
    arrived.fetch_add(1);
    while (arrived.load() < 2) std::this_thread::yield();
  });
  CHECK(arrived.load() == 2);
}

TEST_CASE("worker pool: run_each runs job t on thread t, the caller's job 0, the same thread every run", "[common][worker_pool]") {
  for (std::size_t threads : {1u, 2u, 4u}) {
    WorkerPool pool(threads);
    std::vector<std::thread::id> first(threads), now(threads);
    for (int r = 0; r < 200; ++r) {
      std::vector<std::atomic<int>> ran(threads);
      for (auto& k : ran) k.store(0);
      pool.run_each([&](std::size_t t) {
        ran[t].fetch_add(1);
        now[t] = std::this_thread::get_id();
      });
      for (auto& k : ran) REQUIRE(k.load() == 1);
      if (r == 0) first = now;
      REQUIRE(now == first);
      if (r % 50 == 49) std::this_thread::sleep_for(3 * WorkerPool::spin_time);  // blocked workers too
    }
    CHECK(first[0] == std::this_thread::get_id());
    for (std::size_t a = 0; a < threads; ++a)
      for (std::size_t b = a + 1; b < threads; ++b) CHECK(first[a] != first[b]);
    // Mixed with claimed runs, and a throwing job rethrown after the others ran.
    check_runs(pool, 50, std::chrono::microseconds(0));
    std::vector<std::atomic<int>> ran(threads);
    for (auto& k : ran) k.store(0);
    CHECK_THROWS_WITH(pool.run_each([&](std::size_t t) {
                        ran[t].fetch_add(1);
                        if (t + 1 == threads) throw std::runtime_error("thread " + std::to_string(t));
                      }),
                      Catch::Contains("thread"));
    for (auto& k : ran) CHECK(k.load() == 1);
  }
}

TEST_CASE("worker pool: a worker late for a claimed run does not run the next run_each's job twice", "[common][worker_pool]") {
  // Claimed runs of two jobs, which the caller often finishes before a worker has looked, back to back with
  // run_each: a worker that saw the claimed run but read the kind of run after the next run was published
  // would run its run_each job once for each run (the kind is now read from the word the run was seen in).
  // ThreadSanitizer flags the old read at once; here a job run twice, or late, shows as a wrong count.
  for (std::size_t threads : {2u, 3u}) {
    WorkerPool pool(threads);
    std::vector<std::atomic<int>> each(threads);
    std::atomic<int> claimed{0};
    const int runs = 3000;
    for (int r = 0; r < runs; ++r) {
      pool.run(2, [&](std::size_t) { claimed.fetch_add(1); });
      for (auto& k : each) k.store(0);
      pool.run_each([&](std::size_t t) { each[t].fetch_add(1); });
      int wrong = 0;
      for (auto& k : each) wrong += k.load() != 1 ? 1 : 0;
      REQUIRE(wrong == 0);
    }
    CHECK(claimed.load() == 2 * runs);
  }
}

TEST_CASE("worker pool: a throwing job is rethrown after the others finished, and the pool stays usable", "[common][worker_pool]") {
  for (std::size_t threads : {1u, 3u}) {
    WorkerPool pool(threads);
    std::vector<std::atomic<int>> ran(20);
    for (auto& r : ran) r.store(0);
    CHECK_THROWS_WITH(pool.run(ran.size(),
                               [&](std::size_t k) {
                                 ran[k].fetch_add(1);
                                 if (k == 7 || k == 12) throw std::runtime_error("job " + std::to_string(k));
                               }),
                      Catch::Contains("job"));
    std::size_t once = 0;
    for (auto& r : ran) once += r.load() == 1 ? 1 : 0;
    CHECK(once == ran.size());  // every job ran (exactly once) before run() returned
    check_runs(pool, 100, std::chrono::microseconds(0));
  }
}

TEST_CASE("worker pool: destroyed with blocked workers", "[common][worker_pool]") {
  // A lost wake-up would leave the destructor waiting for ever on a worker: CTest's TIMEOUT on this test turns
  // that into a failure, and each destruction here must also end promptly (a wake-up found only by a
  // time-out would show as a slow one). 1 s: a join of 3 woken threads takes microseconds, and a loaded
  // machine's scheduling delay is tens of milliseconds.
  for (int k = 0; k < 5; ++k) {
    std::atomic<int> ran{0};
    auto pool = std::make_unique<WorkerPool>(4);
    pool->run(8, [&](std::size_t) { ran.fetch_add(1); });
    CHECK(ran.load() == 8);
    std::this_thread::sleep_for(3 * WorkerPool::spin_time);  // the workers stop polling and block
    const auto started = std::chrono::steady_clock::now();
    pool.reset();  // the destructor wakes and joins them
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    CHECK(seconds < 1.0);
  }
}
