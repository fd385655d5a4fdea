// Construction, the event loop and the queries of the ED engine (predictions in ed_prediction.cpp, event
// handling in ed_events.cpp).
#include "particle/ed/event_driven_aggregation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "analysis/input_error.hpp"
#include "particle/ed/elastic_gas.hpp"
#include "particle/common/cell_grid.hpp"
#include "particle/common/cell_list.hpp"

namespace aggkit {

namespace {
// Member-index cells of about 4 contact distances: a cast then skips empty space in few lookups (each a
// likely cache miss) at the price of more exact pair tests per cell; at least one contact distance, and at
// least 3 cells per periodic axis.
double index_cell_side(const Box& box, double radius) {
  double shortest = box.side[0];
  for (int a = 1; a < box.dimension; ++a) shortest = std::min(shortest, box.side[a]);
  return std::max(2 * radius, std::min(8 * radius, shortest / 3.001));
}
// The engine moves particles in a box: walls or periodic images, never open space.
const Box& walled_box(const Box& box) {
  if (box.boundary == Boundary::open)
    throw InputError("boundary", "\"open\"", "\"periodic\" or \"reflecting\": the event-driven engine needs a box");
  return box;
}
}  // namespace

EventDrivenAggregation::EventDrivenAggregation(const Box& box, double radius, std::span<const Vector3> positions,
                                               std::span<const Vector3> velocities, bool sticking, std::size_t cells)
    : box_(walled_box(box)),
      radius_(radius),
      margin_(1e-6 * radius),
      sticking_(sticking),
      requested_cells_(cells),
      members_(positions.size()),
      index_(box, index_cell_side(box, radius), positions.size()),
      grid_(box, (2 * radius + 2e-6 * radius) * (1 + 1e-8), cells ? cells : positions.size(), positions.size()),
      offset_(positions.size(), Vector3{0, 0, 0}),
      origin_(positions.begin(), positions.end()),
      velocity_(velocities.begin(), velocities.end()),
      low_(positions.size(), Vector3{0, 0, 0}),
      high_(positions.size(), Vector3{0, 0, 0}),
      clock_(positions.size(), 0.0L),
      stamp_(positions.size()),
      level_(positions.size(), 0),
      alive_at_(positions.size()),
      top_at_(positions.size()),
      seen_(positions.size(), 0) {
  if (!(radius > 0) || !std::isfinite(radius)) throw InputError("radius", format_value(radius), "a finite radius > 0");
  if (positions.size() < 1 || positions.size() >= ClusterIndex::none)
    throw InputError("count", std::to_string(positions.size()), "1 <= N < 2^32 - 1");
  if (velocities.size() != positions.size())
    throw InputError("velocities", std::to_string(velocities.size()), "one velocity per particle");
  for (std::uint32_t p = 0; p < positions.size(); ++p) {
    for (int d = 0; d < box.dimension; ++d) {
      const double x = positions[p][d];
      const bool inside = box.boundary == Boundary::periodic ? std::isfinite(x)
                                                              : x >= radius && x <= box.side[d] - radius;
      if (!inside || !std::isfinite(velocities[p][d]))
        throw InputError("position", format_value(x), "finite positions and velocities inside the box (at least R from reflecting walls)");
    }
    for (int d = box.dimension; d < 3; ++d) origin_[p][d] = velocity_[p][d] = 0.0;
    origin_[p] = box.wrap(origin_[p]);
    stamp_[p] = new_stamp();
    index_.insert(p, p, offset_[p]);
    alive_at_[p] = p;
    alive_.push_back(p);
  }
  if (largest_overlap() > overlap_tolerance)
    throw InputError("positions", "overlapping", "initial positions with no two particles closer than 2R");
  // The coarsest populated level first, so that registering the clusters one by one raises nothing.
  for (std::uint32_t p = 0; p < positions.size(); ++p)
    if (const int l = grid_.level_for(extent(p)); l < grid_.top()) populated_ = std::max(populated_, l);
  for (std::uint32_t p = 0; p < positions.size(); ++p) register_cluster(p);
  for (std::uint32_t p = 0; p < positions.size(); ++p) predict_cluster(p, /*higher_only=*/true);
  compact_at_ = std::max<std::size_t>(min_compact, positions.size() / 2);
}

// The elastic stage runs on the elastic gas (particle/ed/elastic_gas.hpp, an order of magnitude faster than
// this engine with sticking off); the engine is then rebuilt from the gas's state with the clock at 0.
void EventDrivenAggregation::thermalize(std::size_t collisions, const std::function<void(std::size_t)>& progress) {
  if (collisions == 0) return;
  if (members_.clusters() != particles())
    throw std::logic_error("thermalize: only before any merge (every cluster a single particle)");
  const auto gas = make_elastic_gas(box(), radius_, positions(), velocities());
  gas->thermalize(collisions, progress);  // std::runtime_error when it cannot finish
  EdCounters counters = counters_;
  counters.elastic_collisions += gas->counters().collisions;
  counters.cell_crossings += gas->counters().cell_crossings;
  counters.wall_contacts += gas->counters().wall_contacts;
  counters.stale_events += gas->counters().stale_events;
  const Vector3 impulse = wall_impulse_ + gas->wall_impulse();
  *this = EventDrivenAggregation(box(), radius_, gas->positions(), gas->velocities(), sticking_, requested_cells_);
  counters_ = counters;
  wall_impulse_ = impulse;
}

EdStop EventDrivenAggregation::advance(double t, std::size_t target_clusters, const std::function<void()>& progress) {
  const long double end = clock_origin_ + (long double)t;
  for (std::uint64_t executed = 1;; ++executed) {
    if (sticking_ && members_.clusters() <= target_clusters) return EdStop::clusters_reached;
    if (!skip_stale_events() || queue_.top().time > end) {
      now_ = std::max(now_, end);
      return EdStop::time_reached;
    }
    execute_next_event();
    if (progress && (executed & 0xffff) == 0) progress();
  }
}

bool EventDrivenAggregation::step() {
  if (!skip_stale_events()) return false;
  execute_next_event();
  return true;
}

bool EventDrivenAggregation::skip_stale_events() {
  while (!queue_.empty() && !valid(queue_.top())) {
    queue_.pop();
    ++counters_.stale_events;
  }
  return !queue_.empty();
}

void EventDrivenAggregation::execute_next_event() {
  const Event e = queue_.top();
  queue_.pop();
  now_ = std::max(now_, e.time);
  process(e);
  maybe_compact();
}

void EventDrivenAggregation::maybe_compact() {
  if (queue_.size() < compact_at_) return;
  // Purged once the queue has grown by half since the last purge: a purge is one sequential pass and a
  // heapify, O(1) per event, against a pop's O(log n) cache misses for each stale event it would meet.
  queue_.compact([this](const Event& e) { return valid(e); });
  compact_at_ = std::max<std::size_t>({min_compact, particles() / 2, queue_.size() + queue_.size() / 2});
}

bool EventDrivenAggregation::valid(const Event& e) const {
  switch (e.kind) {
    case EventKind::collision:
      return stamp_[members_.cluster_of(e.a)] == e.stamp_a && stamp_[members_.cluster_of(e.b)] == e.stamp_b;
    case EventKind::cell_crossing: return stamp_[e.a] == e.stamp_a && e.stamp_b == raises_;
    case EventKind::wall: return stamp_[e.a] == e.stamp_a;
    case EventKind::pair_check: return stamp_[e.a] == e.stamp_a && stamp_[e.b] == e.stamp_b;
  }
  return false;
}

Vector3 EventDrivenAggregation::cluster_origin(std::uint32_t cluster) const {
  const double dt = double(now_ - clock_[cluster]);
  return origin_[cluster] + dt * velocity_[cluster];
}

void EventDrivenAggregation::bring_to_now(std::uint32_t cluster) {
  origin_[cluster] = cluster_origin(cluster);
  clock_[cluster] = now_;
}

Vector3 EventDrivenAggregation::position(std::uint32_t particle) const {
  return cluster_origin(members_.cluster_of(particle)) + offset_[particle];
}

std::vector<Vector3> EventDrivenAggregation::positions() const {
  std::vector<Vector3> x(particles());
  for (std::uint32_t p = 0; p < x.size(); ++p) x[p] = box().wrap(position(p));
  return x;
}

std::vector<Vector3> EventDrivenAggregation::velocities() const {
  std::vector<Vector3> v(particles());
  for (std::uint32_t p = 0; p < v.size(); ++p) v[p] = velocity(p);
  return v;
}

double EventDrivenAggregation::kinetic_energy() const {
  double e = 0;
  for (std::uint32_t c = 0; c < particles(); ++c)
    if (members_.size(c) > 0) e += 0.5 * double(members_.size(c)) * dot(velocity_[c], velocity_[c]);
  return e;
}

Vector3 EventDrivenAggregation::momentum() const {
  Vector3 p{0, 0, 0};
  for (std::uint32_t c = 0; c < particles(); ++c)
    if (members_.size(c) > 0) p = p + double(members_.size(c)) * velocity_[c];
  return p;
}

std::vector<std::size_t> EventDrivenAggregation::cluster_sizes() const {
  const std::vector<std::uint32_t> labels = cluster_labels();
  std::vector<std::size_t> sizes(clusters(), 0);
  for (auto l : labels) ++sizes[l];
  return sizes;
}

std::uint32_t EventDrivenAggregation::largest_cluster() const {
  std::uint32_t best = 0;
  for (std::uint32_t c = 1; c < particles(); ++c)
    if (members_.size(c) > members_.size(best)) best = c;
  return best;
}

std::vector<Vector3> EventDrivenAggregation::cluster_positions(std::uint32_t cluster) const {
  std::vector<Vector3> x;
  x.reserve(members_.size(cluster));
  const Vector3 origin = cluster_origin(cluster);
  for (std::uint32_t p = members_.first(cluster); p != ClusterMembership::none; p = members_.next(p))
    x.push_back(origin + offset_[p]);
  return x;
}

double EventDrivenAggregation::largest_overlap() const {
  const double sigma = 2 * radius_;
  const CellGrid grid(box_, sigma, particles());
  CellList cells(grid.size(), particles());
  std::vector<Vector3> x(particles());
  std::vector<CellCoords> cell(particles());
  for (std::uint32_t p = 0; p < particles(); ++p) {
    x[p] = box_.wrap(position(p));
    cell[p] = grid.coords_of(x[p]);
    cells.insert(p, grid.index(cell[p]));
  }
  // Along periodic axes the image is the one nearest to the stencil offset (>= 3 cells per axis).
  double worst = 0;
  for (std::uint32_t i = 0; i < particles(); ++i) {
    for (const CellCoords& o : grid.stencil()) {
      const auto c = grid.neighbour(cell[i], o);
      if (!c) continue;
      for (std::uint32_t j = cells.first(grid.index(*c)); j != CellList::none; j = cells.next(j)) {
        if (j <= i) continue;
        worst = std::max(worst, 1 - norm(grid.stencil_image(x[j] - x[i], o)) / sigma);
      }
    }
  }
  return worst;
}

}  // namespace aggkit
