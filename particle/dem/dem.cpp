#include "particle/dem/dem.hpp"

#include "particle/dem/direct_gravity.hpp"
#include "particle/dem/gravity_tree.hpp"

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "particle/common/simd_clones.hpp"

namespace aggkit {

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b) std::swap(a, b);
  parent[a] = b;  // the smaller index is the root: deterministic
}

}  // namespace

Dem::Dem(const Box& box, ParticleStart start, const DemSettings& settings) : box_(box), settings_(settings) {
  if (box.dimension != 3) throw std::invalid_argument("dem: 3-D only");
  const std::size_t n = start.size();
  if (n < 1 || start.velocities.size() != n || start.radii.size() != n || start.masses.size() != n)
    throw std::invalid_argument("dem: positions, velocities, radii and masses must have one entry per particle");
  if (!(settings.dt > 0) || !std::isfinite(settings.dt)) throw std::invalid_argument("dem: dt must be finite and > 0");
  if (settings.gravity && box.boundary == Boundary::periodic) throw std::invalid_argument("dem: no gravity in a periodic box");
  for (std::size_t i = 0; i < n; ++i)
    if (!(start.radii[i] > 0) || !(start.masses[i] > 0)) throw std::invalid_argument("dem: radii and masses must be > 0");
  x_ = std::move(start.positions);
  v_ = std::move(start.velocities);
  radius_ = std::move(start.radii);
  mass_ = std::move(start.masses);
  periodic_ = box_.boundary == Boundary::periodic;
  inverse_mass_.resize(n);
  inverse_inertia_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    inverse_mass_[i] = 1 / mass_[i];
    inverse_inertia_[i] = 1 / (0.4 * mass_[i] * radius_[i] * radius_[i]);  // 2/5 m R²
  }
  for (int d = 0; d < 3; ++d) side_[d] = box_.side[d], half_side_[d] = 0.5 * box_.side[d];
  heaviest_first_ = mass_;
  std::sort(heaviest_first_.begin(), heaviest_first_.end(), std::greater<>());
  for (std::size_t i = 1; i < n; ++i) heaviest_first_[i] += heaviest_first_[i - 1];
  min_radius_ = *std::min_element(radius_.begin(), radius_.end());
  max_radius_ = *std::max_element(radius_.begin(), radius_.end());
  softening_ = settings.softening >= 0 ? settings.softening : 1e-3 * min_radius_;
  if (settings_.force_threads < 1) settings_.force_threads = 1;
  if (settings_.force_threads > 1) pool_ = std::make_unique<WorkerPool>(settings_.force_threads);
  f_.assign(n, {0, 0, 0});
  u_ = v_;
  if (settings_.friction < 0) throw std::invalid_argument("dem: friction must be >= 0");
  w_.assign(n, {0, 0, 0});
  w_pred_.assign(n, {0, 0, 0});
  torque_.assign(n, {0, 0, 0});
  q_.assign(n, {1, 0, 0, 0});
  if (settings_.gravity_substeps < 1) settings_.gravity_substeps = 1;
  {
    // The largest γ_n dt/m* of a pair (m* ≥ m_min/2) or a wall (m* = m_i ≥ m_min).
    const double lightest = *std::min_element(mass_.begin(), mass_.end());
    const double x = settings_.dt * (settings_.damping_per_mass + settings_.damping / (0.5 * lightest));
    implicit_dashpot_ = settings_.friction == 0 && x > 0 && x > settings_.implicit_dashpot_above;
    if (implicit_dashpot_ && !(settings_.stiffness_per_mass > 0 || settings_.stiffness > 0))
      throw std::invalid_argument("dem: the implicit dashpot needs a stiffness > 0");
  }
  if (settings_.gravity && settings_.gravity_substeps > 1) {
    gravity_.assign(n, {0, 0, 0});
    gravity_forces(gravity_);
  }
  first_evaluation_ = true;  // overlaps present at the start have no onset within a step; they count as collisions
  compute_forces();
  first_evaluation_ = false;
}

inline Vector3 Dem::separation(std::size_t i, std::size_t j) const {
  Vector3 d = x_[j] - x_[i];
  if (periodic_)  // positions lie in [0, L): |d| < L, one image shift at most
    for (int k = 0; k < 3; ++k) d[k] += d[k] > half_side_[k] ? -side_[k] : d[k] < -half_side_[k] ? side_[k] : 0.0;
  return d;
}

template <class Visit>
void Dem::for_each_near_pair(double range, std::size_t parts, Visit&& visit) const {
  const std::size_t n = x_.size();
  // Grid region per axis: the box for periodic/reflecting, the particles' bounding box when open.
  Vector3 lo{0, 0, 0}, extent{0, 0, 0};
  const bool periodic = box_.boundary == Boundary::periodic;
  if (box_.boundary == Boundary::open) {
    Vector3 hi = x_[0];
    lo = x_[0];
    for (const Vector3& p : x_)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
    extent = hi - lo;
  } else {
    extent = box_.side;
  }
  double h = range;
  std::array<std::int64_t, 3> cells{1, 1, 1};
  for (int attempt = 0; attempt < 64; ++attempt) {
    double total = 1;
    for (int d = 0; d < 3; ++d) {
      cells[d] = std::max<std::int64_t>(1, std::int64_t(std::floor(extent[d] / h)));
      if (periodic && cells[d] < 3) cells[d] = 1;  // fewer than 3 cells: one cell, so no neighbour is met twice
      total *= double(cells[d]);
    }
    if (total <= std::max(27.0, 4.0 * double(n))) break;
    h *= std::cbrt(total / std::max(27.0, 4.0 * double(n))) * 1.01;  // sparse cloud: coarser cells
  }
  std::array<double, 3> inverse{};
  for (int d = 0; d < 3; ++d) inverse[d] = extent[d] > 0 ? double(cells[d]) / extent[d] : 0.0;
  const std::size_t total = std::size_t(cells[0] * cells[1] * cells[2]);
  std::vector<std::uint32_t> cell_of(n), start(total + 1, 0), order(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t c[3];
    for (int d = 0; d < 3; ++d) c[d] = std::clamp<std::int64_t>(std::int64_t(std::floor((x_[i][d] - lo[d]) * inverse[d])), 0, cells[d] - 1);
    cell_of[i] = std::uint32_t((c[2] * cells[1] + c[1]) * cells[0] + c[0]);
    ++start[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < total; ++c) start[c + 1] += start[c];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[fill[cell_of[i]]++] = std::uint32_t(i);
  }
  // Each pair of particles once: the pairs within a cell, then those with the 13 neighbour cells of the
  // forward half of the stencil (the other 13 meet this cell from their side). With periodic images every
  // axis has 1 or at least 3 cells, so no neighbour cell is met twice.
  std::vector<std::array<int, 3>> forward;
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const int off[3] = {ox, oy, oz};
        bool used = true;
        for (int d = 0; d < 3; ++d) used = used && !(cells[d] == 1 && off[d] != 0);
        // forward: the first non-zero offset (z, then y, then x) is positive
        const int lead = oz != 0 ? oz : oy != 0 ? oy : ox;
        if (used && lead > 0) forward.push_back({ox, oy, oz});
      }
  // Slabs of z cells as parts (on the worker pool when there is one).
  parts = std::clamp<std::size_t>(parts, 1, std::size_t(cells[2]));
  auto slab = [&](std::size_t part) {
    const std::int64_t z0 = std::int64_t(part) * cells[2] / std::int64_t(parts), z1 = std::int64_t(part + 1) * cells[2] / std::int64_t(parts);
    for (std::int64_t cz = z0; cz < z1; ++cz)
      for (std::int64_t cy = 0; cy < cells[1]; ++cy)
        for (std::int64_t cx = 0; cx < cells[0]; ++cx) {
          const std::size_t c = std::size_t((cz * cells[1] + cy) * cells[0] + cx);
          if (start[c] == start[c + 1]) continue;
          for (std::uint32_t a = start[c]; a < start[c + 1]; ++a)
            for (std::uint32_t b = a + 1; b < start[c + 1]; ++b) visit(part, std::min(order[a], order[b]), std::max(order[a], order[b]));
          const std::int64_t own[3] = {cx, cy, cz};
          for (const std::array<int, 3>& off : forward) {
            std::int64_t other[3];
            bool skip = false;
            for (int d = 0; d < 3 && !skip; ++d) {
              other[d] = own[d] + off[d];
              if (periodic) other[d] = (other[d] + cells[d]) % cells[d];
              else if (other[d] < 0 || other[d] >= cells[d]) skip = true;
            }
            if (skip) continue;
            const std::size_t c2 = std::size_t((other[2] * cells[1] + other[1]) * cells[0] + other[0]);
            for (std::uint32_t a = start[c]; a < start[c + 1]; ++a)
              for (std::uint32_t b = start[c2]; b < start[c2 + 1]; ++b) visit(part, std::min(order[a], order[b]), std::max(order[a], order[b]));
          }
        }
  };
  if (pool_ && parts > 1) pool_->run(parts, slab);
  else
    for (std::size_t part = 0; part < parts; ++part) slab(part);
}

template <class Job>
void Dem::parallel(std::size_t jobs, Job&& job) {
  if (pool_) pool_->run(jobs, job);
  else
    for (std::size_t k = 0; k < jobs; ++k) job(k);
}

void Dem::compute_forces() {
  if (!forces_cleared_) {
    std::fill(f_.begin(), f_.end(), Vector3{0, 0, 0});
    if (settings_.friction > 0) std::fill(torque_.begin(), torque_.end(), Vector3{0, 0, 0});
  }
  forces_cleared_ = false;
  contact_forces();
  if (settings_.gravity && settings_.gravity_substeps == 1) gravity_forces(f_);
  if (implicit_dashpot_) integrate_dashpots();
}

void Dem::integrate_dashpots() {
  // The contacts as the pair loop left them (springs in f_, dashpots pending), in pair order, then the walls.
  std::vector<DashpotContact> dashpots;
  std::vector<double> distance;  // centre distance of each pair (virial)
  for (const auto& buffer : contact_buffers_)
    for (const ContactForce& c : buffer) {
      if (c.dashpot == 0) continue;
      const double spring = norm(c.normal_force);
      dashpots.push_back({c.i, c.j, (1 / spring) * c.normal_force, c.dashpot, spring, mass_[c.i] * mass_[c.j] / (mass_[c.i] + mass_[c.j])});
      distance.push_back(c.virial / spring);
    }
  const std::size_t pairs = dashpots.size();
  dashpots.insert(dashpots.end(), wall_dashpots_.begin(), wall_dashpots_.end());
  if (dashpots.empty()) return;
  DashpotSolve stats;
  const std::vector<double> total = implicit_dashpot_forces(dashpots, mass_, v_, f_, settings_.dt, stats);
  counters_.dashpot_solves += stats.solves;
  counters_.dashpot_iterations += stats.iterations;
  double virial = 0;
  for (std::size_t c = 0; c < dashpots.size(); ++c) {
    const DashpotContact& k = dashpots[c];
    const Vector3 change = (total[c] - k.spring) * k.normal;  // on j, −it on i
    f_[k.j] = f_[k.j] + change;
    if (c < pairs) {
      f_[k.i] = f_[k.i] - change;
      virial += distance[c] * (total[c] - k.spring);
    } else {
      wall_force_ = wall_force_ + change;
    }
  }
  if (!first_evaluation_) counters_.virial_integral += settings_.dt * virial;
}

void Dem::rebuild_pairs() {
  // The pairs within 2 R_max + tolerance + skin, sorted by (i, j) by a counting sort on i; each keeps the state
  // it had in the old list (both sorted: one merge). A pair of the old list missing from the new one has
  // separated beyond the skin: an open episode with an overlap ends there as a rebound.
  const std::size_t n = x_.size();
  const double tolerance = settings_.contact_tolerance * min_radius_;
  const double skin = 0.2 * max_radius_;
  // The search in slabs (fixed by N; on the worker pool), each into its own buffer: the sorted list below
  // does not depend on the split.
  const std::size_t parts = std::clamp<std::size_t>(n / 2048, 1, 64);
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> found(parts);
  for (auto& part : found) part.reserve((pairs_.size() + pairs_.size() / 8) / parts + 16);
  for_each_near_pair(2 * max_radius_ + tolerance + skin, parts, [&](std::size_t part, std::uint32_t i, std::uint32_t j) {
    const Vector3 d = separation(i, j);
    const double reach = radius_[i] + radius_[j] + tolerance + skin;
    if (dot(d, d) < reach * reach) found[part].push_back({i, j});
  });
  std::vector<std::uint32_t> start(n + 1, 0);
  std::size_t pairs = 0;
  for (const auto& part : found) {
    pairs += part.size();
    for (const auto& pair : part) ++start[pair.first + 1];
  }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  PairList list;
  list.first.resize(pairs);
  list.second.resize(pairs);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (const auto& part : found)
      for (const auto& [i, j] : part) {
        const std::uint32_t slot = fill[i]++;
        list.first[slot] = i;
        list.second[slot] = j;
      }
  }
  parallel(parts, [&](std::size_t part) {
    for (std::size_t i = part * n / parts; i < (part + 1) * n / parts; ++i)
      std::sort(list.second.begin() + start[i], list.second.begin() + start[i + 1]);
  });
  list.state.assign(pairs, 0);
  if (settings_.friction > 0) list.history.assign(pairs, Vector3{0, 0, 0});
  std::size_t old = 0;
  for (std::size_t p = 0; p < list.size(); ++p) {
    const auto key = [](std::uint32_t i, std::uint32_t j) { return (std::uint64_t(i) << 32) | j; };
    const std::uint64_t now = key(list.first[p], list.second[p]);
    for (; old < pairs_.size() && key(pairs_.first[old], pairs_.second[old]) < now; ++old)
      if ((pairs_.state[old] & in_graph) && (pairs_.state[old] & episode_overlapped)) ++counters_.rebounds;
    if (old < pairs_.size() && key(pairs_.first[old], pairs_.second[old]) == now) {
      list.state[p] = pairs_.state[old];
      if (settings_.friction > 0) list.history[p] = pairs_.history[old];
      ++old;
    }
  }
  for (; old < pairs_.size(); ++old)
    if ((pairs_.state[old] & in_graph) && (pairs_.state[old] & episode_overlapped)) ++counters_.rebounds;
  pairs_ = std::move(list);
  pairs_built_at_ = x_;
  ++counters_.list_builds;
}

void Dem::contact_forces() {
  // Rebuilt once some particle has moved more than skin/2 since the last build (two such particles close a
  // gap of at most skin): step() checks while it moves them.
  if (moved_beyond_skin_ || pairs_built_at_.size() != x_.size()) rebuild_pairs();
  moved_beyond_skin_ = false;
  // The pairs in fixed chunks (their number from the list's length only), each computing its contacts'
  // forces into its own buffer, possibly on several threads; the forces are then added in pair order, so
  // the sums do not depend on the thread count.
  // Chunks of ~1000 pairs: contacts cluster, so several chunks per thread keep the threads evenly loaded.
  const std::size_t chunks = std::clamp<std::size_t>(pairs_.size() / 1024, 1, 64);
  contact_buffers_.resize(chunks);
  std::vector<ContactTotals> chunk_totals(chunks);
  parallel(chunks, [&](std::size_t c) {
    chunk_totals[c] = pair_forces(c * pairs_.size() / chunks, (c + 1) * pairs_.size() / chunks, contact_buffers_[c]);
  });
  const bool friction = settings_.friction > 0;
  double virial = 0;
  graph_edges_ = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    const ContactTotals& t = chunk_totals[c];
    counters_.collisions += t.collisions;
    counters_.rebounds += t.rebounds;
    counters_.clamped_contacts += t.clamped;
    counters_.max_overlap = std::max(counters_.max_overlap, t.max_overlap);
    counters_.max_friction_ratio = std::max(counters_.max_friction_ratio, t.max_friction_ratio);
    graph_edges_ += t.graph_edges;
    for (const ContactForce& f : contact_buffers_[c]) {
      f_[f.i] = f_[f.i] - f.normal_force;
      f_[f.j] = f_[f.j] + f.normal_force;
      virial += f.virial;
      if (!friction) continue;
      f_[f.i] = f_[f.i] + f.tangential;
      f_[f.j] = f_[f.j] - f.tangential;
      torque_[f.i] = torque_[f.i] + f.torque_i;
      torque_[f.j] = torque_[f.j] + f.torque_j;
    }
  }
  if (!first_evaluation_) counters_.virial_integral += settings_.dt * virial;
  wall_forces();
}

Dem::ContactTotals Dem::pair_forces(std::size_t begin, std::size_t end, std::vector<ContactForce>& contacts) {
  ContactTotals totals;
  contacts.clear();
  const double limit = settings_.overlap_limit * min_radius_;
  const double tolerance = settings_.contact_tolerance * min_radius_;
  const bool friction = settings_.friction > 0;
  const bool damped = settings_.damping_per_mass != 0 || settings_.damping != 0;
  for (std::size_t p = begin; p < end; ++p) {
    const std::uint32_t i = pairs_.first[p], j = pairs_.second[p];
    const Vector3 d = separation(i, j);
    const double r2 = dot(d, d);
    const double reach = radius_[i] + radius_[j];
    const std::uint8_t before = pairs_.state[p];
    if (r2 >= (reach + tolerance) * (reach + tolerance)) {
      // Outside the contact graph's distance: an episode that overlapped ends as a rebound.
      // (Most pairs of the list: nothing to write when they were already out.)
      if (before == 0) continue;
      if ((before & in_graph) && (before & episode_overlapped)) ++totals.rebounds;
      pairs_.state[p] = 0;
      if (friction && (before & overlapping)) pairs_.history[p] = {0, 0, 0};  // zero unless overlapping
      continue;
    }
    ++totals.graph_edges;
    const double r = std::sqrt(r2);
    const double overlap = reach - r;
    std::uint8_t state = in_graph | ((before & in_graph) ? (before & episode_overlapped) : 0);
    if (overlap <= 0 || r == 0) {
      pairs_.state[p] = state;
      if (friction && (before & overlapping)) pairs_.history[p] = {0, 0, 0};  // the history is dropped with the contact
      continue;
    }
    pairs_.state[p] = state | overlapping | episode_overlapped;
    const bool onset = !(before & overlapping);
    if (onset) ++totals.collisions;  // a pair that starts to overlap (at the start: every overlapping pair)
    totals.max_overlap = std::max(totals.max_overlap, overlap / min_radius_);
    double spring = overlap;
    if (overlap > limit) {
      spring = limit;
      ++totals.clamped;
    }
    const Vector3 normal = (1.0 / r) * d;  // from i to j [Trivino2025, eq. 5]
    const double reduced = mass_[i] * mass_[j] / (mass_[i] + mass_[j]);  // [Trivino2025, eq. 2]
    const double stiffness = pair_stiffness(reduced);
    double force = stiffness * spring;
    double dashpot = 0;
    if (damped || friction) {
      const double separating = dot(u_[j] - u_[i], normal);
      // The dashpot switches on with a jump at the onset of a contact. Verlet weighs each force sample by dt
      // (the cell t ± dt/2), so a contact that began s·dt before its first sample would get a dashpot impulse
      // off by (s − ½) dt γ v: a first-order error in the restitution that depends on the onset phase. The
      // first sample's dashpot is weighted by s + ½ instead (s from the overlap over the approach speed).
      double weight = 1;
      if (onset && !first_evaluation_) {
        const double approach = -separating;
        weight = 0.5 + (approach > 0 ? std::min(1.0, overlap / (approach * settings_.dt)) : 1.0);
      }
      // [Trivino2025, eq. 6], set to zero where it would attract; the implicit dashpot adds it later.
      if (implicit_dashpot_) dashpot = weight * pair_damping(reduced);
      else force = std::max(0.0, force - weight * pair_damping(reduced) * separating);
    }
    ContactForce& c = contacts.emplace_back();
    c.i = i, c.j = j;
    c.virial = r * force;  // r_ij · F_ij = (−d) · (−force n)
    c.normal_force = force * normal;  // on j; −it on i [Trivino2025, eq. 7]
    c.dashpot = dashpot;
    if (friction) tangential_force(i, j, pairs_.history[p], normal, overlap, force, stiffness, totals, c);
  }
  return totals;
}

void Dem::wall_forces() {
  // Walls: the same law with the wall as an infinite mass (m* = m_i).
  wall_force_ = {0, 0, 0};
  wall_dashpots_.clear();
  if (box_.boundary != Boundary::reflecting) return;
  const double limit = settings_.overlap_limit * min_radius_;
  for (std::size_t i = 0; i < x_.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      for (int side = 0; side < 2; ++side) {
        const double overlap = side == 0 ? radius_[i] - x_[i][d] : x_[i][d] + radius_[i] - box_.side[d];
        if (overlap <= 0) continue;
        counters_.max_overlap = std::max(counters_.max_overlap, overlap / min_radius_);
        double spring = overlap;
        if (overlap > limit) {
          spring = limit;
          ++counters_.clamped_contacts;
        }
        const double separating = side == 0 ? u_[i][d] : -u_[i][d];
        double force = pair_stiffness(mass_[i]) * spring;
        if (implicit_dashpot_) {  // the dashpot added by integrate_dashpots()
          Vector3 into{0, 0, 0};
          into[d] = side == 0 ? 1.0 : -1.0;
          wall_dashpots_.push_back({DashpotContact::wall, std::uint32_t(i), into, pair_damping(mass_[i]), force, mass_[i]});
        } else {
          force = std::max(0.0, force - pair_damping(mass_[i]) * separating);
        }
        const double signed_force = side == 0 ? force : -force;
        f_[i][d] += signed_force;
        wall_force_[d] += signed_force;
      }
    }
}

std::vector<std::uint32_t> Dem::component_parents() const {
  std::vector<std::uint32_t> parent(x_.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::size_t p = 0; p < pairs_.size(); ++p)
    if (pairs_.state[p] & in_graph) unite(parent, pairs_.first[p], pairs_.second[p]);
  return parent;
}

double Dem::largest_cluster_mass_fraction() const {
  std::vector<std::uint32_t> parent = component_parents();
  std::vector<double> component(x_.size(), 0.0);
  double total = 0, largest = 0;
  for (std::uint32_t i = 0; i < x_.size(); ++i) {
    const std::uint32_t root = find_root(parent, i);
    component[root] += mass_[i];
    total += mass_[i];
    largest = std::max(largest, component[root]);
  }
  return largest / total;
}

bool Dem::largest_cluster_reaches(double fraction) const {
  // A component with e edges has at most e + 1 particles, so at most the mass of the e + 1 heaviest; the
  // margin covers the round-off of the other summation order.
  const std::size_t most = std::min<std::size_t>(graph_edges_ + 1, x_.size());
  if (heaviest_first_[most - 1] < fraction * heaviest_first_.back() * (1 - 1e-9)) return false;
  return largest_cluster_mass_fraction() >= fraction;
}

namespace {
Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
}  // namespace

void Dem::tangential_force(std::uint32_t i, std::uint32_t j, Vector3& history, const Vector3& normal, double overlap, double normal_force,
                           double normal_stiffness, ContactTotals& totals, ContactForce& out) const {
  // Lever arms R − δ/2 that add up to the centre distance: the torques then balance the tangential forces'
  // moment exactly and the angular momentum about any point is kept.
  const double arm_i = radius_[i] - 0.5 * overlap, arm_j = radius_[j] - 0.5 * overlap;
  // Sliding velocity of j's surface relative to i's at the contact point (predicted velocities, as the dashpot).
  const Vector3 relative = (u_[j] - u_[i]) - cross(arm_i * w_pred_[i] + arm_j * w_pred_[j], normal);
  const Vector3 sliding = relative - dot(relative, normal) * normal;
  // The stored displacement, created with the contact, rotated into the current tangent plane (length kept).
  Vector3 xi = history;  // zero for a new contact: nothing to rotate
  if (xi[0] != 0 || xi[1] != 0 || xi[2] != 0) {
    const double length = norm(xi);
    xi = xi - dot(xi, normal) * normal;
    const double projected = norm(xi);
    xi = projected > 0 ? (length / projected) * xi : Vector3{0, 0, 0};
  }
  if (!first_evaluation_) xi = xi + settings_.dt * sliding;
  // Tangential spring k_t = ratio · k_n, truncated at the Coulomb limit μ F_n (the history with it).
  const double kt = settings_.tangential_stiffness_ratio * normal_stiffness;
  Vector3 force = kt * xi;  // on i (dragged along j's sliding), −force on j
  const double limit = settings_.friction * normal_force;
  double size = norm(force);
  if (size > limit) {
    force = size > 0 ? (limit / size) * force : Vector3{0, 0, 0};
    xi = (1 / kt) * force;
    size = norm(force);
  }
  if (limit > 0) totals.max_friction_ratio = std::max(totals.max_friction_ratio, size / limit);
  history = xi;
  out.tangential = force;  // on i; −force on j
  out.torque_i = cross(arm_i * normal, force);
  out.torque_j = cross(arm_j * normal, force);  // (−a_j n) × (−F)
}

void Dem::gravity_forces(std::vector<Vector3>& out) {
  if (settings_.tree) {
    tree_gravity(x_, mass_, settings_.G, softening_, settings_.opening_angle, pool_.get(), out);
    return;
  }
  direct_gravity(x_, mass_, settings_.G, softening_, pool_.get(), out);
}

namespace {

// The translational half of step()'s first pass over particles [begin, end) on flat arrays (3 doubles per
// particle): kick by F dt/2m, drift, periodic wrap by one side, the dashpot's velocity, forces cleared, and
// the Verlet list's displacement check. Branch-free, so that it vectorises; the arithmetic of each particle
// is that of the plain loop.
struct Drift {
  double *x, *v, *f, *u;
  const double *inverse_mass, *built;  // built: positions at the list's build (x itself when there are none)
  double dt, half, moved_limit;
  bool periodic;
  double side[3], half_side[3];
};
constexpr unsigned drift_moved = 1, drift_fault = 2;  // some particle beyond skin/2; a wrap by one side failed

AGGKIT_SIMD_CLONES unsigned drift_chunk(const Drift& a, std::size_t begin, std::size_t end) {
  double* const x = a.x;
  double* const v = a.v;
  double* const f = a.f;
  double* const u = a.u;
  const double* const inverse_mass = a.inverse_mass;
  const double* const built = a.built;
  const double dt = a.dt, half = a.half, limit = a.moved_limit;
  // Without periodic images the shifts are zero and the bounds infinite: the selects then do nothing.
  const bool periodic = a.periodic;
  const double inf = std::numeric_limits<double>::infinity();
  const double shift0 = periodic ? a.side[0] : 0.0, shift1 = periodic ? a.side[1] : 0.0, shift2 = periodic ? a.side[2] : 0.0;
  const double side0 = periodic ? a.side[0] : inf, side1 = periodic ? a.side[1] : inf, side2 = periodic ? a.side[2] : inf;
  const double low = periodic ? 0.0 : -inf;
  const double half0 = periodic ? a.half_side[0] : inf, half1 = periodic ? a.half_side[1] : inf, half2 = periodic ? a.half_side[2] : inf;
  int moved = 0, fault = 0;
#pragma omp simd reduction(| : moved, fault)
  for (std::size_t i = begin; i < end; ++i) {
    const double hm = half * inverse_mass[i];
    double d2 = 0;
    int bad = 0;
    // One component: shift, side, half side of its axis.
    auto component = [&](std::size_t e, double shift, double side, double half_side) {
      const double kick = hm * f[e];
      const double vk = v[e] + kick;
      v[e] = vk;
      double c = x[e] + dt * vk;
      c += c < 0 ? shift : c >= side ? -shift : 0.0;
      bad |= c >= low && c < side ? 0 : 1;
      double d = c - built[e];
      d += d > half_side ? -shift : d < -half_side ? shift : 0.0;
      d2 += d * d;
      x[e] = c;
      u[e] = vk + kick;  // the dashpot's estimate of v(t + dt): second order
      f[e] = 0;
    };
    component(3 * i, shift0, side0, half0);
    component(3 * i + 1, shift1, side1, half1);
    component(3 * i + 2, shift2, side2, half2);
    moved |= d2 > limit ? int(drift_moved) : 0;
    fault |= bad ? int(drift_fault) : 0;
  }
  return unsigned(moved | fault);
}

// The rotational half (friction): ω kicked by the torque's half step, its prediction for the tangential
// springs, torques cleared, and q ← exp(½ ω dt) q (rotation by |ω| dt about ω, space frame), renormalised.
// For a half angle a below 1e-3 (the usual case) cos a and sin(a)/|ω| from their series (next terms
// < 1e-19) and the renormalisation by one Newton step from 1 (|p|² − 1 is round-off), branch-free and
// vectorised; larger angles are left to rotate_large (cos, sin, a square root). ω = 0 leaves q as it is.
struct Spin {
  double *w, *w_pred, *torque;
  std::array<double, 4>* q;
  const double* inverse_inertia;
  double dt, half;
};

std::array<double, 4> rotated(const std::array<double, 4>& r, const std::array<double, 4>& q) {
  return {r[0] * q[0] - r[1] * q[1] - r[2] * q[2] - r[3] * q[3], r[0] * q[1] + r[1] * q[0] + r[2] * q[3] - r[3] * q[2],
          r[0] * q[2] - r[1] * q[3] + r[2] * q[0] + r[3] * q[1], r[0] * q[3] + r[1] * q[2] - r[2] * q[1] + r[3] * q[0]};
}

constexpr double small_half_angle2 = 1e-6;

AGGKIT_SIMD_CLONES bool spin_chunk(const Spin& a, std::size_t begin, std::size_t end) {
  double* const w = a.w;
  double* const w_pred = a.w_pred;
  double* const torque = a.torque;
  double* const q = a.q[0].data();
  const double* const inverse_inertia = a.inverse_inertia;
  const double dt = a.dt, half = a.half;
  int large = 0;
#pragma omp simd reduction(| : large)
  for (std::size_t i = begin; i < end; ++i) {
    const double hi = half * inverse_inertia[i];  // I = 2/5 m R²
    const std::size_t e = 3 * i;
    const double spin0 = hi * torque[e], spin1 = hi * torque[e + 1], spin2 = hi * torque[e + 2];
    const double w0 = w[e] + spin0, w1 = w[e + 1] + spin1, w2c = w[e + 2] + spin2;
    w[e] = w0, w[e + 1] = w1, w[e + 2] = w2c;
    w_pred[e] = w0 + spin0, w_pred[e + 1] = w1 + spin1, w_pred[e + 2] = w2c + spin2;
    torque[e] = 0, torque[e + 1] = 0, torque[e + 2] = 0;
    const double w2 = w0 * w0 + w1 * w1 + w2c * w2c;
    const double a2 = 0.25 * w2 * dt * dt;
    large |= int(w2 > 0) & int(a2 >= small_half_angle2);
    constexpr double c2 = 1.0 / 2, c4 = 1.0 / 24, s2 = 1.0 / 6, s4 = 1.0 / 120;  // multiplications, not divisions
    const double c = 1 - a2 * c2 + a2 * a2 * c4;
    const double sw = half * (1 - a2 * s2 + a2 * a2 * s4);  // sin(a)/|ω|
    // Otherwise (ω = 0, or a large angle left to rotate_large) r = (1, 0, 0, 0) and no renormalisation:
    // p = q exactly. Selects on values, not on the stores, so that the loop vectorises.
    const bool rotate = int(w2 > 0) & int(a2 < small_half_angle2);
    const std::size_t o = 4 * i;
    const double r0 = rotate ? c : 1.0, r1 = rotate ? sw * w0 : 0.0, r2 = rotate ? sw * w1 : 0.0, r3 = rotate ? sw * w2c : 0.0;
    const double q0 = q[o], q1 = q[o + 1], q2 = q[o + 2], q3 = q[o + 3];
    const double p0 = r0 * q0 - r1 * q1 - r2 * q2 - r3 * q3, p1 = r0 * q1 + r1 * q0 + r2 * q3 - r3 * q2,
                 p2 = r0 * q2 - r1 * q3 + r2 * q0 + r3 * q1, p3 = r0 * q3 + r1 * q2 - r2 * q1 + r3 * q0;
    const double length2 = p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3;
    const double inverse_length = rotate ? 1.5 - 0.5 * length2 : 1.0;
    q[o] = p0 * inverse_length, q[o + 1] = p1 * inverse_length, q[o + 2] = p2 * inverse_length, q[o + 3] = p3 * inverse_length;
  }
  return large != 0;
}

void rotate_large(const Spin& a, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    const double wx = a.w[3 * i], wy = a.w[3 * i + 1], wz = a.w[3 * i + 2];
    const double w2 = wx * wx + wy * wy + wz * wz;
    const double a2 = 0.25 * w2 * a.dt * a.dt;
    if (!(w2 > 0) || a2 < small_half_angle2) continue;
    const double angle = std::sqrt(a2);
    const double sw = std::sin(angle) * a.half / angle;
    std::array<double, 4> p = rotated({std::cos(angle), sw * wx, sw * wy, sw * wz}, a.q[i]);
    const double inverse_length = 1 / std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]);
    for (double& c : p) c *= inverse_length;
    a.q[i] = p;
  }
}

// The closing half kick of step(): v += F dt/2m over particles [begin, end) (flat arrays); returns Σ m|v|²
// (a vectorised sum: its order is fixed by the range).
AGGKIT_SIMD_CLONES double kick(double* v, const double* f, const double* inverse_mass, const double* mass, double half, std::size_t begin,
                               std::size_t end) {
  double sum = 0;
#pragma omp simd reduction(+ : sum)
  for (std::size_t i = begin; i < end; ++i) {
    const double h = half * inverse_mass[i];
    const std::size_t e = 3 * i;
    const double v0 = v[e] + h * f[e], v1 = v[e + 1] + h * f[e + 1], v2 = v[e + 2] + h * f[e + 2];
    v[e] = v0, v[e + 1] = v1, v[e + 2] = v2;
    sum += mass[i] * (v0 * v0 + v1 * v1 + v2 * v2);
  }
  return sum;
}

}  // namespace

void Dem::step() {
  const double dt = settings_.dt, half = 0.5 * dt;
  const std::size_t n = x_.size();
  const std::size_t substeps = settings_.gravity ? settings_.gravity_substeps : 1;
  // Impulse splitting (r-RESPA): gravity kicks by K dt/2 at both ends of every K contact steps.
  if (substeps > 1 && counters_.steps % substeps == 0)
    for (std::size_t i = 0; i < n; ++i) v_[i] = v_[i] + (0.5 * double(substeps) * dt * inverse_mass_[i]) * gravity_[i];
  // One pass: kick, drift, wrap, the dashpot's prediction, the list's displacement check, rotation, and the
  // force and torque arrays cleared for the next evaluation (the arrays are streamed once).
  // Fixed chunks of particles (their number from N only), possibly on several threads.
  const bool friction = settings_.friction > 0;
  const double skin = 0.2 * max_radius_, moved_limit = 0.25 * skin * skin;
  const std::size_t chunks = std::clamp<std::size_t>(n / 2048, 1, 64);
  std::vector<char> moved_in(chunks, 0);
  parallel(chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * n / chunks, end = (chunk + 1) * n / chunks;
    const bool check = pairs_built_at_.size() == n;
    Drift drift{x_[0].data(), v_[0].data(), f_[0].data(), u_[0].data(), inverse_mass_.data(),
                check ? pairs_built_at_[0].data() : x_[0].data(), dt, half, moved_limit, periodic_, {}, {}};
    for (int k = 0; k < 3; ++k) drift.side[k] = side_[k], drift.half_side[k] = half_side_[k];
    const unsigned flags = drift_chunk(drift, begin, end);
    if (flags & drift_fault)  // more than a box side in one step, or −tiny + L = L: the exact wrap
      for (std::size_t i = begin; i < end; ++i) {
        Vector3& xi = x_[i];
        for (int k = 0; k < 3; ++k)
          if (!(xi[k] >= 0 && xi[k] < side_[k])) xi[k] = box_.wrap(xi)[k];
      }
    bool moved = check && (flags & drift_moved);
    if (check && (flags & drift_fault) && !moved)
      for (std::size_t i = begin; i < end && !moved; ++i) {
        Vector3 d = x_[i] - pairs_built_at_[i];
        for (int k = 0; k < 3; ++k) d[k] += d[k] > half_side_[k] ? -side_[k] : d[k] < -half_side_[k] ? side_[k] : 0.0;
        moved = dot(d, d) > moved_limit;
      }
    moved_in[chunk] = moved;
    if (!friction) return;
    Spin spin{w_[0].data(), w_pred_[0].data(), torque_[0].data(), q_.data(), inverse_inertia_.data(), dt, half};
    if (spin_chunk(spin, begin, end)) rotate_large(spin, begin, end);
  });
  moved_beyond_skin_ = std::find(moved_in.begin(), moved_in.end(), 1) != moved_in.end();
  forces_cleared_ = true;
  wall_impulse_ = wall_impulse_ - half * wall_force_;
  compute_forces();
  std::vector<double> twice_kinetic(chunks, 0.0);  // Σ m|v|² per chunk, added in chunk order
  parallel(chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * n / chunks, end = (chunk + 1) * n / chunks;
    twice_kinetic[chunk] = kick(v_[0].data(), f_[0].data(), inverse_mass_.data(), mass_.data(), half, begin, end);
    if (friction) kick(w_[0].data(), torque_[0].data(), inverse_inertia_.data(), mass_.data(), half, begin, end);  // ω; sum unused
  });
  for (double sum : twice_kinetic) counters_.kinetic_integral += dt * sum;
  wall_impulse_ = wall_impulse_ - half * wall_force_;
  ++counters_.steps;
  if (substeps > 1 && counters_.steps % substeps == 0) {
    std::fill(gravity_.begin(), gravity_.end(), Vector3{0, 0, 0});
    gravity_forces(gravity_);
    for (std::size_t i = 0; i < n; ++i) v_[i] = v_[i] + (0.5 * double(substeps) * dt * inverse_mass_[i]) * gravity_[i];
  }
  time_ = double(counters_.steps) * dt;  // no accumulated round-off
}

double Dem::adhesive_fraction() const {
  std::uint64_t open = 0;
  for (std::uint8_t state : pairs_.state) open += (state & in_graph) && (state & episode_overlapped) ? 1 : 0;
  return open + counters_.rebounds > 0 ? double(open) / double(open + counters_.rebounds) : std::numeric_limits<double>::quiet_NaN();
}

Vector3 Dem::momentum() const {
  Vector3 p{0, 0, 0};
  for (std::size_t i = 0; i < x_.size(); ++i) p = p + mass_[i] * v_[i];
  return p;
}

double Dem::kinetic_energy() const {
  double k = 0;
  for (std::size_t i = 0; i < x_.size(); ++i)
    k += 0.5 * mass_[i] * dot(v_[i], v_[i]) + 0.2 * mass_[i] * radius_[i] * radius_[i] * dot(w_[i], w_[i]);
  return k;
}

Vector3 Dem::angular_momentum() const {
  Vector3 l{0, 0, 0};
  for (std::size_t i = 0; i < x_.size(); ++i)
    l = l + mass_[i] * cross(x_[i], v_[i]) + (0.4 * mass_[i] * radius_[i] * radius_[i]) * w_[i];
  return l;
}

double Dem::gravitational_energy() const {
  if (!settings_.gravity) return 0;
  const double eps = softening_;
  double u = 0;
  for (std::size_t i = 0; i < x_.size(); ++i)
    for (std::size_t j = i + 1; j < x_.size(); ++j) {
      const double r = norm(separation(i, j));
      // ∫_r^∞ G m m / (s² + ε²) ds = (G m m / ε)(π/2 − atan(r/ε))
      u -= settings_.G * mass_[i] * mass_[j] * (eps > 0 ? (M_PI / 2 - std::atan(r / eps)) / eps : 1 / r);
    }
  return u;
}

double Dem::elastic_energy() const {
  const double limit = settings_.overlap_limit * min_radius_;
  auto spring_energy = [&](double k, double overlap) {
    return overlap <= limit ? 0.5 * k * overlap * overlap : 0.5 * k * limit * limit + k * limit * (overlap - limit);
  };
  double e = 0;
  for_each_near_pair(2 * max_radius_, 1, [&](std::size_t, std::uint32_t i, std::uint32_t j) {
    const double overlap = radius_[i] + radius_[j] - norm(separation(i, j));
    if (overlap > 0) e += spring_energy(pair_stiffness(mass_[i] * mass_[j] / (mass_[i] + mass_[j])), overlap);
  });
  for (std::size_t p = 0; p < pairs_.history.size(); ++p) {  // tangential springs (zero unless overlapping)
    const std::size_t i = pairs_.first[p], j = pairs_.second[p];
    const double kt = settings_.tangential_stiffness_ratio * pair_stiffness(mass_[i] * mass_[j] / (mass_[i] + mass_[j]));
    e += 0.5 * kt * dot(pairs_.history[p], pairs_.history[p]);
  }
  if (box_.boundary == Boundary::reflecting)
    for (std::size_t i = 0; i < x_.size(); ++i)
      for (int d = 0; d < 3; ++d) {
        const double low = radius_[i] - x_[i][d], high = x_[i][d] + radius_[i] - box_.side[d];
        if (low > 0) e += spring_energy(pair_stiffness(mass_[i]), low);
        if (high > 0) e += spring_energy(pair_stiffness(mass_[i]), high);
      }
  return e;
}

std::vector<std::uint32_t> Dem::cluster_labels() const {
  std::vector<std::uint32_t> parent = component_parents(), labels(x_.size());
  std::vector<std::uint32_t> label_of_root(x_.size(), UINT32_MAX);
  std::uint32_t next = 0;
  for (std::uint32_t i = 0; i < x_.size(); ++i) {
    const std::uint32_t root = find_root(parent, i);
    if (label_of_root[root] == UINT32_MAX) label_of_root[root] = next++;
    labels[i] = label_of_root[root];
  }
  return labels;
}

}  // namespace aggkit
