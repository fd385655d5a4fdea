#include "particle/ts/time_stepping_aggregation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

constexpr double paper_radius = 0.2;  // [Degond2024, Table 1]: the units the DAHA parameters are tuned in

// Cells wide enough for the swept contact test of a flight of at most `substep` diameters per cluster
// (reach 2R + 2 · flight) to need only the 3^d stencil; 2R when that would leave a periodic axis fewer than
// 3 cells (the wider reach then falls back to a wider search).
double detection_cell_side(const Box& box, double radius, double substep) {
  const double wide = 2.0 * radius * (1.0 + 2.0 * std::min(substep, 1.0));
  for (int d = 0; d < box.dimension; ++d)
    if (wide > box.side[d] / 3.0) return 2.0 * radius;
  return wide;
}

}  // namespace

TimeSteppingAggregation::TimeSteppingAggregation(const Box& box, double radius, std::span<const Vector3> positions,
                                                 std::span<const Vector3> velocities, const TsSettings& settings)
    : box_(box),
      radius_(radius),
      scale_(paper_radius / radius),
      settings_(settings),
      pool_(settings.threads > 1 ? std::make_unique<WorkerPool>(std::min<std::size_t>(settings.threads, 64)) : nullptr),
      grid_(box, detection_cell_side(box, radius, settings.substep_displacement), positions.size()),
      cells_(grid_.size(), positions.size()),
      members_(positions.size()),
      x_(positions.begin(), positions.end()),
      velocity_(velocities.begin(), velocities.end()),
      flown_(positions.size(), Vector3{0, 0, 0}),
      reflected_(positions.size(), 0),
      before_(positions.size()),
      links_(positions.size()) {
  if (positions.size() != velocities.size() || positions.size() < 2)
    throw InputError("particles.count", std::to_string(positions.size()), "at least 2 particles, one velocity each");
  if (!(settings.interaction_range >= 2.0))
    throw InputError("interaction_range", format_value(settings.interaction_range), "Δ_W / R >= 2 (links touch at 2R)");
  for (const CellCoords& o : grid_.stencil())
    if (o[2] > 0 || (o[2] == 0 && (o[1] > 0 || (o[1] == 0 && o[0] >= 0)))) half_stencil_.push_back(o);
  half_neighbours_.assign(grid_.size() * half_stencil_.size(), no_cell);
  for (std::size_t cell = 0; cell < grid_.size(); ++cell)
    for (std::size_t k = 0; k < half_stencil_.size(); ++k)
      if (const auto n = grid_.neighbour(grid_.coords(cell), half_stencil_[k]))
        half_neighbours_[cell * half_stencil_.size() + k] = std::uint32_t(grid_.index(*n));
  for (std::uint32_t p = 0; p < x_.size(); ++p) cells_.insert(p, grid_.index(grid_.coords_of(x_[p])));
  const auto start_overlaps = overlaps_between_clusters({});
  for (const auto& [a, b] : start_overlaps)
    if (norm(sep(a, b)) < 2.0 * radius_ * (1.0 - 1e-12))
      throw InputError("particles.initial", "particles " + std::to_string(a) + " and " + std::to_string(b) + " at distance " +
                                                format_value(norm(sep(a, b))),
                       "a start without overlaps (distance >= 2R = " + format_value(2 * radius_) + ")");
  double speed = 0;
  for (const Vector3& v : velocity_) speed = std::max(speed, norm(v));
  if (!(speed > 0)) throw InputError("particles.initial.speed", "0", "a speed > 0 (the time step is dt_factor L / max|V|)");
  double side = 0;
  for (int d = 0; d < box_.dimension; ++d) side = std::max(side, box_.side[d]);
  dt0_ = settings_.dt_factor * side / speed;
}

double TimeSteppingAggregation::time_step() const {
  const double n = double(x_.size());
  return dt0_ * (2.0 - std::log(double(members_.clusters())) / std::log(n));
}

template <class F>
void TimeSteppingAggregation::for_near(std::uint32_t i, double reach, F&& f) const {
  const CellCoords c = grid_.coords_of(x_[i]);
  int k[3] = {0, 0, 0};
  for (int d = 0; d < box_.dimension; ++d) k[d] = int(std::ceil(reach / grid_.cell_side()[d] - 1e-12));
  // A small sorted set of cells: periodic axes with fewer than 2k+1 cells would visit a cell twice.
  thread_local std::vector<std::size_t> visit;
  visit.clear();
  for (int z = -k[2]; z <= k[2]; ++z)
    for (int y = -k[1]; y <= k[1]; ++y)
      for (int xo = -k[0]; xo <= k[0]; ++xo)
        if (const auto n = grid_.neighbour(c, {xo, y, z})) visit.push_back(grid_.index(*n));
  std::sort(visit.begin(), visit.end());
  visit.erase(std::unique(visit.begin(), visit.end()), visit.end());
  for (const std::size_t cell : visit)
    for (std::uint32_t j = cells_.first(cell); j != CellList::none; j = cells_.next(j))
      if (j != i) f(j);
}

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
  auto scan = [&](std::uint32_t i, bool all) {
    for_near(i, reach, [&](std::uint32_t j) {
      if (all && j < i) return;
      const Vector3 d = sep(i, j);
      // Different clusters: any overlap (or swept contact) links them. Within a cluster (only after a
      // minimisation, `among` given): an overlap deeper than the tolerance — a free sphere that moved onto
      // a sphere it was not constrained against — is minimised again with that pair as a link.
      const bool linked = members_.cluster_of(j) != members_.cluster_of(i) ? touched(d, i, j)
                                                                           : (!all && dot(d, d) < same_cluster2);
      if (linked) found.emplace_back(std::min(i, j), std::max(i, j));
    });
  };
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
    if (bound)
      for (std::uint32_t c = 0; c < x_.size(); ++c) fastest = std::max(fastest, speed_[c]);
    // Gaps less a margin far above the round-off the positions gather over the quiet flights.
    const double contact_margin = 2.0 * radius_ * (1.0 + 1e-6);
    const double far_gap = narrowest - contact_margin;
    const std::size_t workers = cells >= parallel_cells ? std::min<std::size_t>(settings_.threads, 64) : 1;
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
      pool_->run(workers, [&](std::size_t w) { pass(cells * w / workers, cells * (w + 1) / workers, parts[w], soonest[w]); });
      for (const auto& part : parts) found.insert(found.end(), part.begin(), part.end());
    }
    std::sort(found.begin(), found.end());
    if (bound) *safe = *std::min_element(soonest.begin(), soonest.end());
  } else if (among.empty()) {
    for (std::uint32_t i = 0; i < x_.size(); ++i) scan(i, true);
  } else {
    for (const std::uint32_t i : among) scan(i, false);
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
  }
  return found;
}

void TimeSteppingAggregation::reflect(std::uint32_t cluster) {
  if (box_.boundary != Boundary::reflecting) return;
  for (int d = 0; d < box_.dimension; ++d) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::uint32_t p = members_.first(cluster); p != ClusterMembership::none; p = members_.next(p)) {
      lo = std::min(lo, x_[p][d] - radius_);
      hi = std::max(hi, x_[p][d] + radius_);
    }
    const double side = box_.side[d];
    if (lo >= 0 && hi <= side) continue;
    const double mass = double(members_.size(cluster));
    double& v = velocity_[cluster][d];
    double shift = 0;
    // A specular reflection moves the cluster no farther than its flight did (the path is folded at the
    // wall); any other correction can, and ends the safe time of the quiet flights.
    bool specular = false;
    if (hi - lo > side) {  // wider than the box: centred, at rest along d
      shift = 0.5 * (side - hi - lo);
      wall_impulse_[d] += mass * v;
      v = 0;
    } else if (lo < 0) {
      if (v < 0) {  // specular: back by twice the penetration [Degond2024, Sec. 3 (ii)]
        wall_impulse_[d] += 2 * mass * v;
        v = -v;
        shift = -2 * lo;
        specular = true;
      } else {
        shift = -lo;
      }
      if (side - hi < shift) specular = false;
      shift = std::min(shift, side - hi);
    } else {
      if (v > 0) {
        wall_impulse_[d] += 2 * mass * v;
        v = -v;
        shift = -2 * (hi - side);
        specular = true;
      } else {
        shift = side - hi;
      }
      if (-lo > shift) specular = false;
      shift = std::max(shift, -lo);
    }
    if (!specular) jumped_ = true;
    ++counters_.wall_contacts;
    if (!reflected_[cluster]) reflected_list_.push_back(cluster);
    reflected_[cluster] = 1;
    for (std::uint32_t p = members_.first(cluster); p != ClusterMembership::none; p = members_.next(p)) {
      x_[p][d] += shift;
      flown_[p][d] += shift;
    }
  }
}

template <class F>
void TimeSteppingAggregation::for_ranges(std::size_t n, F&& f) const {
  const std::size_t workers = n >= parallel_cells ? std::min<std::size_t>(settings_.threads, 64) : 1;
  if (workers <= 1) return f(std::size_t(0), n, std::size_t(0));
  pool_->run(workers, [&](std::size_t w) { f(n * w / workers, n * (w + 1) / workers, w); });
}

bool TimeSteppingAggregation::flight(double dt) {
  for (const std::uint32_t c : reflected_list_) reflected_[c] = 0;
  reflected_list_.clear();
  jumped_ = false;
  // One streaming pass: every sphere flies (wrapped on periodic boxes) and, with walls, the clusters with a
  // sphere past one are noted (the test is reflect's own, sphere by sphere); they are then reflected in
  // increasing cluster order, as a walk through every cluster's members per axis would.
  const bool walls = box_.boundary == Boundary::reflecting, periodic = box_.boundary == Boundary::periodic;
  std::vector<std::vector<std::uint32_t>> past(std::max<std::size_t>(std::min<std::size_t>(settings_.threads, 64), 1));
  for_ranges(x_.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
    for (std::size_t p = from; p < to; ++p) {
      const std::uint32_t c = members_.cluster_of(std::uint32_t(p));
      flown_[p] = dt * velocity_[c];
      x_[p] = x_[p] + flown_[p];
      if (periodic) x_[p] = box_.wrap(x_[p]);
      if (walls)
        for (int d = 0; d < box_.dimension; ++d)
          if (x_[p][d] - radius_ < 0 || x_[p][d] + radius_ > box_.side[d]) {
            past[w].push_back(c);
            break;
          }
    }
  });
  if (walls) {
    std::vector<std::uint32_t>& all = past[0];
    for (std::size_t w = 1; w < past.size(); ++w) all.insert(all.end(), past[w].begin(), past[w].end());
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    for (const std::uint32_t c : all) reflect(c);
  }
  // Within the safe time of the last detection pass (header): nothing to detect, cells updated later.
  if (settings_.quiet_flights && !jumped_ && dt < safe_left_) {
    safe_left_ -= dt;
    return false;
  }
  safe_left_ = 0;
  locate();
  return true;
}

void TimeSteppingAggregation::locate() {
  // New cells found in parallel, moved in the (order-dependent) cell list serially.
  std::vector<double> longest(std::max<std::size_t>(settings_.threads, 1), 0.0);
  new_cell_.resize(x_.size());
  for_ranges(x_.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
    for (std::size_t p = from; p < to; ++p) {
      longest[w] = std::max(longest[w], norm(flown_[p]));
      new_cell_[p] = std::uint32_t(grid_.index(grid_.coords_of(x_[p])));
    }
  });
  longest_flight_ = *std::max_element(longest.begin(), longest.end());
  for (std::uint32_t p = 0; p < x_.size(); ++p)
    if (new_cell_[p] != cells_.cell_of(p)) cells_.move(p, new_cell_[p]);
}

void TimeSteppingAggregation::link(std::uint32_t a, std::uint32_t b) {
  if (std::find(links_[a].begin(), links_[a].end(), b) == links_[a].end()) {
    links_[a].push_back(b);
    links_[b].push_back(a);
  }
  std::uint32_t ca = members_.cluster_of(a), cb = members_.cluster_of(b);
  if (ca == cb) return;
  if (members_.size(ca) < members_.size(cb)) std::swap(ca, cb);
  const double na = double(members_.size(ca)), nb = double(members_.size(cb));
  // Momentum-weighted velocity of the merged cluster [Degond2024, eq. 2.9 and Sec. 3, step 3b].
  velocity_[ca] = (1.0 / (na + nb)) * (na * velocity_[ca] + nb * velocity_[cb]);
  velocity_[cb] = {0, 0, 0};
  members_.merge(ca, cb, [](std::uint32_t) {});
  ++counters_.merges;
}

DahaResult TimeSteppingAggregation::minimise(const Group& group, std::vector<std::uint32_t>& moved, double& largest_move) {
  const double range = settings_.interaction_range * radius_;       // Δ_W
  const double constrained = std::max(range, 6.0 * radius_);        // constraint pairs closer than this
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  std::vector<std::uint32_t> order;  // local index → particle
  auto add = [&](std::uint32_t p) {
    if (local.emplace(p, std::uint32_t(order.size())).second) order.push_back(p);
  };
  if (settings_.global) {
    for (std::uint32_t p = members_.first(group.cluster); p != ClusterMembership::none; p = members_.next(p)) add(p);
  } else {
    for (const std::uint32_t s : group.seeds) add(s);
    for (const std::uint32_t s : group.seeds)
      for_near(s, range, [&](std::uint32_t j) {
        if (members_.cluster_of(j) == group.cluster && norm(sep(s, j)) <= range) add(j);
      });
    std::sort(order.begin(), order.end());  // deterministic local order
    for (std::uint32_t k = 0; k < order.size(); ++k) local[order[k]] = k;
  }
  const std::size_t free = order.size();
  DahaProblem problem;
  problem.dimension = box_.dimension;
  problem.contact = 2.0 * radius_ * scale_;
  problem.free = free;
  auto pair_of = [&](std::uint32_t i, std::uint32_t j) {
    const Vector3 raw = x_[j] - x_[i];
    const Vector3 image = box_.minimum_image(raw);
    const bool linked = std::find(links_[i].begin(), links_[i].end(), j) != links_[i].end();
    const bool attract = linked && (settings_.global || norm(image) <= range);  // eq. 3.30
    if (local.find(j) == local.end()) add(j);
    problem.pairs.push_back({local.at(i), local.at(j), attract, scale_ * (image - raw)});
  };
  if (settings_.global) {
    for (std::uint32_t a = 0; a < free; ++a)
      for (std::uint32_t b = a + 1; b < free; ++b) pair_of(order[a], order[b]);
  } else {
    for (std::uint32_t a = 0; a < free; ++a) {
      const std::uint32_t i = order[a];
      std::vector<std::uint32_t> near;
      for_near(i, constrained, [&](std::uint32_t j) {
        if (members_.cluster_of(j) != group.cluster || norm(sep(i, j)) >= constrained) return;
        const auto it = local.find(j);
        if (it != local.end() && it->second < free && it->second <= a) return;  // free pairs once
        near.push_back(j);
      });
      std::sort(near.begin(), near.end());
      for (const std::uint32_t j : near) pair_of(i, j);
    }
  }
  problem.x.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) problem.x[k] = scale_ * x_[order[k]];
  const DahaResult result = aggkit::minimise(problem, settings_.daha);
  for (std::size_t k = 0; k < free; ++k) {
    const Vector3 to = (1.0 / scale_) * problem.x[k];
    largest_move = std::max(largest_move, norm(to - x_[order[k]]));
    x_[order[k]] = to;
  }
  moved.assign(order.begin(), order.begin() + std::ptrdiff_t(free));
  return result;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> TimeSteppingAggregation::merge_binary_contacts(
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found, double dt) {
  const double contact2 = 4.0 * radius_ * radius_;
  // The fraction τ ∈ [0, 1] of the flight at which a swept pair first touched: |d0 + τ w| = 2R with
  // d0 = d − w the separation before the flight.
  auto first_touch = [&](std::uint32_t i, std::uint32_t j) {
    const Vector3 d = sep(i, j), w = flown_[j] - flown_[i], d0 = d - w;
    const double a = dot(w, w), b = 2.0 * dot(d0, w), c = dot(d0, d0) - contact2;
    if (c <= 0 || a <= 0) return 0.0;
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0) return 1.0;
    return std::clamp((-b - std::sqrt(disc)) / (2.0 * a), 0.0, 1.0);
  };
  // Partner clusters of each cluster over the found pairs; a pair of clusters that only met each other
  // (and no wall) in this flight is a binary collision.
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> partners;
  for (const auto& [i, j] : found) {
    const std::uint32_t ci = members_.cluster_of(i), cj = members_.cluster_of(j);
    auto add = [&](std::uint32_t c, std::uint32_t other) {
      auto& list = partners[c];
      if (std::find(list.begin(), list.end(), other) == list.end()) list.push_back(other);
    };
    add(ci, cj);
    add(cj, ci);
  }
  auto binary = [&](std::uint32_t ci, std::uint32_t cj) {
    return partners[ci].size() == 1 && partners[cj].size() == 1 && !reflected_[ci] && !reflected_[cj];
  };
  // Earliest touching pair of each binary collision (found is sorted: deterministic).
  std::unordered_map<std::uint32_t, std::pair<double, std::pair<std::uint32_t, std::uint32_t>>> earliest;  // by lower cluster
  std::vector<std::pair<std::uint32_t, std::uint32_t>> rest;
  for (const auto& pr : found) {
    const std::uint32_t ci = members_.cluster_of(pr.first), cj = members_.cluster_of(pr.second);
    if (!binary(ci, cj)) {
      rest.push_back(pr);
      continue;
    }
    const double tau = first_touch(pr.first, pr.second);
    const auto [it, fresh] = earliest.emplace(std::min(ci, cj), std::make_pair(tau, pr));
    if (!fresh && tau < it->second.first) it->second = {tau, pr};
  }
  std::vector<std::uint32_t> keys;
  for (const auto& e : earliest) keys.push_back(e.first);
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> moved;
  double farthest = 0;  // the largest displacement of a moved sphere from where the pass saw it
  const bool periodic = box_.boundary == Boundary::periodic;  // wrap and minimum image: identities otherwise
  const double inf = std::numeric_limits<double>::infinity();
  for (const std::uint32_t key : keys) {
    const auto& [tau, pr] = earliest[key];
    const auto [i, j] = pr;
    // Back to the contact, merged there, and on with the merged velocity for the rest of the flight: an
    // isolated collision is then exactly ED's, and the minimisation is left the simultaneous ones. (The
    // merge changes velocities only, so it goes first and every sphere is moved in one pass, which also
    // gathers reflect's bounds: reflect is called only when the cluster crosses a wall.)
    link(i, j);
    const std::uint32_t c = members_.cluster_of(i);
    const Vector3 rest_of_flight = ((1.0 - tau) * dt) * velocity_[c];
    Vector3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
    const std::size_t from = moved.size();
    for (std::uint32_t p = members_.first(c); p != ClusterMembership::none; p = members_.next(p)) {
      before_[p] = x_[p];
      x_[p] = x_[p] - (1.0 - tau) * flown_[p];
      x_[p] = x_[p] + rest_of_flight;
      for (int d = 0; d < box_.dimension; ++d) {
        lo[d] = std::min(lo[d], x_[p][d] - radius_);
        hi[d] = std::max(hi[d], x_[p][d] + radius_);
      }
      moved.push_back(p);
    }
    bool inside = true;
    for (int d = 0; d < box_.dimension; ++d) inside = inside && lo[d] >= 0 && hi[d] <= box_.side[d];
    if (!inside) reflect(c);
    ++counters_.contact_time_merges;
    for (std::size_t k = from; k < moved.size(); ++k) {
      const std::uint32_t p = moved[k];
      if (periodic) x_[p] = box_.wrap(x_[p]);
      const std::size_t cell = grid_.index(grid_.coords_of(x_[p]));
      if (cell != cells_.cell_of(p)) cells_.move(p, cell);
      before_[p] = periodic ? box_.minimum_image(x_[p] - before_[p]) : x_[p] - before_[p];
      farthest = std::max(farthest, norm(before_[p]));
    }
  }
  // Near re-check (header): only the moved spheres that can now touch a sphere that was in another
  // cluster at the pass. Not after a round cap hit (a cluster may then hold overlaps deeper than the
  // same-cluster tolerance, which a full re-check of the moved spheres would link again).
  if (settings_.near_recheck && nearest_.size() == x_.size() && counters_.round_cap_hits == 0) {
    double narrowest = grid_.cell_side()[0];
    for (int d = 1; d < box_.dimension; ++d) narrowest = std::min(narrowest, grid_.cell_side()[d]);
    const double reach = 2.0 * radius_ * (1.0 + 1e-6) + farthest;
    std::erase_if(moved, [&](std::uint32_t p) { return std::min(nearest_[p], narrowest) >= reach + norm(before_[p]); });
  }
  counters_.rechecked_spheres += moved.size();
  // What the merged clusters now overlap is left to the minimisation, with the other contacts.
  for (const auto& pr : overlaps_between_clusters(moved)) rest.push_back(pr);
  std::sort(rest.begin(), rest.end());
  rest.erase(std::unique(rest.begin(), rest.end()), rest.end());
  return rest;
}

void TimeSteppingAggregation::resolve(std::vector<std::pair<std::uint32_t, std::uint32_t>> new_links) {
  std::size_t rounds = 0;
  while (!new_links.empty()) {
    if (rounds++ >= settings_.max_rounds) {
      ++counters_.round_cap_hits;
      break;
    }
    ++counters_.rounds;
    const std::uint64_t merges_before = counters_.merges;
    for (const auto& [a, b] : new_links) link(a, b);
    if (rounds > 1) counters_.secondary_merges += counters_.merges - merges_before;
    std::vector<Group> groups;
    std::unordered_map<std::uint32_t, std::size_t> group_of;
    for (const auto& [a, b] : new_links) {
      const std::uint32_t c = members_.cluster_of(a);
      const auto [it, fresh] = group_of.emplace(c, groups.size());
      if (fresh) groups.push_back({c, {}});
      groups[it->second].seeds.push_back(a);
      groups[it->second].seeds.push_back(b);
    }
    for (Group& g : groups) {
      std::sort(g.seeds.begin(), g.seeds.end());
      g.seeds.erase(std::unique(g.seeds.begin(), g.seeds.end()), g.seeds.end());
    }
    std::vector<DahaResult> results(groups.size());
    std::vector<std::vector<std::uint32_t>> moved(groups.size());
    std::vector<double> moves(groups.size(), 0.0);
    const std::size_t workers = std::min(settings_.threads, groups.size());
    if (workers <= 1) {
      for (std::size_t g = 0; g < groups.size(); ++g) results[g] = minimise(groups[g], moved[g], moves[g]);
    } else {
      // Separate clusters: disjoint free spheres, each group reads only its own cluster.
      pool_->run(groups.size(), [&](std::size_t g) { results[g] = minimise(groups[g], moved[g], moves[g]); });
    }
    std::vector<std::uint32_t> check;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const DahaResult& r = results[g];
      ++counters_.minimisations;
      counters_.minimisation_iterations += r.iterations;
      counters_.free_spheres += moved[g].size();
      if (!r.converged) ++counters_.iteration_cap_hits;
      counters_.max_overlap = std::max(counters_.max_overlap, r.max_overlap);
      counters_.largest_move = std::max(counters_.largest_move, moves[g]);
      counters_.overlap_sum += r.mean_overlap;
      last_mean_ = r.mean_overlap;
      bool outside = false;
      for (const std::uint32_t p : moved[g]) {
        x_[p] = box_.wrap(x_[p]);
        if (box_.boundary == Boundary::reflecting)
          for (int d = 0; d < box_.dimension; ++d)
            outside = outside || x_[p][d] < radius_ || x_[p][d] > box_.side[d] - radius_;
      }
      if (outside) {  // pushed past a wall by the minimisation: the cluster is moved back as a whole
        reflect(groups[g].cluster);
        for (std::uint32_t p = members_.first(groups[g].cluster); p != ClusterMembership::none; p = members_.next(p))
          check.push_back(p);
      } else {
        check.insert(check.end(), moved[g].begin(), moved[g].end());
      }
    }
    for (const std::uint32_t p : check) {
      const std::size_t cell = grid_.index(grid_.coords_of(x_[p]));
      if (cell != cells_.cell_of(p)) cells_.move(p, cell);
    }
    new_links = overlaps_between_clusters(check);
  }
}

void TimeSteppingAggregation::step(double dt) {
  if (!(dt > 0)) dt = time_step();
  ++counters_.steps;
  last_mean_ = 0;
  // Substeps: no cluster flies farther than substep_displacement · 2R in one flight, so that a contact is
  // found by the swept test below, and resolved from a shallow overlap, however long the step.
  double speed = 0;
  speed_.assign(x_.size(), 0.0);
  for (std::uint32_t c = 0; c < x_.size(); ++c)
    if (members_.size(c) > 0) speed = std::max(speed, speed_[c] = norm(velocity_[c]));
  const double cap = settings_.substep_displacement * 2.0 * radius_;
  const double pieces = std::max(1.0, std::ceil(speed * dt / cap));
  const std::size_t substeps = std::size_t(std::min(pieces, 1e9));
  for (std::size_t k = 0; k < substeps; ++k) {
    ++counters_.substeps;
    if (!flight(dt / double(substeps))) {
      ++counters_.quiet_flights;
      continue;
    }
    double safe = 0;
    auto found = overlaps_between_clusters({}, true, &safe, settings_.contact_time ? &nearest_ : nullptr);
    if (found.empty()) {
      // Nothing moves before the next flight: the pass's safe time holds from here (a margin for the
      // round-off of the positions flown meanwhile).
      safe_left_ = safe * (1.0 - 1e-9);
      continue;
    }
    if (settings_.contact_time) found = merge_binary_contacts(std::move(found), dt / double(substeps));
    resolve(std::move(found));
    for (std::uint32_t c = 0; c < x_.size(); ++c) speed_[c] = members_.size(c) > 0 ? norm(velocity_[c]) : 0.0;
  }
  time_ += dt;
}

TsStop TimeSteppingAggregation::advance(double t, std::size_t target_clusters, const std::function<void()>& progress) {
  for (;;) {
    if (target_clusters > 0 && members_.clusters() <= target_clusters) return TsStop::clusters_reached;
    if (time_ >= t) return TsStop::time_reached;
    const double dt = time_step();
    if (time_ + dt >= t - 1e-12 * std::abs(t)) {
      step(t - time_);
      time_ = t;
    } else {
      step(dt);
    }
    if (progress && counters_.steps % 256 == 0) progress();
  }
}

bool TimeSteppingAggregation::at_rest() const {
  const Vector3* first = nullptr;
  double scale = 0;
  for (std::uint32_t c = 0; c < x_.size(); ++c)
    if (members_.size(c) > 0) scale = std::max(scale, norm(velocity_[c]));
  for (std::uint32_t c = 0; c < x_.size(); ++c) {
    if (members_.size(c) == 0) continue;
    if (!first) first = &velocity_[c];
    else if (norm(velocity_[c] - *first) > 1e-12 * scale) return false;
  }
  return true;
}

std::vector<Vector3> TimeSteppingAggregation::velocities() const {
  std::vector<Vector3> v(x_.size());
  for (std::uint32_t p = 0; p < x_.size(); ++p) v[p] = velocity_[members_.cluster_of(p)];
  return v;
}

std::vector<Vector3> TimeSteppingAggregation::cluster_positions(std::uint32_t cluster) const {
  // Unwrapped along the links (breadth first from the cluster's first particle).
  std::unordered_map<std::uint32_t, Vector3> placed;
  std::vector<std::uint32_t> queue{members_.first(cluster)};
  placed[queue[0]] = x_[queue[0]];
  for (std::size_t k = 0; k < queue.size(); ++k) {
    const std::uint32_t i = queue[k];
    for (const std::uint32_t j : links_[i])
      if (placed.emplace(j, placed[i] + sep(i, j)).second) queue.push_back(j);
  }
  std::vector<Vector3> out;
  for (std::uint32_t p = members_.first(cluster); p != ClusterMembership::none; p = members_.next(p)) out.push_back(placed.at(p));
  return out;
}

std::uint32_t TimeSteppingAggregation::largest_cluster() const {
  std::uint32_t best = 0;
  for (std::uint32_t c = 0; c < x_.size(); ++c)
    if (members_.size(c) > members_.size(best)) best = c;
  return best;
}

double TimeSteppingAggregation::kinetic_energy() const {
  double e = 0;
  for (std::uint32_t c = 0; c < x_.size(); ++c)
    if (members_.size(c) > 0) e += 0.5 * double(members_.size(c)) * dot(velocity_[c], velocity_[c]);
  return e;
}

Vector3 TimeSteppingAggregation::momentum() const {
  Vector3 p{0, 0, 0};
  for (std::uint32_t c = 0; c < x_.size(); ++c)
    if (members_.size(c) > 0) p = p + double(members_.size(c)) * velocity_[c];
  return p;
}

double TimeSteppingAggregation::largest_overlap() const {
  const double contact2 = 4.0 * radius_ * radius_;
  double worst = 0;
  for (std::uint32_t i = 0; i < x_.size(); ++i)
    for_near(i, 2.0 * radius_, [&](std::uint32_t j) {
      const Vector3 d = sep(i, j);
      worst = std::max(worst, std::sqrt(std::max(0.0, contact2 - dot(d, d))));
    });
  return worst * scale_;
}

double TimeSteppingAggregation::largest_relative_overlap() const {
  double worst = 0;
  for (std::uint32_t i = 0; i < x_.size(); ++i)
    for_near(i, 2.0 * radius_, [&](std::uint32_t j) { worst = std::max(worst, 1.0 - norm(sep(i, j)) / (2.0 * radius_)); });
  return worst;
}

std::size_t TimeSteppingAggregation::links() const {
  std::size_t n = 0;
  for (const auto& l : links_) n += l.size();
  return n / 2;
}

}  // namespace aggkit
