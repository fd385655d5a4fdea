#include "particle/ts/time_stepping_aggregation.hpp"

#include <algorithm>
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
      flights_(box, radius, positions),
      detection_(grid_, positions.size()),
      velocity_(velocities.begin(), velocities.end()),
      reflected_(positions.size(), 0),
      before_(positions.size()),
      links_(positions.size()) {
  if (positions.size() != velocities.size() || positions.size() < 2)
    throw InputError("particles.count", std::to_string(positions.size()), "at least 2 particles, one velocity each");
  settings.validate();
  for (std::uint32_t p = 0; p < positions.size(); ++p) cells_.insert(p, grid_.index(grid_.coords_of(flights_.x[p])));
  const auto start_overlaps = detection_.overlaps(spheres(), {});
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
  refresh_live();
}

SphereView TimeSteppingAggregation::spheres() const {
  return {box_, radius_, grid_, cells_, members_, flights_.x, flights_.flown, speed_, longest_flight_, pool_.get()};
}

double TimeSteppingAggregation::time_step() const {
  const double n = double(particles());
  return dt0_ * (2.0 - std::log(double(members_.clusters())) / std::log(n));
}

void TimeSteppingAggregation::reflect(std::uint32_t cluster) {
  if (box_.boundary != Boundary::reflecting) return;
  for (int d = 0; d < box_.dimension; ++d) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::uint32_t p = members_.first(cluster); p != ClusterMembership::none; p = members_.next(p)) {
      lo = std::min(lo, flights_.x[p][d] - radius_);
      hi = std::max(hi, flights_.x[p][d] + radius_);
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
      flights_.x[p][d] += shift;
      flights_.flown[p][d] += shift;
    }
  }
}

bool TimeSteppingAggregation::quiet_flight(double dt) {
  flights_.log(dt, velocity_, members_, pool_.get());
  if (box_.boundary == Boundary::reflecting) {
    refresh_live();
    for (const std::uint32_t c : flights_.near_walls(dt, velocity_, members_, live_, pool_.get())) {
      // Up to date, and the applied flight's test: reflected when a sphere is past a wall.
      flights_.sync(c, velocity_, members_);
      const std::vector<Vector3>& x = flights_.x;
      bool past = false;
      for (std::uint32_t p = members_.first(c); p != ClusterMembership::none && !past; p = members_.next(p))
        for (int d = 0; d < box_.dimension; ++d)
          past = past || x[p][d] - radius_ < 0 || x[p][d] + radius_ > box_.side[d];
      if (past) reflect(c);
      flights_.measure_extent(c, members_);
    }
  }
  if (!jumped_) {
    safe_left_ -= dt;
    return false;
  }
  // A wall moved a cluster by more than its flight: the safe time is over, detect now.
  sync_all();
  safe_left_ = 0;
  flights_.forget_extents();
  locate();
  return true;
}

bool TimeSteppingAggregation::flight(double dt) {
  detection_.fly(dt);
  for (const std::uint32_t c : reflected_list_) reflected_[c] = 0;
  reflected_list_.clear();
  jumped_ = false;
  // A stretch of quiet flights is logged when it is long enough to repay the extents' pass over every
  // sphere and the clusters are few beside the spheres (header); otherwise it is applied flight by flight,
  // which the workers share by spheres. Either way the same run.
  if (settings_.quiet_flights && dt < safe_left_ &&
      (!flights_.empty() || (safe_left_ > logged_stretch * dt && members_.clusters() * logged_clusters <= particles())))
    return quiet_flight(dt);
  sync_all();
  flights_.forget_extents();
  fly_every_sphere(dt);
  // Within the safe time of the last detection pass (header): nothing to detect, cells updated later.
  if (settings_.quiet_flights && !jumped_ && dt < safe_left_) {
    safe_left_ -= dt;
    return false;
  }
  safe_left_ = 0;
  locate();
  return true;
}

void TimeSteppingAggregation::fly_every_sphere(double dt) {
  // One streaming pass: every sphere flies (wrapped on periodic boxes) and, with walls, the clusters with a
  // sphere past one are noted (the test is reflect's own, sphere by sphere); they are then reflected in
  // increasing cluster order, as a walk through every cluster's members per axis would.
  const bool walls = box_.boundary == Boundary::reflecting, periodic = box_.boundary == Boundary::periodic;
  std::vector<Vector3>& x = flights_.x;
  std::vector<Vector3>& flown = flights_.flown;
  std::vector<std::vector<std::uint32_t>> past(thread_count());
  for_ranges(x.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
    for (std::size_t p = from; p < to; ++p) {
      const std::uint32_t c = members_.cluster_of(std::uint32_t(p));
      flown[p] = dt * velocity_[c];
      x[p] = x[p] + flown[p];
      if (periodic) x[p] = box_.wrap(x[p]);
      if (walls)
        for (int d = 0; d < box_.dimension; ++d)
          if (x[p][d] - radius_ < 0 || x[p][d] + radius_ > box_.side[d]) {
            past[w].push_back(c);
            break;
          }
    }
  });
  if (!walls) return;
  std::vector<std::uint32_t>& all = past[0];
  for (std::size_t w = 1; w < past.size(); ++w) all.insert(all.end(), past[w].begin(), past[w].end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  for (const std::uint32_t c : all) reflect(c);
}

void TimeSteppingAggregation::locate() {
  // New cells found in parallel, moved in the (order-dependent) cell list serially.
  // The spheres that changed cell are found in parallel (in increasing order within each worker's range,
  // the ranges in order) and moved serially in that order: the same cell list as a serial walk.
  const std::size_t workers = thread_count();
  std::vector<double> longest(workers, 0.0);
  movers_.resize(workers);
  for_ranges(particles(), [&](std::size_t from, std::size_t to, std::size_t w) {
    // Locals, not longest[w] and movers_[w] in the loop: the workers' slots share cache lines (the
    // vector's storage is kept by swapping it out and back).
    std::vector<std::pair<std::uint32_t, std::uint32_t>> movers;
    movers.swap(movers_[w]);
    movers.clear();
    double most = 0;
    for (std::size_t p = from; p < to; ++p) {
      most = std::max(most, norm(flights_.flown[p]));
      const auto cell = std::uint32_t(grid_.index(grid_.coords_of(flights_.x[p])));
      if (cell != cells_.cell_of(std::uint32_t(p))) movers.push_back({std::uint32_t(p), cell});
    }
    longest[w] = most;
    movers_[w].swap(movers);
  });
  longest_flight_ = *std::max_element(longest.begin(), longest.end());
  for (std::size_t w = 0; w < workers; ++w)
    for (const auto& [p, cell] : movers_[w]) cells_.move(p, cell);
}

double TimeSteppingAggregation::update_speeds() {
  // Live clusters only (O(clusters) per step): link() zeroes the speed of a cluster it absorbs.
  speed_.resize(particles());
  refresh_live();
  const std::vector<std::uint32_t>& alive = live_;
  std::vector<double> fastest(thread_count(), 0.0);
  for_ranges(alive.size(), [&](std::size_t from, std::size_t to, std::size_t w) {
    double top = 0;  // a local maximum: a store to fastest[w] per cluster would alias speed_ for the compiler
    for (std::size_t k = from; k < to; ++k) {
      const std::uint32_t c = alive[k];
      const double s = norm(velocity_[c]);
      speed_[c] = s;
      top = std::max(top, s);
    }
    fastest[w] = top;
  });
  return *std::max_element(fastest.begin(), fastest.end());
}

void TimeSteppingAggregation::step(double dt) {
  if (!(dt > 0)) dt = time_step();
  ++counters_.steps;
  last_mean_ = 0;
  // Substeps: no cluster flies farther than substep_displacement · 2R in one flight, so that a contact is
  // found by the swept test below, and resolved from a shallow overlap, however long the step.
  const double speed = update_speeds();
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
    auto found = detection_.detect(spheres(), settings_.local_detection && !jumped_, fastest(), safe, counters_);
    if (found.empty()) {
      // Nothing moves before the next flight: every sphere's safe time holds that long (each with a margin
      // for the round-off of the positions flown meanwhile).
      safe_left_ = safe;
      continue;
    }
    if (settings_.contact_time) found = merge_binary_contacts(std::move(found), dt / double(substeps));
    resolve(std::move(found));
    update_speeds();
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

void TimeSteppingAggregation::refresh_live() {
  if (!live_stale_) return;
  live_.clear();
  for (std::uint32_t c = 0; c < particles(); ++c)
    if (members_.size(c) > 0) live_.push_back(c);
  live_stale_ = false;
}

double TimeSteppingAggregation::fastest() const {
  double most = 0;
  for (const std::uint32_t c : live_) most = std::max(most, speed_[c]);
  return most;
}

bool TimeSteppingAggregation::at_rest() const {
  const Vector3* first = nullptr;
  double scale = 0;
  for (const std::uint32_t c : live_) scale = std::max(scale, norm(velocity_[c]));
  for (const std::uint32_t c : live_) {
    if (!first) first = &velocity_[c];
    else if (norm(velocity_[c] - *first) > 1e-12 * scale) return false;
  }
  return true;
}

std::vector<Vector3> TimeSteppingAggregation::velocities() const {
  std::vector<Vector3> v(particles());
  for (std::uint32_t p = 0; p < particles(); ++p) v[p] = velocity_[members_.cluster_of(p)];
  return v;
}

std::vector<Vector3> TimeSteppingAggregation::cluster_positions(std::uint32_t cluster) const {
  sync_all();
  // Unwrapped along the links (breadth first from the cluster's first particle).
  std::unordered_map<std::uint32_t, Vector3> placed;
  std::vector<std::uint32_t> queue{members_.first(cluster)};
  placed[queue[0]] = flights_.x[queue[0]];
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
  for (std::uint32_t c = 0; c < particles(); ++c)
    if (members_.size(c) > members_.size(best)) best = c;
  return best;
}

double TimeSteppingAggregation::kinetic_energy() const {
  double e = 0;
  for (std::uint32_t c = 0; c < particles(); ++c)
    if (members_.size(c) > 0) e += 0.5 * double(members_.size(c)) * dot(velocity_[c], velocity_[c]);
  return e;
}

Vector3 TimeSteppingAggregation::momentum() const {
  Vector3 p{0, 0, 0};
  for (std::uint32_t c = 0; c < particles(); ++c)
    if (members_.size(c) > 0) p = p + double(members_.size(c)) * velocity_[c];
  return p;
}

double TimeSteppingAggregation::largest_overlap() const {
  sync_all();
  const double contact2 = 4.0 * radius_ * radius_;
  double worst = 0;
  for (std::uint32_t i = 0; i < particles(); ++i)
    for_near(i, 2.0 * radius_, [&](std::uint32_t j) {
      const Vector3 d = sep(i, j);
      worst = std::max(worst, std::sqrt(std::max(0.0, contact2 - dot(d, d))));
    });
  return worst * scale_;
}

double TimeSteppingAggregation::largest_relative_overlap() const {
  sync_all();
  double worst = 0;
  for (std::uint32_t i = 0; i < particles(); ++i)
    for_near(i, 2.0 * radius_, [&](std::uint32_t j) { worst = std::max(worst, 1.0 - norm(sep(i, j)) / (2.0 * radius_)); });
  return worst;
}

std::size_t TimeSteppingAggregation::links() const {
  std::size_t n = 0;
  for (const auto& l : links_) n += l.size();
  return n / 2;
}

}  // namespace aggkit
