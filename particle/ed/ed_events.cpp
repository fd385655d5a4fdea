// Event handling of the ED engine: sticking (merge) or elastic collisions, broad-phase crossings, pair
// checks, wall contacts.
#include <algorithm>
#include <cmath>

#include "particle/ed/event_driven_aggregation.hpp"

namespace aggkit {

void EventDrivenAggregation::process(const Event& e) {
  switch (e.kind) {
    case EventKind::collision: collide(e.a, e.b); break;
    case EventKind::cell_crossing: cross(e.a, e.level, e.axis, int(e.b), e.direction); break;
    case EventKind::wall: reflect(e.a, e.axis); break;
    case EventKind::pair_check: check_pair(e.a, e.b); break;
  }
}

void EventDrivenAggregation::collide(std::uint32_t i, std::uint32_t j) {
  const std::uint32_t ci = members_.cluster_of(i), cj = members_.cluster_of(j);
  bring_to_now(ci);
  bring_to_now(cj);
  // At contact |Δx| = 2R <= L/3 (CellGrid), so the minimum image is the contact image.
  const Vector3 dx = box_.minimum_image(position(j) - position(i));
  if (sticking_) {
    merge(i, j, dx);
    return;
  }
  // Elastic collision of two singletons of equal mass: the normal components of the velocities swap
  // ([Allen2017, §3.7]): v_i += (Δv·n) n, v_j −= (Δv·n) n with n = Δx/|Δx|, Δv = v_j − v_i.
  const Vector3 n = (1.0 / norm(dx)) * dx;
  const double dvn = dot(velocity_[cj] - velocity_[ci], n);
  velocity_[ci] = velocity_[ci] + dvn * n;
  velocity_[cj] = velocity_[cj] - dvn * n;
  stamp_[ci] = new_stamp();
  stamp_[cj] = new_stamp();
  ++counters_.elastic_collisions;
  predict_cluster(ci);
  predict_cluster(cj);
}

// Particles i and j (clusters ci ≠ cj) touch with x_j − x_i = dx (contact image). The smaller cluster joins
// the larger; its particles are shifted by a whole number of periods if needed so that the merged cluster is
// contiguous, and the merged cluster moves with the momentum-weighted velocity (momentum conservation).
void EventDrivenAggregation::merge(std::uint32_t i, std::uint32_t j, const Vector3& dx) {
  std::uint32_t survivor = members_.cluster_of(i), absorbed = members_.cluster_of(j);
  Vector3 shift = (position(i) + dx) - position(j);  // moves j's cluster next to i
  if (members_.size(absorbed) > members_.size(survivor)) {
    std::swap(survivor, absorbed);
    shift = (position(j) - dx) - position(i);
  }
  const double ms = double(members_.size(survivor)), ma = double(members_.size(absorbed));
  const Vector3 v = (1.0 / (ms + ma)) * (ms * velocity_[survivor] + ma * velocity_[absorbed]);
  const Vector3 displacement = origin_[absorbed] + shift - origin_[survivor];
  unregister_cluster(survivor);
  unregister_cluster(absorbed);
  const std::uint32_t at = alive_at_[absorbed], moved = alive_.back();
  alive_[at] = moved;
  alive_at_[moved] = at;
  alive_.pop_back();
  Vector3& low = low_[survivor];
  Vector3& high = high_[survivor];
  members_.merge(survivor, absorbed, [&](std::uint32_t p) {
    index_.erase(absorbed, p, offset_[p]);
    offset_[p] = offset_[p] + displacement;
    index_.insert(survivor, p, offset_[p]);
    for (int a = 0; a < 3; ++a) {
      low[a] = std::min(low[a], offset_[p][a]);
      high[a] = std::max(high[a], offset_[p][a]);
    }
  });
  velocity_[survivor] = v;
  velocity_[absorbed] = {0, 0, 0};
  stamp_[survivor] = new_stamp();
  stamp_[absorbed] = new_stamp();
  ++counters_.merges;
  register_cluster(survivor);
  predict_cluster(survivor);
}

// A face of cluster c's inflated box crossed a grid line at `level`: its registration there moves by one cell
// along `axis`; clusters in the newly covered cells that were not candidates before become candidates.
void EventDrivenAggregation::cross(std::uint32_t c, int level, int axis, int face, int direction) {
  ++counters_.cell_crossings;
  const HierarchicalGrid::Range old = grid_.range(c, level);
  HierarchicalGrid::Range moved = old;
  (face ? moved.hi : moved.lo)[axis] += direction;
  std::array<std::uint32_t, 8> old_cells, new_cells;
  const int n_old = grid_.cells(level, old, old_cells), n_new = grid_.cells(level, moved, new_cells);
  const bool owner = level == level_[c];
  grid_.place(c, level, moved, owner);
  ++epoch_;
  seen_[c] = epoch_;
  auto meet = [&](std::uint32_t y) {
    if (seen_[y] == epoch_) return;
    seen_[y] = epoch_;
    if (grid_.share_cell(level, old, grid_.range(y, level))) return;  // already candidates
    predict_pair(c, y);
  };
  for (int k = 0; k < n_new; ++k) {
    if (std::find(old_cells.begin(), old_cells.begin() + n_old, new_cells[k]) != old_cells.begin() + n_old) continue;
    for (const auto& e : grid_.owners(level, new_cells[k])) meet(e.cluster);
    if (owner)
      for (const auto& e : grid_.passengers(level, new_cells[k])) meet(e.cluster);
  }
  predict_crossing(c);
}

// The overlap window of candidates x, y opens or closes: predict again while they are still candidates (else
// a later crossing makes them candidates again).
void EventDrivenAggregation::check_pair(std::uint32_t x, std::uint32_t y) {
  ++counters_.pair_checks;
  if (candidates(x, y)) predict_pair(x, y);
}

// The cluster touches the wall across `axis`: that velocity component is reversed for the whole cluster.
// A cluster wedged between both walls (it spans the box along the axis to within round-off) stops along it
// instead of bouncing at infinite frequency. The wall takes the momentum the cluster loses.
void EventDrivenAggregation::reflect(std::uint32_t c, int axis) {
  bring_to_now(c);
  const double m = double(members_.size(c));
  const double v = velocity_[c][axis];
  const double side = box_.side[axis];
  const double gap_after = v < 0 ? side - radius_ - (origin_[c][axis] + high_[c][axis])
                                 : origin_[c][axis] + low_[c][axis] - radius_;
  const bool wedged = gap_after <= overlap_tolerance * radius_;
  velocity_[c][axis] = wedged ? 0.0 : -v;
  wall_impulse_[axis] += (wedged ? 1.0 : 2.0) * m * v;
  stamp_[c] = new_stamp();
  ++counters_.wall_contacts;
  predict_cluster(c);
}

}  // namespace aggkit
