// Predictions of the ED engine: contacts between particles of different clusters (exact roots,
// collision_time.hpp), cell crossings of particles and wall contacts of clusters.
#include <cmath>
#include <limits>

#include "particle/ed/collision_time.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

namespace aggkit {

namespace {
constexpr double never = std::numeric_limits<double>::infinity();
}

// x_j − x_i for j in the stencil cell at `offset` from i's cell. Along periodic axes the image is the one
// nearest to offset·(cell side): j lies within one cell side of it, and the other images are at least
// L − cell side >= 2 cell sides away (>= 3 cells per periodic axis), so the choice is unambiguous even for
// positions that drifted by round-off across a cell face.
Vector3 EventDrivenAggregation::separation(std::uint32_t, const Vector3& xi, std::uint32_t j,
                                           const CellCoords& offset) const {
  Vector3 d = position(j) - xi;
  const Box& b = box();
  if (b.boundary == Boundary::periodic)
    for (int a = 0; a < b.dimension; ++a)
      d[a] -= b.side[a] * std::nearbyint((d[a] - offset[a] * grid_.cell_side()[a]) / b.side[a]);
  return d;
}

void EventDrivenAggregation::predict_collisions(std::uint32_t i, int axis, int direction, bool higher_only) {
  const std::uint32_t ci = members_.cluster_of(i);
  const Vector3 xi = position(i);
  const Vector3& vi = velocity_[ci];
  const double sigma = 2 * radius_;
  for (const CellCoords& o : grid_.stencil()) {
    if (axis >= 0 && o[axis] != direction) continue;
    const auto cell = grid_.neighbour(cell_[i], o);
    if (!cell) continue;
    for (std::uint32_t j = cells_.first(grid_.index(*cell)); j != CellList::none; j = cells_.next(j)) {
      const std::uint32_t cj = members_.cluster_of(j);
      if (cj == ci || (higher_only && j < i)) continue;
      const double t = collision_time(separation(i, xi, j, o), velocity_[cj] - vi, sigma);
      if (t == never) continue;
      queue_.push({now_ + (long double)t, stamp_[ci], stamp_[cj], i, j, EventKind::collision, 0, 0});
    }
  }
}

void EventDrivenAggregation::predict_crossing(std::uint32_t p) {
  const std::uint32_t c = members_.cluster_of(p);
  const Vector3 x = position(p);
  const Vector3& v = velocity_[c];
  const Box& b = box();
  const bool periodic = b.boundary == Boundary::periodic;
  double best = never;
  int best_axis = 0, best_direction = 0;
  for (int a = 0; a < b.dimension; ++a) {
    if (v[a] == 0) continue;
    const double side = grid_.cell_side()[a];
    // Coordinate within the particle's recorded cell (nearest periodic image), clamped against round-off.
    double u = x[a] - cell_[p][a] * side;
    if (periodic) u -= b.side[a] * std::nearbyint((u - 0.5 * side) / b.side[a]);
    u = std::clamp(u, 0.0, side);
    double t;
    if (v[a] > 0) {
      if (!periodic && cell_[p][a] == grid_.counts()[a] - 1) continue;
      t = (side - u) / v[a];
    } else {
      if (!periodic && cell_[p][a] == 0) continue;
      t = u / -v[a];
    }
    if (t < best) {
      best = t;
      best_axis = a;
      best_direction = v[a] > 0 ? 1 : -1;
    }
  }
  if (best == never) return;
  queue_.push({now_ + (long double)best, stamp_[c], 0, p, 0, EventKind::cell_crossing, std::uint8_t(best_axis),
               std::int8_t(best_direction)});
}

void EventDrivenAggregation::predict_wall(std::uint32_t c) {
  const Box& b = box();
  if (b.boundary != Boundary::reflecting) return;
  const Vector3 origin = cluster_origin(c);
  const Vector3& v = velocity_[c];
  double best = never;
  int best_axis = 0;
  for (int a = 0; a < b.dimension; ++a) {
    double t = never;
    if (v[a] > 0) t = std::max(0.0, b.side[a] - radius_ - (origin[a] + high_[c][a])) / v[a];
    else if (v[a] < 0) t = std::max(0.0, origin[a] + low_[c][a] - radius_) / -v[a];
    if (t < best) {
      best = t;
      best_axis = a;
    }
  }
  if (best == never) return;
  queue_.push({now_ + (long double)best, stamp_[c], 0, c, 0, EventKind::wall, std::uint8_t(best_axis), 0});
}

void EventDrivenAggregation::predict_cluster(std::uint32_t c) {
  for (std::uint32_t p = members_.first(c); p != ClusterMembership::none; p = members_.next(p)) {
    predict_crossing(p);
    predict_collisions(p);
  }
  predict_wall(c);
}

}  // namespace aggkit
