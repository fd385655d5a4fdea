// Contact detection of the time-stepping engine: the pairs of spheres of different clusters that overlap, or
// (swept) that met during the last flight [Degond2024, Sec. 3, step (b)], with the per-sphere safe times of
// local detection and quiet flights (time_stepping_aggregation.hpp).
#include "particle/ts/contact_detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "particle/common/checkpoint.hpp"
#include "particle/ts/time_stepping_aggregation.hpp"
#include "particle/ts/time_stepping_neighbours.hpp"
#include "particle/ts/worker_ranges.hpp"

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
Contact contact_test(const SphereView& s, bool swept) {
  const double apart = (2.0 * s.radius + (swept ? 2.0 * s.longest_flight : 0.0)) * (1.0 + 1e-9);
  return {s.flown, 4.0 * s.radius * s.radius, apart * apart, swept};
}

// The sorted union of per-worker lists.
void gather(SpherePairs& found, const std::vector<SpherePairs>& parts) {
  for (const auto& part : parts) found.insert(found.end(), part.begin(), part.end());
}

void sort_unique(SpherePairs& found) {
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
}

}  // namespace

// A bound of a sphere found by a range of cells that does not hold it, applied after the pass.
struct ContactDetection::Spill {
  std::uint32_t sphere;
  double distance, time;
};

ContactDetection::ContactDetection(const CellGrid& grid, std::size_t spheres)
    : expires_(spheres, 0.0),
      near_key_(spheres, 0.0),
      rate_(spheres, 0.0),
      checked_pass_(spheres, 0),
      changed_(spheres, 0),
      stale_(spheres, 0) {
  for (const CellCoords& o : grid.stencil())
    if (o[2] > 0 || (o[2] == 0 && (o[1] > 0 || (o[1] == 0 && o[0] >= 0)))) stencil_.push_back(o);
  half_width_ = stencil_.size();
  for (std::size_t k = 1; k < half_width_; ++k) stencil_.push_back({-stencil_[k][0], -stencil_[k][1], -stencil_[k][2]});
  neighbours_.assign(grid.size() * stencil_.size(), no_cell);
  for (std::size_t cell = 0; cell < grid.size(); ++cell)
    for (std::size_t k = 0; k < stencil_.size(); ++k)
      if (const auto n = grid.neighbour(grid.coords(cell), stencil_[k]))
        neighbours_[cell * stencil_.size() + k] = std::uint32_t(grid.index(*n));
}

// f(j, d) for every j != i in the 3^d cells around i's cell in the cell list, d = x_j − x_i as the image the
// stencil's offset stands for (the same bits from either sphere of a pair).
template <class F>
void ContactDetection::for_stencil(const SphereView& s, std::uint32_t i, F&& f) const {
  const std::uint32_t* row = &neighbours_[s.cells.cell_of(i) * stencil_.size()];
  for (std::size_t k = 0; k < stencil_.size(); ++k)
    if (row[k] != no_cell)
      for (std::uint32_t j = s.cells.first(row[k]); j != CellList::none; j = s.cells.next(j))
        if (j != i) f(j, s.grid.stencil_image(s.x[j] - s.x[i], stencil_[k]));
}

double ContactDetection::narrowest(const SphereView& s) const {
  double side = s.grid.cell_side()[0];
  for (int d = 1; d < s.box.dimension; ++d) side = std::min(side, s.grid.cell_side()[d]);
  return side;
}

SpherePairs ContactDetection::overlaps(const SphereView& s, std::span<const std::uint32_t> among) {
  // The cell list is up to date for the given spheres: every pair once from the half stencil.
  if (among.empty() && 2.0 * s.radius <= narrowest(s)) return half_stencil_pass(s, false, false, 0.0);
  return search(s, among, false);
}

SpherePairs ContactDetection::search(const SphereView& s, std::span<const std::uint32_t> among, bool swept) const {
  const Contact touched = contact_test(s, swept);
  const double same_cluster2 = touched.contact2 * (1 - same_cluster_tolerance) * (1 - same_cluster_tolerance);
  const double reach = 2.0 * s.radius + (swept ? 2.0 * s.longest_flight : 0.0);
  const bool stencil = reach <= narrowest(s);
  auto scan_into = [&](std::uint32_t i, bool all, SpherePairs& out) {
    auto pair = [&](std::uint32_t j, const Vector3& d) {
      if (all && j < i) return;
      // Different clusters: any overlap (or swept contact) links them. Within a cluster (only after a
      // minimisation, `among` given): an overlap deeper than the tolerance — a free sphere that moved onto
      // a sphere it was not constrained against — is minimised again with that pair as a link.
      const bool linked = s.members.cluster_of(j) != s.members.cluster_of(i) ? touched(d, i, j)
                                                                             : (!all && dot(d, d) < same_cluster2);
      if (linked) out.emplace_back(std::min(i, j), std::max(i, j));
    };
    if (stencil) return for_stencil(s, i, pair);
    for_near(s.grid, s.cells, s.x, i, reach, [&](std::uint32_t j) { pair(j, s.box.minimum_image(s.x[j] - s.x[i])); });
  };
  SpherePairs found;
  if (among.empty()) {
    for (std::uint32_t i = 0; i < s.x.size(); ++i) scan_into(i, true, found);
    return found;  // each pair once, from its lower sphere
  }
  if (s.pool && among.size() >= parallel_scan) {
    // Chunks of the given spheres claimed by the workers (their neighbourhoods cost unevenly); the sorted
    // union does not depend on who scanned what.
    const std::size_t chunks = 8 * s.pool->threads();
    std::vector<SpherePairs> parts(chunks);
    s.pool->run(chunks, [&](std::size_t k) {
      SpherePairs out;
      for (std::size_t a = among.size() * k / chunks; a < among.size() * (k + 1) / chunks; ++a) scan_into(among[a], false, out);
      parts[k] = std::move(out);
    });
    gather(found, parts);
  } else {
    for (const std::uint32_t i : among) scan_into(i, false, found);
  }
  sort_unique(found);
  return found;
}

void ContactDetection::start_bounds(const SphereView& s, double fastest) {
  const double far_gap = narrowest(s) - contact_margin(s.radius);
  for_ranges(s.pool, s.x.size(), [&](std::size_t from, std::size_t to, std::size_t) {
    const double inf = std::numeric_limits<double>::infinity();
    for (std::size_t p = from; p < to; ++p) {
      rate_[p] = s.speed[s.members.cluster_of(std::uint32_t(p))] + fastest;
      expires_[p] = far_time(far_gap, rate_[p]);  // the safe time until the pass ends
      near_key_[p] = inf;                         // the nearest distance until the pass ends
    }
  });
}

void ContactDetection::pass_cells(const SphereView& s, std::size_t from, std::size_t to, bool swept, bool bound,
                                  SpherePairs& out, std::vector<Spill>& spill) {
  const Contact touched = contact_test(s, swept);
  const double margin = contact_margin(s.radius);
  const std::size_t width = half_width_, row = stencil_.size();
  double* soon = expires_.data();
  double* close = near_key_.data();
  for (std::size_t here = from; here < to; ++here) {
    if (s.cells.first(here) == CellList::none) continue;
    for (std::size_t k = 0; k < width; ++k) {
      const std::uint32_t there = neighbours_[here * row + k];
      if (there == no_cell) continue;
      const bool own = there >= from && there < to;
      const CellCoords& o = stencil_[k];
      for (std::uint32_t i = s.cells.first(here); i != CellList::none; i = s.cells.next(i)) {
        const std::uint32_t ci = s.members.cluster_of(i);
        for (std::uint32_t j = there == here ? s.cells.next(i) : s.cells.first(there); j != CellList::none; j = s.cells.next(j)) {
          const std::uint32_t cj = s.members.cluster_of(j);
          if (cj == ci) continue;
          const Vector3 d = s.grid.stencil_image(s.x[j] - s.x[i], o);
          if (touched(d, i, j)) out.emplace_back(std::min(i, j), std::max(i, j));
          if (!bound) continue;
          const double distance = std::sqrt(dot(d, d));
          const double time = closing_time(distance, margin, s.speed[ci] + s.speed[cj]);
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
}

void ContactDetection::finish_bounds(const SphereView& s, const std::vector<std::vector<Spill>>& spills) {
  for (const auto& spill : spills)
    for (const Spill& sp : spill) {
      near_key_[sp.sphere] = std::min(near_key_[sp.sphere], sp.distance);
      expires_[sp.sphere] = std::min(expires_[sp.sphere], sp.time);
    }
  const double side = narrowest(s);
  for_ranges(s.pool, s.x.size(), [&](std::size_t from, std::size_t to, std::size_t) {
    for (std::size_t p = from; p < to; ++p) {
      expires_[p] = clock_ + expires_[p] * (1.0 - 1e-9);  // the clock the safe time holds until
      near_key_[p] = std::min(near_key_[p], side) + rate_[p] * clock_;
      checked_pass_[p] = passes_;
    }
  });
}

SpherePairs ContactDetection::half_stencil_pass(const SphereView& s, bool swept, bool bound, double fastest) {
  // Every pair once: each cell against itself and the half of its stencil ahead of it (a precomputed table),
  // over ranges of cells on the workers; the sorted union does not depend on the split. Local detection's
  // state (header): per sphere, its safe time (pairs in neighbouring cells by their gap and closing speed,
  // the others at least the narrowest cell side apart) and its nearest other-cluster distance, both minima
  // over its pairs. A pair updates both spheres: a range of cells writes the spheres of its own cells
  // directly and keeps those of other ranges' cells (the stencil's cells past its end) in a list applied
  // after the pass, so no two workers write one sphere and the minima do not depend on the split.
  const std::size_t cells = s.grid.size();
  const std::size_t workers = cells >= ts_parallel_items ? ts_threads(s.pool) : 1;
  if (bound) start_bounds(s, fastest);
  // Ranges of cells claimed by the workers (their spheres and pairs cost unevenly).
  const std::size_t chunks = workers <= 1 ? 1 : 4 * workers;
  std::vector<std::vector<Spill>> spills(chunks);
  SpherePairs found;
  if (workers <= 1) {
    pass_cells(s, 0, cells, swept, bound, found, spills[0]);
  } else {
    std::vector<SpherePairs> parts(chunks);
    // Each chunk fills locals (the slots of parts share cache lines) and stores them once.
    s.pool->run(chunks, [&](std::size_t k) {
      SpherePairs out;
      std::vector<Spill> spill;
      pass_cells(s, cells * k / chunks, cells * (k + 1) / chunks, swept, bound, out, spill);
      parts[k] = std::move(out);
      spills[k] = std::move(spill);
    });
    gather(found, parts);
  }
  std::sort(found.begin(), found.end());
  if (bound) finish_bounds(s, spills);
  return found;
}

SpherePairs ContactDetection::examine(const SphereView& s, std::span<const std::uint32_t> spheres, double most) {
  const Contact touched = contact_test(s, true);
  const double side = narrowest(s), margin = contact_margin(s.radius), far_gap = side - margin;
  // A neighbour not examined itself gets the distance as a bound (near_key_), applied after the pass.
  using Near = std::pair<std::uint32_t, double>;
  auto one = [&](std::uint32_t i, SpherePairs& out, std::vector<Near>& near) {
    const std::uint32_t ci = s.members.cluster_of(i);
    const double rate = s.speed[ci] + most;
    double soon = far_time(far_gap, rate), close = std::numeric_limits<double>::infinity();
    // The image of each pair is the half-stencil pass's, mirrored: the same answers from either sphere.
    for_stencil(s, i, [&](std::uint32_t j, const Vector3& d) {
      const std::uint32_t cj = s.members.cluster_of(j);
      if (cj == ci) return;
      if (touched(d, i, j)) out.emplace_back(std::min(i, j), std::max(i, j));
      const double distance = std::sqrt(dot(d, d));
      close = std::min(close, distance);
      soon = std::min(soon, closing_time(distance, margin, s.speed[ci] + s.speed[cj]));
      if (!stale_[j]) near.emplace_back(j, distance);
    });
    rate_[i] = rate;
    expires_[i] = clock_ + soon * (1.0 - 1e-9);
    near_key_[i] = std::min(close, side) + rate * clock_;
    checked_pass_[i] = passes_;
  };
  SpherePairs found;
  std::vector<Near> near;
  if (s.pool && spheres.size() >= parallel_scan) {
    // Chunks claimed by the workers; each writes the state of its own spheres only.
    const std::size_t chunks = 8 * s.pool->threads();
    std::vector<SpherePairs> parts(chunks);
    std::vector<std::vector<Near>> nears(chunks);
    s.pool->run(chunks, [&](std::size_t k) {
      SpherePairs out;
      std::vector<Near> seen;
      for (std::size_t a = spheres.size() * k / chunks; a < spheres.size() * (k + 1) / chunks; ++a) one(spheres[a], out, seen);
      parts[k] = std::move(out);
      nears[k] = std::move(seen);
    });
    gather(found, parts);
    for (const auto& seen : nears) near.insert(near.end(), seen.begin(), seen.end());
  } else {
    for (const std::uint32_t i : spheres) one(i, found, near);
  }
  for (const auto& [j, distance] : near) near_key_[j] = std::min(near_key_[j], distance + rate_[j] * clock_);
  sort_unique(found);  // a pair of two examined spheres is found from both
  return found;
}

std::vector<std::uint32_t> ContactDetection::expired(const SphereView& s, double& earliest) const {
  const std::size_t workers = ts_threads(s.pool);
  std::vector<std::vector<std::uint32_t>> due(workers);
  std::vector<double> first(workers, std::numeric_limits<double>::infinity());
  for_ranges(s.pool, s.x.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
    std::vector<std::uint32_t> list;
    double soonest = std::numeric_limits<double>::infinity();
    for (std::size_t p = from; p < to; ++p) {
      if (expires_[p] <= clock_ || checked_pass_[p] <= changed_[s.members.cluster_of(std::uint32_t(p))]) {
        list.push_back(std::uint32_t(p));
      } else {
        soonest = std::min(soonest, expires_[p]);
      }
    }
    due[w] = std::move(list);
    first[w] = soonest;
  });
  earliest = *std::min_element(first.begin(), first.end());
  std::vector<std::uint32_t> spheres;
  for (std::size_t w = 0; w < workers; ++w) {
    if (w == 0) spheres = std::move(due[0]);
    else spheres.insert(spheres.end(), due[w].begin(), due[w].end());
  }
  return spheres;
}

SpherePairs ContactDetection::detect(const SphereView& s, bool local, double fastest, double& safe, TsCounters& counters) {
  ++passes_;
  safe = 0;
  const std::size_t n = s.x.size();
  if (local && bounds_ && 2.0 * s.radius + 2.0 * s.longest_flight <= narrowest(s)) {
    double first = 0;
    const std::vector<std::uint32_t> spheres = expired(s, first);
    if (double(spheres.size()) <= local_share * double(n)) {
      for (const std::uint32_t p : spheres) stale_[p] = 1;
      auto found = examine(s, spheres, fastest);
      for (const std::uint32_t p : spheres) {
        stale_[p] = 0;
        first = std::min(first, expires_[p]);
      }
      safe = first - clock_;
      ++counters.local_passes;
      counters.examined_spheres += spheres.size();
      return found;
    }
  }
  // Every sphere: the half-stencil pass bounds the safe times; the wider search a long flight needs does not.
  bounds_ = false;
  SpherePairs found;
  const double reach = 2.0 * s.radius + 2.0 * s.longest_flight;
  if (reach <= narrowest(s)) {
    const bool bound = !s.speed.empty();
    found = half_stencil_pass(s, true, bound, bound ? fastest : 0.0);
    bounds_ = bound;
  } else {
    found = search(s, {}, true);
  }
  counters.examined_spheres += n;
  if (bounds_) {
    std::vector<double> first(ts_threads(s.pool), std::numeric_limits<double>::infinity());
    for_ranges(s.pool, n, [&](std::size_t from, std::size_t to, std::size_t w) {
      double soonest = std::numeric_limits<double>::infinity();
      for (std::size_t p = from; p < to; ++p) soonest = std::min(soonest, expires_[p]);
      first[w] = soonest;
    });
    safe = *std::min_element(first.begin(), first.end()) - clock_;
  }
  return found;
}

void ContactDetection::save(StateWriter& out) const {
  out.put(expires_);
  out.put(near_key_);
  out.put(rate_);
  out.put(checked_pass_);
  out.put(changed_);
  out.put(passes_);
  out.put(clock_);
  out.put(std::uint8_t(bounds_));
}

void ContactDetection::restore(StateReader& in) {
  const std::size_t n = stale_.size();
  in.get(expires_);
  in.get(near_key_);
  in.get(rate_);
  in.get(checked_pass_);
  in.get(changed_);
  in.get(passes_);
  in.get(clock_);
  bounds_ = in.read<std::uint8_t>() != 0;
  if (expires_.size() != n || near_key_.size() != n || rate_.size() != n || checked_pass_.size() != n || changed_.size() != n)
    throw CheckpointError("the checkpoint's TS configuration has another number of particles");
}

}  // namespace aggkit
