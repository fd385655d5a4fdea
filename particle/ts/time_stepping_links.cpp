// Links and their resolution in the time-stepping engine: clusters merged with momentum-weighted velocities,
// binary contacts merged at their contact time, and the damped Arrow–Hurwicz minimisation of the clusters
// that changed [Degond2024, Sec. 3, steps (b)-(d)].
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "particle/ts/time_stepping_aggregation.hpp"

namespace aggkit {

namespace {

// job(k) for each of `merged` contact-time merges, on the pool's workers (none: in order on this thread).
template <class Job>
void for_merges(WorkerPool* pool, std::size_t merged, Job&& job) {
  if (!pool) {
    for (std::size_t k = 0; k < merged; ++k) job(k);
    return;
  }
  // Runs of consecutive merges claimed by the workers: one claim per merge (most move a few spheres) would
  // cost more than the moves.
  const std::size_t runs = std::min(merged, 8 * pool->threads());
  pool->run(runs, [&](std::size_t r) {
    for (std::size_t k = merged * r / runs; k < merged * (r + 1) / runs; ++k) job(k);
  });
}

}  // namespace

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
  if (cb < speed_.size()) speed_[cb] = 0;  // absorbed: no longer a live cluster (update_speeds skips it)
  live_stale_ = true;
  detection_.changed(ca);  // its spheres are examined at the next pass (local detection)
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
    const Vector3 raw = flights_.x[j] - flights_.x[i];
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
  for (std::size_t k = 0; k < order.size(); ++k) problem.x[k] = scale_ * flights_.x[order[k]];
  const DahaResult result = aggkit::minimise(problem, settings_.daha);
  for (std::size_t k = 0; k < free; ++k) {
    const Vector3 to = (1.0 / scale_) * problem.x[k];
    largest_move = std::max(largest_move, norm(to - flights_.x[order[k]]));
    flights_.x[order[k]] = to;
  }
  moved.assign(order.begin(), order.begin() + std::ptrdiff_t(free));
  return result;
}

std::vector<TimeSteppingAggregation::Collision> TimeSteppingAggregation::binary_collisions(const SpherePairs& found,
                                                                                         SpherePairs& rest) {
  const double contact2 = 4.0 * radius_ * radius_;
  // The fraction τ ∈ [0, 1] of the flight at which a swept pair first touched: |d0 + τ w| = 2R with
  // d0 = d − w the separation before the flight.
  auto first_touch = [&](std::uint32_t i, std::uint32_t j) {
    const Vector3 d = sep(i, j), w = flights_.flown[j] - flights_.flown[i], d0 = d - w;
    const double a = dot(w, w), b = 2.0 * dot(d0, w), c = dot(d0, d0) - contact2;
    if (c <= 0 || a <= 0) return 0.0;
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0) return 1.0;
    return std::clamp((-b - std::sqrt(disc)) / (2.0 * a), 0.0, 1.0);
  };
  // Partner clusters of each cluster over the found pairs; a pair of clusters that only met each other
  // (and no wall) in this flight is a binary collision. The distinct cluster pairs, sorted by lower then
  // higher cluster; per cluster, its partner and whether it has more than one (scratch arrays of N, reset
  // for the clusters touched).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> meets;
  meets.reserve(found.size());
  for (const auto& [i, j] : found) {
    const std::uint32_t ci = members_.cluster_of(i), cj = members_.cluster_of(j);
    meets.emplace_back(std::min(ci, cj), std::max(ci, cj));
  }
  std::sort(meets.begin(), meets.end());
  meets.erase(std::unique(meets.begin(), meets.end()), meets.end());
  constexpr std::uint32_t nobody = ClusterMembership::none, several = ClusterMembership::none - 1;
  partner_.resize(particles(), nobody);
  for (const auto& [ci, cj] : meets) {
    partner_[ci] = partner_[ci] == nobody ? cj : several;
    partner_[cj] = partner_[cj] == nobody ? ci : several;
  }
  auto binary = [&](std::uint32_t ci, std::uint32_t cj) {
    return partner_[ci] == cj && partner_[cj] == ci && !reflected_[ci] && !reflected_[cj];
  };
  std::vector<Collision> collisions;
  for (const auto& pr : found) {
    const std::uint32_t ci = members_.cluster_of(pr.first), cj = members_.cluster_of(pr.second);
    if (!binary(ci, cj)) {
      rest.push_back(pr);
      continue;
    }
    collisions.push_back({std::min(ci, cj), first_touch(pr.first, pr.second), pr});
  }
  for (const auto& [ci, cj] : meets) partner_[ci] = partner_[cj] = nobody;
  // Earliest touching pair of each binary collision (found is sorted: the first of equal times wins).
  std::stable_sort(collisions.begin(), collisions.end(), [](const Collision& a, const Collision& b) { return a.key < b.key; });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < collisions.size(); ++k) {
    if (kept > 0 && collisions[kept - 1].key == collisions[k].key) {
      if (collisions[k].tau < collisions[kept - 1].tau) collisions[kept - 1] = collisions[k];
    } else {
      collisions[kept++] = collisions[k];
    }
  }
  collisions.resize(kept);
  return collisions;
}

std::vector<std::vector<std::uint32_t>> TimeSteppingAggregation::to_recheck(const std::vector<std::uint32_t>& survivor,
                                                                           double farthest, WorkerPool* pool) const {
  // Near re-check (header): only the moved spheres that can now touch a sphere that was in another
  // cluster at the pass. Not after a round cap hit (a cluster may then hold overlaps deeper than the
  // same-cluster tolerance, which a full re-check of the moved spheres would link again). Per merged
  // cluster, on the workers.
  const bool near = settings_.near_recheck && detection_.bounds() && counters_.round_cap_hits == 0;
  const double reach = 2.0 * radius_ * (1.0 + 1e-6) + farthest;
  std::vector<std::vector<std::uint32_t>> recheck(survivor.size());
  for_merges(pool, survivor.size(), [&](std::size_t k) {
    std::vector<std::uint32_t> mine;  // a local: the slots of recheck share cache lines
    for (std::uint32_t p = members_.first(survivor[k]); p != ClusterMembership::none; p = members_.next(p))
      if (!near || detection_.nearest_bound(p) < reach + norm(before_[p])) mine.push_back(p);
    recheck[k] = std::move(mine);
  });
  return recheck;
}

std::vector<std::uint32_t> TimeSteppingAggregation::move_to_contact(const std::vector<Collision>& collisions, double dt) {
  // Back to the contact, merged there, and on with the merged velocity for the rest of the flight: an
  // isolated collision is then exactly ED's, and the minimisation is left the simultaneous ones. The merges
  // (velocities and membership) go first, in key order; then every merged cluster's spheres are moved, the
  // clusters spread over the workers (disjoint spheres); then the clusters now past a wall are reflected and
  // the cell list is updated, in key order again: the same run on any number of threads.
  const std::size_t merged = collisions.size();
  std::vector<std::uint32_t> survivor(merged);
  std::vector<Vector3> onward(merged);
  std::size_t spheres = 0;
  for (std::size_t k = 0; k < merged; ++k) {
    const auto [i, j] = collisions[k].pair;
    link(i, j);
    survivor[k] = members_.cluster_of(i);
    onward[k] = ((1.0 - collisions[k].tau) * dt) * velocity_[survivor[k]];
    spheres += members_.size(survivor[k]);
    ++counters_.contact_time_merges;
  }
  std::vector<Vector3>& x = flights_.x;
  const bool periodic = box_.boundary == Boundary::periodic;  // wrap and minimum image: identities otherwise
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<char> inside(merged, 1);
  auto move_back = [&](std::size_t k) {
    const double tau = collisions[k].tau;
    Vector3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
    for (std::uint32_t p = members_.first(survivor[k]); p != ClusterMembership::none; p = members_.next(p)) {
      before_[p] = x[p];
      x[p] = x[p] - (1.0 - tau) * flights_.flown[p];
      x[p] = x[p] + onward[k];
      for (int d = 0; d < box_.dimension; ++d) {
        lo[d] = std::min(lo[d], x[p][d] - radius_);
        hi[d] = std::max(hi[d], x[p][d] + radius_);
      }
    }
    for (int d = 0; d < box_.dimension; ++d) inside[k] = inside[k] && lo[d] >= 0 && hi[d] <= box_.side[d];
  };
  // Per collision: the spheres whose cell changed (with the new cell) and the largest displacement from
  // where the pass saw a sphere.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> changed(merged);
  std::vector<double> farthest_of(merged, 0.0);
  auto relocate = [&](std::size_t k) {
    double most = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> to;  // a local: the slots of changed share cache lines
    for (std::uint32_t p = members_.first(survivor[k]); p != ClusterMembership::none; p = members_.next(p)) {
      if (periodic) x[p] = box_.wrap(x[p]);
      const auto cell = std::uint32_t(grid_.index(grid_.coords_of(x[p])));
      if (cell != cells_.cell_of(p)) to.push_back({p, cell});
      before_[p] = periodic ? box_.minimum_image(x[p] - before_[p]) : x[p] - before_[p];
      most = std::max(most, norm(before_[p]));
    }
    changed[k] = std::move(to);
    farthest_of[k] = most;
  };
  WorkerPool* const pool = pool_ && merged > 1 && spheres >= parallel_merge ? pool_.get() : nullptr;
  auto each = [&](auto&& job) { for_merges(pool, merged, job); };
  each(move_back);
  for (std::size_t k = 0; k < merged; ++k)
    if (!inside[k]) reflect(survivor[k]);
  each(relocate);
  double farthest = 0;
  for (std::size_t k = 0; k < merged; ++k) farthest = std::max(farthest, farthest_of[k]);
  const std::vector<std::vector<std::uint32_t>> recheck = to_recheck(survivor, farthest, pool);
  std::vector<std::uint32_t> moved;
  for (std::size_t k = 0; k < merged; ++k) {
    for (const auto& [p, cell] : changed[k]) cells_.move(p, cell);
    moved.insert(moved.end(), recheck[k].begin(), recheck[k].end());
  }
  return moved;
}

SpherePairs TimeSteppingAggregation::merge_binary_contacts(SpherePairs found, double dt) {
  SpherePairs rest;
  const std::vector<std::uint32_t> moved = move_to_contact(binary_collisions(found, rest), dt);
  counters_.rechecked_spheres += moved.size();
  // What the merged clusters now overlap is left to the minimisation, with the other contacts.
  // (None left: nothing to re-check; an empty list would ask for a pass over every sphere.)
  if (!moved.empty())
    for (const auto& pr : detection_.overlaps(spheres(), moved)) rest.push_back(pr);
  std::sort(rest.begin(), rest.end());
  rest.erase(std::unique(rest.begin(), rest.end()), rest.end());
  return rest;
}

std::vector<TimeSteppingAggregation::Group> TimeSteppingAggregation::groups_of(const SpherePairs& new_links) const {
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
  return groups;
}

std::vector<std::uint32_t> TimeSteppingAggregation::settle(const std::vector<Group>& groups,
                                                           const std::vector<DahaResult>& results,
                                                           const std::vector<std::vector<std::uint32_t>>& moved,
                                                           const std::vector<double>& moves) {
  std::vector<Vector3>& x = flights_.x;
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
      x[p] = box_.wrap(x[p]);
      if (box_.boundary == Boundary::reflecting)
        for (int d = 0; d < box_.dimension; ++d) outside = outside || x[p][d] < radius_ || x[p][d] > box_.side[d] - radius_;
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
    const std::size_t cell = grid_.index(grid_.coords_of(x[p]));
    if (cell != cells_.cell_of(p)) cells_.move(p, cell);
  }
  return check;
}

void TimeSteppingAggregation::resolve(SpherePairs new_links) {
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
    const std::vector<Group> groups = groups_of(new_links);
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
    new_links = detection_.overlaps(spheres(), settle(groups, results, moved, moves));
  }
}

}  // namespace aggkit
