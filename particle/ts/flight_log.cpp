#include "particle/ts/flight_log.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "particle/common/simd_clones.hpp"
#include "particle/ts/worker_ranges.hpp"

namespace aggkit {

namespace {

// The replay of logged flights for a block of `lanes` spheres, coordinates by axis: per flight f = Δt v and
// x ← x + f, wrapped on periodic boxes, exactly the arithmetic of an applied flight. Vectorised over the
// block; contraction into fused multiply-adds is off, so that every vector unit gives the bits of the
// applied flight's separate multiply and add.
constexpr std::size_t lanes = 32;
struct ReplayBlock {
  double x[3][lanes], v[3][lanes], f[3][lanes];
};
AGGKIT_SIMD_CLONES __attribute__((optimize("fp-contract=off"))) void replay_block(ReplayBlock& b, const double* dts,
                                                                                  std::size_t flights, int dimension,
                                                                                  const double* periodic_side) {
  for (std::size_t k = 0; k < flights; ++k) {
    const double dt = dts[k];
    for (int a = 0; a < dimension; ++a) {
      for (std::size_t m = 0; m < lanes; ++m) {
        b.f[a][m] = dt * b.v[a][m];
        b.x[a][m] = b.x[a][m] + b.f[a][m];
      }
      if (periodic_side) {  // Box::wrap, branch-free
        const double side = periodic_side[a];
        for (std::size_t m = 0; m < lanes; ++m) {
          const double r = b.x[a][m] - side * std::floor(b.x[a][m] / side);
          b.x[a][m] = r >= side ? 0.0 : r;
        }
      }
    }
  }
}

}  // namespace

FlightLog::FlightLog(const Box& box, double radius, std::span<const Vector3> positions)
    : x(positions.begin(), positions.end()),
      flown(positions.size(), Vector3{0, 0, 0}),
      box_(box),
      radius_(radius),
      applied_(positions.size(), 0),
      extent_low_(positions.size()),
      extent_high_(positions.size()),
      drift_(positions.size()) {}

void FlightLog::log(double dt, const std::vector<Vector3>& velocity, const ClusterMembership& members, WorkerPool* pool) {
  // Bounded log (memory, and the round-off the extents' margin covers).
  if (logged_.size() >= (std::size_t(1) << 20)) sync_all(velocity, members, pool);
  logged_.push_back(dt);
}

void FlightLog::replay(const std::uint32_t* ids, std::size_t count, std::size_t from, const std::vector<Vector3>& velocity,
                       const ClusterMembership& members) {
  // Blocks of `lanes` spheres side by side (replay_block): one sphere's flights are a chain of dependent
  // additions, a block's are independent chains on the vector unit.
  ReplayBlock b;
  const double* periodic_side = box_.boundary == Boundary::periodic ? box_.side.data() : nullptr;
  for (std::size_t first = 0; first < count; first += lanes) {
    const std::size_t held = std::min(lanes, count - first);
    for (std::size_t m = 0; m < lanes; ++m) {
      const std::uint32_t p = ids[first + std::min(m, held - 1)];  // the last sphere again as padding
      const Vector3& u = velocity[members.cluster_of(p)];
      for (int a = 0; a < 3; ++a) {
        b.x[a][m] = x[p][a];
        b.v[a][m] = u[a];
        b.f[a][m] = flown[p][a];
      }
    }
    replay_block(b, logged_.data() + from, logged_.size() - from, box_.dimension, periodic_side);
    for (std::size_t m = 0; m < held; ++m)
      for (int a = 0; a < box_.dimension; ++a) {
        x[ids[first + m]][a] = b.x[a][m];
        flown[ids[first + m]][a] = b.f[a][m];
      }
  }
}

void FlightLog::sync(std::uint32_t cluster, const std::vector<Vector3>& velocity, const ClusterMembership& members) {
  const std::size_t from = applied_[cluster];
  if (from == logged_.size()) return;
  if (from == 0) partial_.push_back(cluster);
  thread_local std::vector<std::uint32_t> ids;
  ids.clear();
  for (std::uint32_t p = members.first(cluster); p != ClusterMembership::none; p = members.next(p)) ids.push_back(p);
  replay(ids.data(), ids.size(), from, velocity, members);
  applied_[cluster] = std::uint32_t(logged_.size());
}

void FlightLog::sync_all(const std::vector<Vector3>& velocity, const ClusterMembership& members, WorkerPool* pool) {
  if (logged_.empty()) return;
  // The clusters brought up to date part of the way (at a wall) by their members, the rest by index.
  for (const std::uint32_t c : partial_) sync(c, velocity, members);
  for_ranges(pool, x.size(), [&](std::size_t from, std::size_t to, std::size_t) {
    constexpr std::size_t batch = 4 * lanes;
    std::uint32_t ids[batch];
    std::size_t held = 0;
    for (std::size_t p = from; p < to; ++p) {
      if (applied_[members.cluster_of(std::uint32_t(p))] != 0) continue;
      ids[held++] = std::uint32_t(p);
      if (held == batch) {
        replay(ids, held, 0, velocity, members);
        held = 0;
      }
    }
    if (held > 0) replay(ids, held, 0, velocity, members);
  });
  for (const std::uint32_t c : partial_) applied_[c] = 0;  // the only clusters sync() marked
  partial_.clear();
  logged_.clear();
}

void FlightLog::measure_extent(std::uint32_t cluster, const ClusterMembership& members) {
  const double inf = std::numeric_limits<double>::infinity();
  Vector3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (std::uint32_t p = members.first(cluster); p != ClusterMembership::none; p = members.next(p))
    for (int d = 0; d < box_.dimension; ++d) {
      lo[d] = std::min(lo[d], x[p][d] - radius_);
      hi[d] = std::max(hi[d], x[p][d] + radius_);
    }
  extent_low_[cluster] = lo;
  extent_high_[cluster] = hi;
  drift_[cluster] = {0, 0, 0};
}

std::vector<std::uint32_t> FlightLog::near_walls(double dt, const std::vector<Vector3>& velocity,
                                                 const ClusterMembership& members,
                                                 const std::vector<std::uint32_t>& live, WorkerPool* pool) {
  if (!extents_) {
    for_ranges(pool, live.size(), [&](std::size_t from, std::size_t to, std::size_t) {
      for (std::size_t k = from; k < to; ++k) measure_extent(live[k], members);
    });
    extents_ = true;
  }
  double side = 0;
  for (int d = 0; d < box_.dimension; ++d) side = std::max(side, box_.side[d]);
  // Far above the round-off of a position summed over up to 2^20 flights (2^20 · 2^-53 of the box).
  const double margin = 1e-9 * side;
  // Found on the workers, gathered in increasing order.
  std::vector<std::vector<std::uint32_t>> near(ts_threads(pool));
  for_ranges(pool, live.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
    std::vector<std::uint32_t> found;
    for (std::size_t k = from; k < to; ++k) {
      const std::uint32_t c = live[k];
      drift_[c] = drift_[c] + dt * velocity[c];
      bool close = false;
      for (int d = 0; d < box_.dimension; ++d)
        close = close || extent_low_[c][d] + drift_[c][d] < margin || extent_high_[c][d] + drift_[c][d] > box_.side[d] - margin;
      if (close) found.push_back(c);
    }
    near[w] = std::move(found);
  });
  for (std::size_t w = 1; w < near.size(); ++w) near[0].insert(near[0].end(), near[w].begin(), near[w].end());
  return std::move(near[0]);
}

void FlightLog::forget_log() {
  logged_.clear();
  partial_.clear();
  std::fill(applied_.begin(), applied_.end(), 0u);
  extents_ = false;
}

}  // namespace aggkit
