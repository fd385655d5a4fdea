// Contact detection of the time-stepping engine: the pairs of spheres of different clusters that overlap, or
// (swept) that met during the last flight [Degond2024, Sec. 3, step (b)], with the per-sphere safe times of
// local detection and quiet flights (time_stepping_aggregation.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "particle/ts/time_stepping_aggregation.hpp"
#include "particle/ts/time_stepping_neighbours.hpp"

namespace aggkit {

namespace {

// Different clusters at separation d (from i to j): overlapping now, or (swept) touched in the last flight.
// A swept pair touched if the segment of its separations, from d − w to d (w the relative displacement),
// passes within 2R: d + s w' with w' = −w, s ∈ [0, 1], closest at s = d·w / |w|². Farther apart than 2R plus
// the two longest flights (a margin for round-off): not touched, without the swept test. Symmetric to the
// bit in (d, i, j) ↔ (−d, j, i), so a pair examined from either sphere gives the same answer.
struct Contact {
  const std::vector<Vector3>& flown;
  double contact2, apart2;
  bool swept;
  bool operator()(const Vector3& d, std::uint32_t i, std::uint32_t j) const {
    double closest2 = dot(d, d);
    if (swept && closest2 >= contact2) {
      if (closest2 >= apart2) return false;
      const Vector3 w = flown[j] - flown[i];
      const double ww = dot(w, w);
      if (ww > 0) {
        const double s = std::clamp(dot(d, w) / ww, 0.0, 1.0);
        const Vector3 c = d - s * w;
        closest2 = dot(c, c);
      }
    }
    return closest2 < contact2;
  }
};

// The time a pair at `distance` needs to close its gap (less the margin) at `closing` speed.
double closing_time(double distance, double margin, double closing) {
  const double gap = distance - margin;
  if (closing > 0) return std::max(gap, 0.0) / closing;
  return gap > 0 ? std::numeric_limits<double>::infinity() : 0.0;
}

// The safe time of a sphere against the spheres it did not examine (at least `far_gap` + the margin away)
// and `rate` = its speed plus the largest.
double far_time(double far_gap, double rate) {
  if (!(far_gap > 0)) return 0.0;
  return rate > 0 ? far_gap / rate : std::numeric_limits<double>::infinity();
}

// The contact test after a flight whose longest sphere displacement is `longest` (swept), or of overlaps
// now: pairs farther apart than 2R plus twice that (and a margin for round-off) skip the swept test.
Contact contact_test(const std::vector<Vector3>& flown, double radius, double longest, bool swept) {
  const double apart = (2.0 * radius + (swept ? 2.0 * longest : 0.0)) * (1.0 + 1e-9);
  return {flown, 4.0 * radius * radius, apart * apart, swept};
}

}  // namespace

double TimeSteppingAggregation::fastest() const {
  double most = 0;
  for (const std::uint32_t c : live()) most = std::max(most, speed_[c]);
  return most;
}

double TimeSteppingAggregation::narrowest() const {
  double side = grid_.cell_side()[0];
  for (int d = 1; d < box_.dimension; ++d) side = std::min(side, grid_.cell_side()[d]);
  return side;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> TimeSteppingAggregation::overlaps_between_clusters(
    std::span<const std::uint32_t> among, bool swept, bool* bounds) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> found;
  if (bounds) *bounds = false;
  const Contact touched = contact_test(flown_, radius_, longest_flight_, swept);
  const double same_cluster2 = touched.contact2 * (1 - same_cluster_tolerance) * (1 - same_cluster_tolerance);
  const double reach = 2.0 * radius_ + (swept ? 2.0 * longest_flight_ : 0.0);
  const double side = narrowest();
  auto scan_into = [&](std::uint32_t i, bool all, std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) {
    auto pair = [&](std::uint32_t j, const Vector3& d) {
      if (all && j < i) return;
      // Different clusters: any overlap (or swept contact) links them. Within a cluster (only after a
      // minimisation, `among` given): an overlap deeper than the tolerance — a free sphere that moved onto
      // a sphere it was not constrained against — is minimised again with that pair as a link.
      const bool linked = members_.cluster_of(j) != members_.cluster_of(i) ? touched(d, i, j)
                                                                           : (!all && dot(d, d) < same_cluster2);
      if (linked) out.emplace_back(std::min(i, j), std::max(i, j));
    };
    if (reach <= side) return for_stencil(i, pair);  // the cell list is up to date for the given spheres
    for_near(i, reach, [&](std::uint32_t j) { pair(j, sep(i, j)); });
  };
  auto scan = [&](std::uint32_t i, bool all) { scan_into(i, all, found); };
  if (among.empty() && reach <= side) {
    // Every pair once: each cell against itself and the half of its stencil ahead of it (a precomputed
    // table), over ranges of cells on `threads` workers; the sorted union does not depend on the split.
    const std::size_t cells = grid_.size(), width = half_width_, row = stencil_.size();
    // Local detection's state (header): per sphere, its safe time (pairs in neighbouring cells by their gap
    // and closing speed, the others at least the narrowest cell side apart) and its nearest other-cluster
    // distance, both minima over its pairs. A pair updates both spheres: a range of cells writes the spheres
    // of its own cells directly and keeps those of other ranges' cells (the stencil's cells past its end) in
    // a list applied after the pass, so no two workers write one sphere and the minima do not depend on the
    // split.
    const bool bound = bounds != nullptr && !speed_.empty();
    const double most = bound ? fastest() : 0.0;
    const double margin = contact_margin(), far_gap = side - margin;
    const std::size_t workers = cells >= parallel_cells ? thread_count() : 1;
    double* soon = expires_.data();   // the safe time until the pass ends, then the clock it holds until
    double* close = near_key_.data();  // the nearest distance until the pass ends
    if (bound)
      for_ranges(x_.size(), [&](std::size_t from, std::size_t to, std::size_t) {
        const double inf = std::numeric_limits<double>::infinity();
        for (std::size_t p = from; p < to; ++p) {
          rate_[p] = speed_[members_.cluster_of(std::uint32_t(p))] + most;
          soon[p] = far_time(far_gap, rate_[p]);
          close[p] = inf;
        }
      });
    struct Spill {
      std::uint32_t sphere;
      double distance, time;
    };
    auto pass = [&](std::size_t from, std::size_t to, std::vector<std::pair<std::uint32_t, std::uint32_t>>& out,
                    std::vector<Spill>& spill) {
      for (std::size_t here = from; here < to; ++here) {
        if (cells_.first(here) == CellList::none) continue;
        for (std::size_t k = 0; k < width; ++k) {
          const std::uint32_t there = neighbours_[here * row + k];
          if (there == no_cell) continue;
          const bool own = there >= from && there < to;
          const CellCoords& o = stencil_[k];
          for (std::uint32_t i = cells_.first(here); i != CellList::none; i = cells_.next(i)) {
            const std::uint32_t ci = members_.cluster_of(i);
            for (std::uint32_t j = there == here ? cells_.next(i) : cells_.first(there); j != CellList::none; j = cells_.next(j)) {
              const std::uint32_t cj = members_.cluster_of(j);
              if (cj == ci) continue;
              const Vector3 d = grid_.stencil_image(x_[j] - x_[i], o);
              if (touched(d, i, j)) out.emplace_back(std::min(i, j), std::max(i, j));
              if (!bound) continue;
              const double distance = std::sqrt(dot(d, d));
              const double time = closing_time(distance, margin, speed_[ci] + speed_[cj]);
              close[i] = std::min(close[i], distance);
              soon[i] = std::min(soon[i], time);
              if (own) {
                close[j] = std::min(close[j], distance);
                soon[j] = std::min(soon[j], time);
              } else {
                spill.push_back({j, distance, time});
              }
            }
          }
        }
      }
    };
    // Ranges of cells claimed by the workers (their spheres and pairs cost unevenly).
    const std::size_t chunks = workers <= 1 ? 1 : 4 * workers;
    std::vector<std::vector<Spill>> spills(chunks);
    if (workers <= 1) {
      pass(0, cells, found, spills[0]);
    } else {
      std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> parts(chunks);
      // Each chunk fills locals (the slots of parts share cache lines) and stores them once.
      pool_->run(chunks, [&](std::size_t k) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
        std::vector<Spill> spill;
        pass(cells * k / chunks, cells * (k + 1) / chunks, out, spill);
        parts[k] = std::move(out);
        spills[k] = std::move(spill);
      });
      for (const auto& part : parts) found.insert(found.end(), part.begin(), part.end());
    }
    std::sort(found.begin(), found.end());
    if (bound) {
      for (const auto& spill : spills)
        for (const Spill& s : spill) {
          close[s.sphere] = std::min(close[s.sphere], s.distance);
          soon[s.sphere] = std::min(soon[s.sphere], s.time);
        }
      for_ranges(x_.size(), [&](std::size_t from, std::size_t to, std::size_t) {
        for (std::size_t p = from; p < to; ++p) {
          soon[p] = clock_ + soon[p] * (1.0 - 1e-9);
          close[p] = std::min(close[p], side) + rate_[p] * clock_;
          checked_pass_[p] = passes_;
        }
      });
      *bounds = true;
    }
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

std::vector<std::pair<std::uint32_t, std::uint32_t>> TimeSteppingAggregation::examine(std::span<const std::uint32_t> spheres,
                                                                                      double most) {
  const Contact touched = contact_test(flown_, radius_, longest_flight_, true);
  const double side = narrowest(), margin = contact_margin(), far_gap = side - margin;
  // A neighbour not examined itself gets the distance as a bound (near_key_), applied after the pass.
  using Near = std::pair<std::uint32_t, double>;
  auto one = [&](std::uint32_t i, std::vector<std::pair<std::uint32_t, std::uint32_t>>& out, std::vector<Near>& near) {
    const std::uint32_t ci = members_.cluster_of(i);
    const double rate = speed_[ci] + most;
    double soon = far_time(far_gap, rate), close = std::numeric_limits<double>::infinity();
    // The image of each pair is the half-stencil pass's, mirrored: the same answers from either sphere.
    for_stencil(i, [&](std::uint32_t j, const Vector3& d) {
      const std::uint32_t cj = members_.cluster_of(j);
      if (cj == ci) return;
      if (touched(d, i, j)) out.emplace_back(std::min(i, j), std::max(i, j));
      const double distance = std::sqrt(dot(d, d));
      close = std::min(close, distance);
      soon = std::min(soon, closing_time(distance, margin, speed_[ci] + speed_[cj]));
      if (!stale_[j]) near.emplace_back(j, distance);
    });
    rate_[i] = rate;
    expires_[i] = clock_ + soon * (1.0 - 1e-9);
    near_key_[i] = std::min(close, side) + rate * clock_;
    checked_pass_[i] = passes_;
  };
  std::vector<std::pair<std::uint32_t, std::uint32_t>> found;
  std::vector<Near> near;
  if (pool_ && spheres.size() >= parallel_scan) {
    // Chunks claimed by the workers; each writes the state of its own spheres only.
    const std::size_t chunks = 8 * pool_->threads();
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> parts(chunks);
    std::vector<std::vector<Near>> nears(chunks);
    pool_->run(chunks, [&](std::size_t k) {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
      std::vector<Near> seen;
      for (std::size_t a = spheres.size() * k / chunks; a < spheres.size() * (k + 1) / chunks; ++a) one(spheres[a], out, seen);
      parts[k] = std::move(out);
      nears[k] = std::move(seen);
    });
    for (const auto& part : parts) found.insert(found.end(), part.begin(), part.end());
    for (const auto& seen : nears) near.insert(near.end(), seen.begin(), seen.end());
  } else {
    for (const std::uint32_t i : spheres) one(i, found, near);
  }
  for (const auto& [j, distance] : near) near_key_[j] = std::min(near_key_[j], distance + rate_[j] * clock_);
  // A pair of two examined spheres is found from both.
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  return found;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> TimeSteppingAggregation::detect(double& safe) {
  ++passes_;
  safe = 0;
  const std::size_t n = x_.size();
  if (settings_.local_detection && bounds_ && !jumped_ && 2.0 * radius_ + 2.0 * longest_flight_ <= narrowest()) {
    // The spheres whose safe time ran out in the flight, or whose cluster changed since their examination;
    // and the earliest end among the others.
    const std::size_t workers = thread_count();
    std::vector<std::vector<std::uint32_t>> due(workers);
    std::vector<double> earliest(workers, std::numeric_limits<double>::infinity());
    for_ranges(n, [&](std::size_t from, std::size_t to, std::size_t w) {
      std::vector<std::uint32_t> list;
      double first = std::numeric_limits<double>::infinity();
      for (std::size_t p = from; p < to; ++p) {
        if (expires_[p] <= clock_ || checked_pass_[p] <= changed_[members_.cluster_of(std::uint32_t(p))]) {
          list.push_back(std::uint32_t(p));
        } else {
          first = std::min(first, expires_[p]);
        }
      }
      due[w] = std::move(list);
      earliest[w] = first;
    });
    std::size_t count = 0;
    for (const auto& list : due) count += list.size();
    if (double(count) <= local_share * double(n)) {
      std::vector<std::uint32_t> spheres;
      spheres.reserve(count);
      for (const auto& list : due) spheres.insert(spheres.end(), list.begin(), list.end());
      for (const std::uint32_t p : spheres) stale_[p] = 1;
      auto found = examine(spheres, fastest());
      double first = *std::min_element(earliest.begin(), earliest.end());
      for (const std::uint32_t p : spheres) {
        stale_[p] = 0;
        first = std::min(first, expires_[p]);
      }
      safe = first - clock_;
      ++counters_.local_passes;
      counters_.examined_spheres += spheres.size();
      return found;
    }
  }
  auto found = overlaps_between_clusters({}, true, &bounds_);
  counters_.examined_spheres += n;
  if (bounds_) {
    std::vector<double> first(thread_count(), std::numeric_limits<double>::infinity());
    for_ranges(n, [&](std::size_t from, std::size_t to, std::size_t w) {
      double soonest = std::numeric_limits<double>::infinity();
      for (std::size_t p = from; p < to; ++p) soonest = std::min(soonest, expires_[p]);
      first[w] = soonest;
    });
    safe = *std::min_element(first.begin(), first.end()) - clock_;
  }
  return found;
}

}  // namespace aggkit
