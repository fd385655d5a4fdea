// Predictions of the ED engine: broad-phase crossings and wall contacts of clusters, overlap windows of
// candidate pairs and, inside them, exact first contacts (collision_time.hpp) found by casting the smaller
// cluster's members through the larger one's member index.
#include <algorithm>
#include <cmath>
#include <limits>

#include "particle/ed/collision_time.hpp"
#include "particle/ed/event_driven_aggregation.hpp"
#include "particle/ed/overlap_window.hpp"

namespace aggkit {

namespace {
constexpr double never = std::numeric_limits<double>::infinity();
constexpr double cast_reach = 4;  // index cells of relative displacement searched per prediction
// Steps of the overlap-window search of a candidate pair before a pair check is scheduled instead: in a
// periodic box the windows of two small boxes rarely coincide, and a pair check is cheaper than stepping
// through many periods (ν = 0.3 periodic, N = 3·10^4: 8 steps instead of 64 cut the run time by ~18 %,
// 3 steps by ~10 % more; 1 step doubles the pair checks and is slower again).
constexpr int pair_search_steps = 3;
}

// The next time a face of the cluster's inflated box crosses a grid line at any level it is registered at.
void EventDrivenAggregation::predict_crossing(std::uint32_t c) {
  if (level_[c] == grid_.top()) return;
  const Vector3 origin = cluster_origin(c);
  const Vector3& v = velocity_[c];
  const double pad = radius_ + margin_;
  double best = never;
  int best_level = 0, best_axis = 0, best_face = 0;
  for (int l = level_[c]; l <= passenger_top(c); ++l) {
    const auto& r = grid_.range(c, l);
    for (int a = 0; a < box_.dimension; ++a) {
      if (v[a] == 0 || grid_.count(l, a) == 1) continue;
      const double h = grid_.side(l, a);
      const double lo = origin[a] + low_[c][a] - pad, hi = origin[a] + high_[c][a] + pad;
      double t_lo, t_hi;
      if (v[a] > 0) {
        t_lo = ((r.lo[a] + 1) * h - lo) / v[a];
        t_hi = ((r.hi[a] + 1) * h - hi) / v[a];
      } else {
        t_lo = (lo - r.lo[a] * h) / -v[a];
        t_hi = (hi - r.hi[a] * h) / -v[a];
      }
      for (int face = 0; face < 2; ++face) {
        const double t = std::max(0.0, face ? t_hi : t_lo);
        if (t < best) {
          best = t;
          best_level = l;
          best_axis = a;
          best_face = face;
        }
      }
    }
  }
  if (best == never) return;
  queue_.push({now_ + (long double)best, stamp_[c], raises_, c, std::uint32_t(best_face), EventKind::cell_crossing,
               std::uint8_t(best_axis), std::int8_t(velocity_[c][best_axis] > 0 ? 1 : -1), std::uint8_t(best_level)});
}

void EventDrivenAggregation::predict_wall(std::uint32_t c) {
  if (box_.boundary != Boundary::reflecting) return;
  const Vector3 origin = cluster_origin(c);
  const Vector3& v = velocity_[c];
  double best = never;
  int best_axis = 0;
  for (int a = 0; a < box_.dimension; ++a) {
    double t = never;
    if (v[a] > 0) t = std::max(0.0, box_.side[a] - radius_ - (origin[a] + high_[c][a])) / v[a];
    else if (v[a] < 0) t = std::max(0.0, origin[a] + low_[c][a] - radius_) / -v[a];
    if (t < best) {
      best = t;
      best_axis = a;
    }
  }
  if (best == never) return;
  queue_.push({now_ + (long double)best, stamp_[c], 0, c, 0, EventKind::wall, std::uint8_t(best_axis), 0});
}

// Candidates x, y: the first window in which their inflated boxes overlap; a pair check when it opens,
// else (overlapping now) the exact first contact within it, or a pair check when it closes.
void EventDrivenAggregation::predict_pair(std::uint32_t x, std::uint32_t y) {
  const Vector3 w = velocity_[y] - velocity_[x];
  const double speed = norm(w);
  if (speed == 0) return;  // relative rest: they never meet
  const Vector3 ox = cluster_origin(x), oy = cluster_origin(y);
  const Vector3 ex = extent(x), ey = extent(y);
  Vector3 y0{0, 0, 0}, s{0, 0, 0}, period{0, 0, 0};
  for (int a = 0; a < box_.dimension; ++a) {
    y0[a] = (oy[a] + 0.5 * (low_[y][a] + high_[y][a])) - (ox[a] + 0.5 * (low_[x][a] + high_[x][a]));
    s[a] = 0.5 * (ex[a] + ey[a]);
    if (box_.boundary == Boundary::periodic) period[a] = box_.side[a];
  }
  const double min_length = margin_ / speed;
  const OverlapWindow window = first_overlap(box_.dimension, y0, w, s, period, min_length, pair_search_steps);
  if (window.kind == OverlapWindow::none) return;
  if (window.kind == OverlapWindow::recheck || window.begin > min_length) {
    queue_.push({now_ + (long double)window.begin, stamp_[x], stamp_[y], x, y, EventKind::pair_check, 0, 0});
    return;
  }
  // The search stops after a relative displacement of a few index cells (then a pair check goes on): big
  // clusters change velocity often (every absorbed monomer), and a long cast would mostly be thrown away.
  double shortest = box_.side[0];
  for (int a = 1; a < box_.dimension; ++a) shortest = std::min(shortest, box_.side[a]);
  const double reach = std::min(0.5 * shortest, cast_reach * index_.grid().cell_side()[0]);
  const double horizon = std::min(window.end, reach / speed);
  const Contact contact = first_contact(x, y, horizon);
  if (contact.a != ClusterIndex::none) {
    queue_.push({now_ + (long double)contact.time, stamp_[members_.cluster_of(contact.a)],
                 stamp_[members_.cluster_of(contact.b)], contact.a, contact.b, EventKind::collision, 0, 0});
    return;
  }
  queue_.push({now_ + (long double)horizon, stamp_[x], stamp_[y], x, y, EventKind::pair_check, 0, 0});
}

// The first contact of clusters x and y before `horizon` (from now), if any. In the larger cluster's frame
// the smaller one's members move with w = v_small − v_large; each is cast through the larger one's index
// during the window in which it is within a contact distance of the larger one's box, front-first, stopping
// at the best contact found so far.
EventDrivenAggregation::Contact EventDrivenAggregation::first_contact(std::uint32_t x, std::uint32_t y,
                                                                      double horizon) {
  Contact best{horizon, ClusterIndex::none, ClusterIndex::none};
  const double sigma = 2 * radius_;
  if (members_.size(x) == 1 && members_.size(y) == 1) {
    const std::uint32_t i = members_.first(x), j = members_.first(y);
    const double t = collision_time(box_.minimum_image(cluster_origin(y) + offset_[j] - cluster_origin(x) - offset_[i]),
                                    velocity_[y] - velocity_[x], sigma);
    if (t < best.time) best = {t, i, j};
    return best;
  }
  const std::uint32_t owner = members_.size(x) >= members_.size(y) ? x : y;
  const std::uint32_t mover = owner == x ? y : x;
  const Vector3 w = velocity_[mover] - velocity_[owner];
  const Vector3 shift = cluster_origin(mover) - cluster_origin(owner);
  Vector3 centre{0, 0, 0}, half{0, 0, 0}, period{0, 0, 0};
  for (int a = 0; a < box_.dimension; ++a) {
    centre[a] = 0.5 * (low_[owner][a] + high_[owner][a]);
    half[a] = 0.5 * (high_[owner][a] - low_[owner][a]) + sigma + margin_;
    if (box_.boundary == Boundary::periodic) period[a] = box_.side[a];
  }
  const double min_length = margin_ / norm(w);
  rays_.clear();
  for (std::uint32_t p = members_.first(mover); p != ClusterMembership::none; p = members_.next(p)) {
    // Along periodic axes the member may leave the box and meet it again (another image) before the horizon.
    double t = 0;
    while (t < best.time) {
      const Vector3 y0 = shift + offset_[p] - centre + t * w;
      const OverlapWindow window = first_overlap(box_.dimension, y0, w, half, period, min_length, 64, best.time - t);
      if (window.kind == OverlapWindow::none || t + window.begin >= best.time) break;
      if (window.kind == OverlapWindow::recheck) {
        rays_.push_back({t + window.begin, best.time, p});
        break;
      }
      rays_.push_back({t + window.begin, t + window.end, p});
      t += window.end + min_length;
    }
  }
  std::sort(rays_.begin(), rays_.end(), [](const Ray& a, const Ray& b) { return a.begin < b.begin; });
  ++memo_call_;
  for (const Ray& r : rays_) {
    if (r.begin >= best.time) break;
    cast(owner, shift + offset_[r.particle], w, r.begin, std::min(r.end + min_length, best.time), r.particle, best);
  }
  return best;
}

std::uint32_t EventDrivenAggregation::first_in_cell(std::uint32_t owner, const CellCoords& cell) const {
  const std::size_t slot = (std::size_t(cell[0]) * 73856093u ^ std::size_t(cell[1]) * 19349663u ^ std::size_t(cell[2]) * 83492791u) &
                           (memo_size - 1);
  MemoCell& m = memo_[slot];
  // Component by component: std::array's == is a memcmp call here, a sixth of a large 3-D run's time.
  if (m.call == memo_call_ && m.cell[0] == cell[0] && m.cell[1] == cell[1] && m.cell[2] == cell[2]) return m.head;
  m = {cell, memo_call_, index_.first(owner, cell)};
  return m.head;
}

// Member `ray` of another cluster, at `start` in `owner`'s frame at time 0 and moving with w, walks the
// owner's index cells (DDA of [Amanatides1987]) from `from` to `to`; at each cell entered the members in the
// new stencil layer are tested for an exact contact (all of the stencil at the first cell).
void EventDrivenAggregation::cast(std::uint32_t owner, const Vector3& start, const Vector3& w, double from,
                                  double to, std::uint32_t ray, Contact& best) const {
  const CellGrid& g = index_.grid();
  const Vector3& side = g.cell_side();
  const int dimension = box_.dimension;
  const double sigma = 2 * radius_;
  const Vector3 minus_w{-w[0], -w[1], -w[2]};
  auto test = [&](const CellCoords& c, int axis, int direction, double t) {
    const Vector3 u = start + t * w;
    for (const CellCoords& o : g.stencil()) {
      if (axis >= 0 && o[axis] != direction) continue;
      const CellCoords cell{c[0] + o[0], c[1] + o[1], c[2] + o[2]};
      for (std::uint32_t m = first_in_cell(owner, cell); m != ClusterIndex::none; m = index_.next(m)) {
        const double tc = collision_time(g.stencil_image(offset_[m] - u, o), minus_w, sigma);
        if (tc == never) continue;
        if (t + tc < best.time) best = {t + tc, ray, m};
      }
    }
  };
  const Vector3 u = start + from * w;
  CellCoords c = index_.cell_of(u);
  test(c, -1, 0, from);
  double next[3] = {never, never, never}, step[3] = {0, 0, 0};
  int direction[3] = {0, 0, 0};
  for (int a = 0; a < dimension; ++a) {
    if (w[a] > 0) {
      next[a] = from + std::max(0.0, ((c[a] + 1) * side[a] - u[a]) / w[a]);
      direction[a] = 1;
    } else if (w[a] < 0) {
      next[a] = from + std::max(0.0, (c[a] * side[a] - u[a]) / w[a]);
      direction[a] = -1;
    }
    if (w[a] != 0) step[a] = side[a] / std::abs(w[a]);
  }
  while (true) {
    int a = 0;
    for (int b = 1; b < dimension; ++b)
      if (next[b] < next[a]) a = b;
    const double t = next[a];
    if (t >= to || t >= best.time) return;
    c[a] += direction[a];
    test(c, a, direction[a], t);
    next[a] += step[a];
  }
}

}  // namespace aggkit
