#include "particle/dem/dem.hpp"

#include "particle/dem/direct_gravity.hpp"
#include "particle/dem/gravity_tree.hpp"
#include "particle/dem/dem_inline.hpp"

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

bool implicit_dashpot_wanted(const DemSettings& settings, double lightest_mass) {
  const double x = settings.dt * (settings.damping_per_mass + settings.damping / (0.5 * lightest_mass));
  return settings.friction == 0 && x > 0 && x > settings.implicit_dashpot_above;
}

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
    implicit_dashpot_ = implicit_dashpot_wanted(settings_, *std::min_element(mass_.begin(), mass_.end()));
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

void Dem::gravity_forces(std::vector<Vector3>& out) {
  if (settings_.tree) {
    tree_gravity(x_, mass_, settings_.G, softening_, settings_.opening_angle, pool_.get(), out);
    return;
  }
  direct_gravity(x_, mass_, settings_.G, softening_, pool_.get(), out);
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
