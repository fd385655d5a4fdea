#pragma once
// The split of a loop of the time-stepping engine over its workers (particle/common/worker_pool.hpp).
#include <cstddef>

#include "particle/common/worker_pool.hpp"

namespace aggkit {

// Fewer cells or spheres than this: one worker (thread start-up dominates).
inline constexpr std::size_t ts_parallel_items = 16384;

inline std::size_t ts_threads(const WorkerPool* pool) { return pool ? pool->threads() : 1; }

// f(from, to, worker) over ranges of [0, n) on the pool's threads (one below ts_parallel_items items, or
// without a pool).
template <class F>
void for_ranges(WorkerPool* pool, std::size_t n, F&& f) {
  const std::size_t workers = n >= ts_parallel_items ? ts_threads(pool) : 1;
  if (workers <= 1) return f(std::size_t(0), n, std::size_t(0));
  // Range w on thread w, phase after phase: each range stays in one core's cache (worker_pool.hpp).
  pool->run_each([&](std::size_t w) { f(n * w / workers, n * (w + 1) / workers, w); });
}

}  // namespace aggkit
