// Contact detection of the time-stepping engine: the pairs of spheres of different clusters that overlap, or
// (swept) that met during the last flight [Degond2024, Sec. 3, step (b)], with the safe time of quiet flights.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "particle/ts/time_stepping_aggregation.hpp"
#include "particle/ts/time_stepping_neighbours.hpp"

namespace aggkit {

std::vector<std::pair<std::uint32_t, std::uint32_t>> TimeSteppingAggregation::overlaps_between_clusters(
    std::span<const std::uint32_t> among, bool swept, double* safe, std::vector<double>* nearest) const {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> found;
  if (safe) *safe = 0;
  if (nearest) nearest->clear();  // empty: not computed (the pass below fills it)
  const double contact2 = 4.0 * radius_ * radius_;
  const double same_cluster2 = contact2 * (1 - same_cluster_tolerance) * (1 - same_cluster_tolerance);
  // A swept pair touched during the flight if the segment of its separations, from d − w to d (w the
  // relative displacement), passes within 2R: d + s w' with w' = −w, s ∈ [0, 1], closest at s = d·w / |w|².
  const double reach = 2.0 * radius_ + (swept ? 2.0 * longest_flight_ : 0.0);
  // Different clusters at separation d (from i to j): overlapping now, or (swept) touched in the flight.
  // Farther apart than 2R plus the two longest flights (a margin for round-off): not touched, without the
  // swept test.
  const double apart = reach * (1.0 + 1e-9);
  const double apart2 = apart * apart;
  auto touched = [&](const Vector3& d, std::uint32_t i, std::uint32_t j) {
    double closest2 = dot(d, d);
    if (swept && closest2 >= contact2) {
      if (closest2 >= apart2) return false;
      const Vector3 w = flown_[j] - flown_[i];
      const double ww = dot(w, w);
      if (ww > 0) {
        const double s = std::clamp(dot(d, w) / ww, 0.0, 1.0);
        const Vector3 c = d - s * w;
        closest2 = dot(c, c);
      }
    }
    return closest2 < contact2;
  };
  auto scan_into = [&](std::uint32_t i, bool all, std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) {
    for_near(i, reach, [&](std::uint32_t j) {
      if (all && j < i) return;
      const Vector3 d = sep(i, j);
      // Different clusters: any overlap (or swept contact) links them. Within a cluster (only after a
      // minimisation, `among` given): an overlap deeper than the tolerance — a free sphere that moved onto
      // a sphere it was not constrained against — is minimised again with that pair as a link.
      const bool linked = members_.cluster_of(j) != members_.cluster_of(i) ? touched(d, i, j)
                                                                           : (!all && dot(d, d) < same_cluster2);
      if (linked) out.emplace_back(std::min(i, j), std::max(i, j));
    });
  };
  auto scan = [&](std::uint32_t i, bool all) { scan_into(i, all, found); };
  double narrowest = grid_.cell_side()[0];
  for (int d = 1; d < box_.dimension; ++d) narrowest = std::min(narrowest, grid_.cell_side()[d]);
  if (among.empty() && reach <= narrowest) {
    // Every pair once: each cell against itself and the half of its stencil ahead of it (a precomputed
    // table), over ranges of cells on `threads` workers; the sorted union does not depend on the split.
    const std::size_t cells = grid_.size(), width = half_stencil_.size();
    // Safe time (header, quiet flights): pairs in neighbouring cells by their gap and closing speed bound,
    // the others at least the narrowest cell side apart. A minimum: independent of the split.
    const bool bound = safe != nullptr && !speed_.empty();
    double fastest = 0;
    if (bound) {
      std::vector<double> top(thread_count(), 0.0);
      for_ranges(x_.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
        double most = 0;
        for (std::size_t c = from; c < to; ++c) most = std::max(most, speed_[c]);
        top[w] = most;
      });
      fastest = *std::max_element(top.begin(), top.end());
    }
    // Gaps less a margin far above the round-off the positions gather over the quiet flights.
    const double contact_margin = 2.0 * radius_ * (1.0 + 1e-6);
    const double far_gap = narrowest - contact_margin;
    const std::size_t workers = cells >= parallel_cells ? thread_count() : 1;
    // Nearest other-cluster distance per sphere (near re-check): a pair updates both spheres, which other
    // workers' cells may hold, so with several workers the minimum is taken atomically.
    double* close = nullptr;
    if (nearest) {
      nearest->assign(x_.size(), std::numeric_limits<double>::infinity());
      close = nearest->data();
    }
    auto closer = [&](std::uint32_t p, double distance) {
      if (workers <= 1) {
        close[p] = std::min(close[p], distance);
        return;
      }
      std::atomic_ref<double> slot(close[p]);
      double now = slot.load(std::memory_order_relaxed);
      while (distance < now && !slot.compare_exchange_weak(now, distance, std::memory_order_relaxed)) {
      }
    };
    auto pass = [&](std::size_t from, std::size_t to, std::vector<std::pair<std::uint32_t, std::uint32_t>>& out,
                    double& soonest) {
      for (std::size_t here = from; here < to; ++here) {
        if (cells_.first(here) == CellList::none) continue;
        for (std::size_t k = 0; k < width; ++k) {
          const std::uint32_t there = half_neighbours_[here * width + k];
          if (there == no_cell) continue;
          const CellCoords& o = half_stencil_[k];
          for (std::uint32_t i = cells_.first(here); i != CellList::none; i = cells_.next(i)) {
            const std::uint32_t ci = members_.cluster_of(i);
            for (std::uint32_t j = there == here ? cells_.next(i) : cells_.first(there); j != CellList::none; j = cells_.next(j)) {
              const std::uint32_t cj = members_.cluster_of(j);
              if (cj == ci) continue;
              const Vector3 d = grid_.stencil_image(x_[j] - x_[i], o);
              if (touched(d, i, j)) out.emplace_back(std::min(i, j), std::max(i, j));
              if (bound || close) {
                const double distance = std::sqrt(dot(d, d));
                if (close) {
                  closer(i, distance);
                  closer(j, distance);
                }
                if (bound) {
                  const double closing = speed_[ci] + speed_[cj];
                  const double gap = distance - contact_margin;
                  if (gap < soonest * closing) soonest = std::max(gap, 0.0) / closing;
                }
              }
            }
          }
        }
      }
    };
    const double inf = std::numeric_limits<double>::infinity();
    const double far = far_gap > 0 && fastest > 0 ? far_gap / (2.0 * fastest) : (far_gap > 0 ? inf : 0.0);
    std::vector<double> soonest(std::max<std::size_t>(workers, 1), far);
    if (workers <= 1) {
      pass(0, cells, found, soonest[0]);
    } else {
      std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> parts(workers);
      // Each worker fills locals (the slots of parts and soonest share cache lines) and stores them once.
      pool_->run_each([&](std::size_t w) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
        double soon = far;
        pass(cells * w / workers, cells * (w + 1) / workers, out, soon);
        parts[w] = std::move(out);
        soonest[w] = soon;
      });
      for (const auto& part : parts) found.insert(found.end(), part.begin(), part.end());
    }
    std::sort(found.begin(), found.end());
    if (bound) *safe = *std::min_element(soonest.begin(), soonest.end());
  } else if (among.empty()) {
    for (std::uint32_t i = 0; i < x_.size(); ++i) scan(i, true);
  } else {
    if (pool_ && among.size() >= parallel_scan) {
      // Chunks of the given spheres claimed by the workers (their neighbourhoods cost unevenly); the sorted
      // union does not depend on who scanned what.
      const std::size_t chunks = 8 * pool_->threads();
      std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> parts(chunks);
      pool_->run(chunks, [&](std::size_t k) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
        for (std::size_t a = among.size() * k / chunks; a < among.size() * (k + 1) / chunks; ++a) scan_into(among[a], false, out);
        parts[k] = std::move(out);
      });
      for (const auto& part : parts) found.insert(found.end(), part.begin(), part.end());
    } else {
      for (const std::uint32_t i : among) scan(i, false);
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
  }
  return found;
}

}  // namespace aggkit
