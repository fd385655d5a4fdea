#pragma once
// The engine behind elastic_gas.hpp (internal to particle/ed/): the class, specialised at compile time for
// 2-D and 3-D, and its event dynamics — predictions, collisions, cell crossings, wall contacts and the
// event loop's step. Set-up, clock renormalisation and the queries are in elastic_gas.cpp, which holds
// the only instantiations.
#include "particle/ed/elastic_gas.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "analysis/input_error.hpp"
#include "particle/common/huge_page_allocator.hpp"
#include "particle/common/tournament_tree.hpp"

namespace aggkit::elastic_gas_detail {

constexpr double never = std::numeric_limits<double>::infinity();
constexpr std::uint32_t none = 0xffffffffu;

template <int D>
class ElasticGasIn final : public ElasticGas {
 public:
  ElasticGasIn(const Box& box, double radius, std::span<const Vector3> x, std::span<const Vector3> v,
               double particles_per_cell);

  void advance(double t) override;
  void thermalize(std::size_t collisions, const std::function<void(std::size_t pending)>& progress) override;
  bool step() override;

  double time() const override { return double(epoch_ + (long double)now_); }
  std::size_t particles() const override { return state_.size(); }
  const ElasticGasCounters& counters() const override { return counters_; }
  std::uint32_t collisions_of(std::uint32_t particle) const override { return next_[slot_of_[particle]].collisions; }
  std::vector<Vector3> positions() const override;
  std::vector<Vector3> velocities() const override;
  double kinetic_energy() const override;
  Vector3 momentum() const override;
  Vector3 wall_impulse() const override { return wall_impulse_; }
  double collision_virial() const override { return virial_; }
  double largest_overlap() const override;

 private:
  // Position and velocity of a particle at the time `t` of its last event (delayed state).
  struct State {
    double x[D];
    double v[D];
    double t;
    std::uint32_t stamp;  // changes whenever the velocity does
  };
  // Its next events: the earliest predicted collision (partner and the partner's trajectory stamp at the
  // prediction) and the next cell crossing or wall contact along `axis` in `direction`.
  struct Next {
    double collision = never;
    double crossing = never;
    std::uint32_t partner = none;
    std::uint32_t partner_stamp = 0;
    std::int8_t axis = 0;
    std::int8_t direction = 0;
    bool wall = false;
    std::uint32_t collisions = 0;  // so far (thermalisation)
    std::array<int, D> cell{};
  };

  void bring_to_now(std::uint32_t i);
  void predict_crossing(std::uint32_t i);
  // Earliest collision of i with particles in the stencil cells (only those on side `direction` of `axis`
  // when axis >= 0), never with `skip`; improves on next_[i].collision when `keep` is set.
  void predict_collisions(std::uint32_t i, int axis, int direction, std::uint32_t skip, bool keep);
  void nearest_of(std::uint32_t i, const double* xi, const std::uint32_t* candidate,
                  const std::int8_t* candidate_block, int n, const std::int8_t (*image)[D], bool keep);
  void schedule(std::uint32_t i) { tree_.set(i, std::min(next_[i].collision, next_[i].crossing)); }
  void collide(std::uint32_t i, std::uint32_t j);
  void cross(std::uint32_t i);
  // The cell a particle's coming crossing enters (wrapped on periodic axes).
  std::array<int, D> entered_cell(const Next& nx) const {
    std::array<int, D> c = nx.cell;
    const int d = nx.axis;
    c[d] += nx.direction;
    if (c[d] == counts_[d]) c[d] = 0;
    else if (c[d] < 0) c[d] = counts_[d] - 1;
    return c;
  }
  void reflect(std::uint32_t i);
  void count_collision(std::uint32_t i);
  void rebase();  // clock renormalisation and re-sorting of the particles by cell
  // Events between renormalisations: 8 per particle (measured: 2, 8 and 32 run equally fast at N = 10^6;
  // the O(N) re-sort then costs well under 1 % of the run).
  std::uint64_t rebase_interval() const { return 8 * std::uint64_t(state_.size()) + 100000; }

  // Cells are stored in Morton (Z-order) of their coordinates, and particles are sorted by cell, so that
  // the cells and particles of a stencil lie close together in memory.
  std::size_t cell_index(const std::array<int, D>& c) const {
    std::size_t k = 0;
    for (int d = 0; d < D; ++d) k |= spread_[d][std::size_t(c[d])];
    return k;
  }
  // Cell k holds its particles in cell_members_[k * capacity_ ...]: first the count, then the slots, so
  // a cell is one cache line that is read without chasing pointers.
  const std::uint32_t* members(std::size_t cell) const { return &cell_members_[cell * capacity_]; }
  void link(std::uint32_t i, std::size_t cell) {
    std::uint32_t* m = &cell_members_[cell * capacity_];
    if (m[0] + 1 == capacity_) {
      grow_cells();  // places every particle, i included, by next_[·].cell
      return;
    }
    m[++m[0]] = i;
  }
  void unlink(std::uint32_t i, std::size_t cell) {
    std::uint32_t* m = &cell_members_[cell * capacity_];
    std::uint32_t k = 1;
    while (m[k] != i) ++k;
    m[k] = m[m[0]--];
  }
  // The cell tables of the stencil around cell c (only the layer on side `direction` of `axis` when
  // axis >= 0; none past a reflecting wall) and the periodic image of each, −1, 0 or +1 box sides per axis;
  // returns how many. The tables are prefetched.
  static constexpr int stencil_size = D == 2 ? 9 : 27;
  int stencil_cells(const std::array<int, D>& c, int axis, int direction, const std::uint32_t** blocks,
                    std::int8_t (*image)[D]) const;
  void build_morton();
  // The cells (about per_cell particles each, never narrower than a diameter) and the 3^d stencil.
  void build_grid(const Box& box, std::size_t n, double per_cell);
  // The particles in slots in cell order (InputError for a position outside the box or a non-finite value).
  void place(std::span<const Vector3> x, std::span<const Vector3> v);
  void grow_cells();  // doubles the capacity of every cell (a crowded cell), O(cells)
  void fill_cells();
  std::array<int, D> coords_of(const double* x) const {
    std::array<int, D> c;
    for (int d = 0; d < D; ++d) c[d] = std::clamp(int(std::floor(x[d] / cell_side_[d])), 0, counts_[d] - 1);
    return c;
  }

  bool periodic_;
  double side_[D], cell_side_[D];
  int counts_[D];
  double sigma_;  // contact distance 2R
  double radius_;
  std::vector<std::array<int, D>> stencil_;

  template <class T>
  using Array = std::vector<T, HugePageAllocator<T>>;
  Array<State> state_;  // what neighbours read, densely packed
  Array<Next> next_;
  std::size_t cells_ = 1;  // the Morton index range
  std::vector<std::size_t> spread_[D];  // coordinate -> its bits spread to their Morton positions
  std::uint32_t capacity_ = 16;  // count + up to 15 particles per cell; doubled when a cell fills up
  Array<std::uint32_t> cell_members_;
  Array<std::uint32_t> cell_of_;  // per slot: its cell's index (read before its event slot is in cache)
  std::vector<std::uint32_t> id_, slot_of_;  // slot -> particle as given, and back
  TournamentTree tree_;
  std::uint32_t lookahead_[16] = {};  // the queue's subtree winners at the previous event
  std::uint8_t lookahead_age_[16] = {};  // for how many events each has been a winner

  double now_ = 0;
  long double epoch_ = 0;
  std::uint64_t rebase_at_ = 0;
  Vector3 wall_impulse_{0, 0, 0};
  double virial_ = 0;  // Σ r_ij · Δp_i over collisions
  std::size_t thermal_target_ = 0, thermal_pending_ = 0;
  ElasticGasCounters counters_;
};

template <int D>
void ElasticGasIn<D>::bring_to_now(std::uint32_t i) {
  State& s = state_[i];
  const double dt = now_ - s.t;
  for (int d = 0; d < D; ++d) s.x[d] += s.v[d] * dt;
  s.t = now_;
}

template <int D>
int ElasticGasIn<D>::stencil_cells(const std::array<int, D>& c, int axis, int direction, const std::uint32_t** blocks,
                                   std::int8_t (*image)[D]) const {
  int nblocks = 0;
  for (const auto& o : stencil_) {
    if (axis >= 0 && o[axis] != direction) continue;
    std::array<int, D> cn;
    bool outside = false;
    for (int d = 0; d < D; ++d) {
      int k = c[d] + o[d];
      image[nblocks][d] = 0;
      if (k < 0) {
        if (!periodic_) { outside = true; break; }
        k += counts_[d];
        image[nblocks][d] = -1;
      } else if (k >= counts_[d]) {
        if (!periodic_) { outside = true; break; }
        k -= counts_[d];
        image[nblocks][d] = 1;
      }
      cn[d] = k;
    }
    if (outside) continue;
    blocks[nblocks] = members(cell_index(cn));
    __builtin_prefetch(blocks[nblocks]);
    ++nblocks;
  }
  return nblocks;
}

template <int D>
void ElasticGasIn<D>::predict_crossing(std::uint32_t i) {
  const State& s = state_[i];
  const double dt0 = now_ - s.t;
  Next& nx = next_[i];
  nx.crossing = never;
  for (int d = 0; d < D; ++d) {
    const double vd = s.v[d];
    if (vd == 0) continue;
    const double xd = s.x[d] + vd * dt0;
    const int c = nx.cell[d];
    const bool last = c == counts_[d] - 1, first = c == 0;
    double t;
    bool wall = false;
    if (vd > 0) {
      if (!periodic_ && last) {
        t = (side_[d] - radius_ - xd) / vd;
        wall = true;
      } else {
        t = ((c + 1) * cell_side_[d] - xd) / vd;
      }
    } else {
      if (!periodic_ && first) {
        t = (xd - radius_) / -vd;
        wall = true;
      } else {
        t = (xd - c * cell_side_[d]) / -vd;
      }
    }
    t = std::max(t, 0.0);
    if (now_ + t < nx.crossing) {
      nx.crossing = now_ + t;
      nx.axis = std::int8_t(d);
      nx.direction = std::int8_t(vd > 0 ? 1 : -1);
      nx.wall = wall;
    }
  }
}

template <int D>
void ElasticGasIn<D>::predict_collisions(std::uint32_t i, int axis, int direction, std::uint32_t skip, bool keep) {
  const State& si = state_[i];
  double xi[D];
  const double dti = now_ - si.t;
  for (int d = 0; d < D; ++d) xi[d] = si.x[d] + si.v[d] * dti;
  Next& nx = next_[i];
  const std::array<int, D>& c = nx.cell;
  // The run is bound by memory latency, not arithmetic: first the stencil cells are located and fetched,
  // then their particles' states, so that the cache misses overlap; the roots are computed last.
  const std::uint32_t* blocks[stencil_size];
  std::int8_t image[stencil_size][D];
  const int nblocks = stencil_cells(c, axis, direction, blocks, image);
  constexpr int most = 512;
  std::uint32_t candidate[most];
  std::int8_t candidate_block[most];
  int n = 0;
  for (int b = 0; b < nblocks; ++b) {
    const std::uint32_t* m = blocks[b];
    for (std::uint32_t k = 1, count = m[0]; k <= count; ++k) {
      const std::uint32_t j = m[k];
      if (j == i || j == skip) continue;
      __builtin_prefetch(&state_[j]);
      if (n == most) {  // only in pathologically crowded cells: evaluate what is gathered so far
        nearest_of(i, xi, candidate, candidate_block, n, image, keep);
        keep = true;
        n = 0;
      }
      candidate[n] = j;
      candidate_block[n] = std::int8_t(b);
      ++n;
    }
  }
  nearest_of(i, xi, candidate, candidate_block, n, image, keep);
}

// Earliest contact of i (at xi now) among the candidates; stored in next_[i] when earlier than what is kept.
template <int D>
void ElasticGasIn<D>::nearest_of(std::uint32_t i, const double* xi, const std::uint32_t* candidate,
                                 const std::int8_t* candidate_block, int n, const std::int8_t (*image)[D],
                                 bool keep) {
  const State& si = state_[i];
  Next& nx = next_[i];
  double best = keep ? nx.collision - now_ : never;
  std::uint32_t partner = keep ? nx.partner : none;
  const double sigma2 = sigma_ * sigma_;
  for (int q = 0; q < n; ++q) {
    const std::uint32_t j = candidate[q];
    const State& sj = state_[j];
    const std::int8_t* img = image[candidate_block[q]];
    const double dtj = now_ - sj.t;
    double dx[D], dv[D], b = 0;
    for (int d = 0; d < D; ++d) {
      dx[d] = sj.x[d] + sj.v[d] * dtj + img[d] * side_[d] - xi[d];
      dv[d] = sj.v[d] - si.v[d];
      b += dx[d] * dv[d];
    }
    if (b >= 0) continue;  // receding (collision_time.hpp)
    double dx2 = 0, dv2 = 0;
    for (int d = 0; d < D; ++d) {
      dx2 += dx[d] * dx[d];
      dv2 += dv[d] * dv[d];
    }
    const double cc = dx2 - sigma2;
    double t;
    if (cc <= 0) {
      t = 0;  // touching by round-off while approaching
    } else {
      const double disc = b * b - dv2 * cc;
      if (disc < 0) continue;
      t = cc / (-b + std::sqrt(disc));  // cancellation-free smaller root (collision_time.hpp)
    }
    if (t < best) {
      best = t;
      partner = j;
    }
  }
  if (partner == none || best == never) {
    nx.collision = never;
    nx.partner = none;
    return;
  }
  nx.collision = now_ + best;
  if (partner != nx.partner || !keep) nx.partner_stamp = state_[partner].stamp;
  nx.partner = partner;
}

template <int D>
void ElasticGasIn<D>::count_collision(std::uint32_t i) {
  if (++next_[i].collisions == thermal_target_ && thermal_target_ > 0) --thermal_pending_;
}

// Elastic collision of equal masses: the normal components of the velocities are exchanged
// ([Allen2017, §3.7]): v_i += (Δv·n) n, v_j −= (Δv·n) n.
template <int D>
void ElasticGasIn<D>::collide(std::uint32_t i, std::uint32_t j) {
  bring_to_now(i);
  bring_to_now(j);
  State& a = state_[i];
  State& b = state_[j];
  double n[D], r2 = 0;
  for (int d = 0; d < D; ++d) {
    double dx = b.x[d] - a.x[d];
    if (periodic_) dx -= side_[d] * std::nearbyint(dx / side_[d]);  // contact: |dx| = 2R <= L/3
    n[d] = dx;
    r2 += dx * dx;
  }
  const double inv = 1.0 / std::sqrt(r2);
  double dvn = 0;
  for (int d = 0; d < D; ++d) {
    n[d] *= inv;
    dvn += (b.v[d] - a.v[d]) * n[d];
  }
  for (int d = 0; d < D; ++d) {
    a.v[d] += dvn * n[d];
    b.v[d] -= dvn * n[d];
  }
  virial_ -= r2 * inv * dvn;  // (x_a − x_b) · Δp_a = −|r| n · (Δv·n) n, > 0 for an approaching pair
  ++a.stamp;
  ++b.stamp;
  ++counters_.collisions;
  count_collision(i);
  count_collision(j);
  // Two particles in free flight cannot meet again after separating: the partner is skipped, which also
  // keeps a grazing contact (Δv·n ≈ 0) from being found again at t = 0 through round-off.
  for (std::uint32_t p : {i, j}) {
    predict_crossing(p);
    predict_collisions(p, -1, 0, p == i ? j : i, false);
    schedule(p);
  }
}

template <int D>
void ElasticGasIn<D>::cross(std::uint32_t i) {
  bring_to_now(i);
  Next& nx = next_[i];
  const int d = nx.axis, dir = nx.direction;
  std::array<int, D>& c = nx.cell;
  unlink(i, cell_of_[i]);
  State& s = state_[i];
  const std::array<int, D> entered = entered_cell(nx);
  if (entered[d] != c[d] + dir) s.x[d] -= dir * side_[d];  // through a periodic face
  c = entered;
  // On the face between the cells exactly (round-off of the crossing time must not leave it outside).
  s.x[d] = dir > 0 ? c[d] * cell_side_[d] : (c[d] + 1) * cell_side_[d];
  cell_of_[i] = std::uint32_t(cell_index(c));
  link(i, cell_of_[i]);
  ++counters_.cell_crossings;
  predict_crossing(i);
  predict_collisions(i, d, dir, none, true);  // the cells already in the stencil were predicted before
  schedule(i);
}

template <int D>
void ElasticGasIn<D>::reflect(std::uint32_t i) {
  bring_to_now(i);
  State& s = state_[i];
  const int d = next_[i].axis;
  s.x[d] = s.v[d] > 0 ? side_[d] - radius_ : radius_;
  wall_impulse_[d] += 2 * s.v[d];
  s.v[d] = -s.v[d];
  ++s.stamp;
  ++counters_.wall_contacts;
  predict_crossing(i);
  predict_collisions(i, -1, 0, none, false);
  schedule(i);
}

template <int D>
bool ElasticGasIn<D>::step() {
  const double t = tree_.top_time();
  if (t == never) return false;
  const std::uint32_t i = tree_.top_slot();
  now_ = std::max(now_, t);
  __builtin_prefetch(members(cell_of_[i]));
  Next& nx = next_[i];
  if (nx.crossing <= nx.collision) {
    if (nx.wall) reflect(i);
    else cross(i);
  } else if (state_[nx.partner].stamp == nx.partner_stamp) {
    collide(i, nx.partner);
  } else {
    // The partner changed course since the prediction: only i needs a new prediction (its crossing stands).
    ++counters_.stale_events;
    predict_collisions(i, -1, 0, none, false);
    schedule(i);
  }
  if (counters_.events() >= rebase_at_) rebase();
  // Memory latency bounds the run: start fetching what the next events will read first.
  // The next few events are most likely among the 16 subtree winners of the queue: fetching their slots
  // ahead measured +12 % in 2-D at N = 10^6 (depths 4–6 alike, 2–3 no gain; 3-D within the noise).
  // In stages, one per event for which a winner stays a winner, the second needing what the first fetched:
  // its slot, state, cell index and queue block; then its cell table and, for a crossing, the destination
  // cell's (+5–20 % in 2-D). Three quarters of the events have been winners for 4 events or more, yet
  // further stages — the tables it will predict against, then their particles' states — measured no gain
  // within the ±15 % run-to-run scatter (bench/results/log/ed-ballistic-aggregation.md, event-driven aggregation: the elastic gas).
  int k = 0;
  tree_.for_each_subtree_winner(4, [&](std::uint32_t j) {
    std::uint8_t& age = lookahead_age_[k];
    age = lookahead_[k] == j ? std::uint8_t(std::min(age + 1, 2)) : std::uint8_t(0);
    lookahead_[k++] = j;
    if (age == 0) {
      __builtin_prefetch(&next_[j]);
      __builtin_prefetch(&state_[j]);
      __builtin_prefetch(&cell_of_[j]);
      tree_.prefetch(j);
    } else if (age == 1) {
      __builtin_prefetch(members(cell_of_[j]));
      const Next& nj = next_[j];
      if (nj.crossing <= nj.collision && !nj.wall)  // a cell crossing: its destination cell too
        __builtin_prefetch(members(cell_index(entered_cell(nj))));
    }
  });
  return true;
}

}  // namespace aggkit::elastic_gas_detail
