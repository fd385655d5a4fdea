// Contacts of the DEM engine: the pair list with its contact state and tangential history (rebuilt from cell
// lists with a skin), the normal spring–dashpot and Coulomb friction forces per pair, and the walls.
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
#include "particle/dem/dem_inline.hpp"

namespace aggkit {

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

}  // namespace aggkit
