// The elastic hard-sphere gas of elastic_gas.hpp: set-up, clock renormalisation with re-sorting, the run
// loops and the queries (event dynamics in elastic_gas_engine.hpp).
#include "particle/ed/elastic_gas_engine.hpp"

namespace aggkit {

namespace elastic_gas_detail {

template <int D>
ElasticGasIn<D>::ElasticGasIn(const Box& box, double radius, std::span<const Vector3> x, std::span<const Vector3> v,
                              double particles_per_cell)
    : periodic_(box.boundary == Boundary::periodic), sigma_(2 * radius), radius_(radius) {
  box.validate();
  if (box.boundary == Boundary::open)
    throw InputError("boundary", "\"open\"", "\"periodic\" or \"reflecting\": the elastic gas needs a box");
  if (!(radius > 0) || !std::isfinite(radius)) throw InputError("radius", format_value(radius), "a finite radius > 0");
  if (x.empty() || x.size() >= none) throw InputError("count", std::to_string(x.size()), "1 <= N < 2^32 - 1");
  if (v.size() != x.size()) throw InputError("velocities", std::to_string(v.size()), "one velocity per particle");
  if (!(particles_per_cell >= 0) || !std::isfinite(particles_per_cell))
    throw InputError("particles_per_cell", format_value(particles_per_cell), "a finite number >= 0 (0: default)");
  // Default (bench/results/log/ed-ballistic-aggregation.md, elastic gas): about 2 particles per cell in 2-D and 1 in 3-D.
  const double per_cell = particles_per_cell > 0 ? particles_per_cell : (D == 2 ? 2.0 : 1.0);
  build_grid(box, x.size(), per_cell);
  // Room for the crowding a gas shows (Poisson fluctuations about the mean occupancy); grown if exceeded.
  while (capacity_ < 4 * per_cell + 8) capacity_ *= 2;
  place(x, v);
  fill_cells();
  if (largest_overlap() > overlap_tolerance)
    throw InputError("positions", "overlapping", "initial positions with no two particles closer than 2R");
  const std::size_t n = x.size();
  tree_.reset(n);
  for (std::uint32_t s = 0; s < n; ++s) {
    predict_crossing(s);
    predict_collisions(s, -1, 0, none, false);
    schedule(s);
  }
  rebase_at_ = rebase_interval();
}

template <int D>
void ElasticGasIn<D>::build_grid(const Box& box, std::size_t n, double per_cell) {
  // Cells never narrower than a diameter, so only the 3^d stencil can hold a contact partner.
  const double wanted = std::max(sigma_, std::pow(box.volume() * per_cell / double(n), 1.0 / D));
  for (int d = 0; d < D; ++d) {
    side_[d] = box.side[d];
    if (periodic_ && side_[d] < 3 * sigma_)
      throw InputError("box", format_value(side_[d]),
                       "a periodic box side of at least 3 contact distances (" + format_value(3 * sigma_) + ")");
    counts_[d] = int(std::clamp(std::floor(side_[d] / wanted), 1.0, 1.0e6));
    if (periodic_) counts_[d] = std::max(counts_[d], 3);
    cell_side_[d] = side_[d] / counts_[d];
  }
  build_morton();
  std::array<int, D> o;
  for (int k = 0; k < (D == 2 ? 9 : 27); ++k) {
    int r = k;
    for (int d = 0; d < D; ++d, r /= 3) o[d] = r % 3 - 1;
    stencil_.push_back(o);
  }
}

template <int D>
void ElasticGasIn<D>::place(std::span<const Vector3> x, std::span<const Vector3> v) {
  const std::size_t n = x.size();
  state_.resize(n);
  next_.assign(n, Next{});
  id_.resize(n);
  slot_of_.resize(n);
  // Slots in cell order from the start, for locality.
  std::vector<std::size_t> cell_of(n);
  for (std::uint32_t p = 0; p < n; ++p) {
    double pos[D];
    for (int d = 0; d < D; ++d) {
      double xd = x[p][d];
      const bool inside = periodic_ ? std::isfinite(xd) : xd >= radius_ && xd <= side_[d] - radius_;
      if (!inside || !std::isfinite(v[p][d]))
        throw InputError("position", format_value(xd),
                         "finite positions and velocities inside the box (at least R from reflecting walls)");
      if (periodic_) xd -= side_[d] * std::floor(xd / side_[d]);
      if (xd >= side_[d]) xd = 0.0;  // round-off of the wrap
      pos[d] = xd;
    }
    cell_of[p] = cell_index(coords_of(pos));
  }
  std::iota(id_.begin(), id_.end(), 0u);
  std::stable_sort(id_.begin(), id_.end(), [&](std::uint32_t a, std::uint32_t b) { return cell_of[a] < cell_of[b]; });
  for (std::uint32_t s = 0; s < n; ++s) {
    const std::uint32_t p = id_[s];
    slot_of_[p] = s;
    State& st = state_[s];
    for (int d = 0; d < D; ++d) {
      double xd = x[p][d];
      if (periodic_) xd -= side_[d] * std::floor(xd / side_[d]);
      if (xd >= side_[d]) xd = 0.0;
      st.x[d] = xd;
      st.v[d] = v[p][d];
    }
    st.t = 0;
    st.stamp = 0;
    next_[s].cell = coords_of(st.x);
  }
}

template <int D>
void ElasticGasIn<D>::advance(double t) {
  double stop = double((long double)t - epoch_);
  while (tree_.top_time() <= stop) {
    step();
    stop = double((long double)t - epoch_);  // a rebase moves the clock's origin
  }
  now_ = std::max(now_, stop);
}

template <int D>
void ElasticGasIn<D>::thermalize(std::size_t collisions, const std::function<void(std::size_t pending)>& progress) {
  if (collisions == 0) return;
  thermal_target_ = collisions;
  thermal_pending_ = 0;
  for (const Next& nx : next_) thermal_pending_ += nx.collisions < collisions;
  // Each collision serves two particles; crossings, walls and stale events come on top. The budget only
  // catches runs that cannot finish (a particle that never meets another).
  const std::uint64_t budget = counters_.events() + 10'000 * std::uint64_t(collisions + 1) * particles() + 1'000'000;
  while (thermal_pending_ > 0) {
    if (counters_.events() > budget || !step())
      throw std::runtime_error("thermalisation cannot finish: " + std::to_string(thermal_pending_) +
                               " particles never reach " + std::to_string(collisions) + " collisions");
    if (progress && (counters_.events() & 0xffff) == 0) progress(thermal_pending_);
  }
  thermal_target_ = 0;
}

// Bit b of coordinate d goes to the next free Morton position, axes taken in turn while they have bits
// left, so unequal cell counts waste no index range beyond rounding each count up to a power of two.
template <int D>
void ElasticGasIn<D>::build_morton() {
  int bits[D], most = 0;
  for (int d = 0; d < D; ++d) {
    bits[d] = 0;
    while ((1 << bits[d]) < counts_[d]) ++bits[d];
    most = std::max(most, bits[d]);
  }
  int position[D][32];
  int next_position = 0;
  for (int b = 0; b < most; ++b)
    for (int d = 0; d < D; ++d)
      if (b < bits[d]) position[d][b] = next_position++;
  cells_ = std::size_t(1) << next_position;
  for (int d = 0; d < D; ++d) {
    spread_[d].assign(std::size_t(counts_[d]), 0);
    for (int c = 0; c < counts_[d]; ++c)
      for (int b = 0; b < bits[d]; ++b)
        if (c >> b & 1) spread_[d][std::size_t(c)] |= std::size_t(1) << position[d][b];
  }
}

template <int D>
void ElasticGasIn<D>::fill_cells() {
  std::vector<std::uint32_t> count(cells_, 0);
  std::uint32_t crowded = 0;
  for (const Next& nx : next_) crowded = std::max(crowded, ++count[cell_index(nx.cell)]);
  while (capacity_ < crowded + 2) capacity_ *= 2;
  cell_members_.assign(cells_ * capacity_, 0);
  cell_of_.resize(state_.size());
  for (std::uint32_t s = 0; s < state_.size(); ++s) {
    cell_of_[s] = std::uint32_t(cell_index(next_[s].cell));
    std::uint32_t* m = &cell_members_[cell_of_[s] * capacity_];
    m[++m[0]] = s;
  }
}

template <int D>
void ElasticGasIn<D>::grow_cells() {
  capacity_ *= 2;
  fill_cells();  // the particle being linked is already counted in its new cell
}

// Clock renormalisation (every few N events): every particle is brought to now, times are shifted so that
// now = 0, and the particles are re-sorted by cell so that neighbours sit close in memory.
template <int D>
void ElasticGasIn<D>::rebase() {
  const std::size_t n = state_.size();
  const double shift = now_;
  for (std::uint32_t s = 0; s < n; ++s) {
    bring_to_now(s);
    state_[s].t = 0;
    if (next_[s].collision != never) next_[s].collision -= shift;
    if (next_[s].crossing != never) next_[s].crossing -= shift;
  }
  epoch_ += (long double)shift;
  now_ = 0;
  // The new order: cell by cell in Morton order (a counting sort read off the cell table).
  std::vector<std::uint32_t> order;
  order.reserve(n);
  for (std::size_t c = 0; c < cells_; ++c) {
    const std::uint32_t* m = members(c);
    for (std::uint32_t k = 1; k <= m[0]; ++k) order.push_back(m[k]);
  }
  std::vector<std::uint32_t> new_slot(n);
  for (std::uint32_t s = 0; s < n; ++s) new_slot[order[s]] = s;
  auto permute = [&](auto& v) {
    auto copy = v;
    for (std::uint32_t s = 0; s < n; ++s) v[s] = copy[order[s]];
  };
  permute(state_);
  permute(next_);
  permute(id_);
  for (std::uint32_t s = 0; s < n; ++s) {
    slot_of_[id_[s]] = s;
    if (next_[s].partner != none) next_[s].partner = new_slot[next_[s].partner];
  }
  fill_cells();
  tree_.reset(n);
  for (std::uint32_t s = 0; s < n; ++s) schedule(s);
  rebase_at_ = counters_.events() + rebase_interval();
}

template <int D>
std::vector<Vector3> ElasticGasIn<D>::positions() const {
  std::vector<Vector3> out(state_.size(), Vector3{0, 0, 0});
  for (std::uint32_t s = 0; s < state_.size(); ++s) {
    const State& st = state_[s];
    Vector3& x = out[id_[s]];
    for (int d = 0; d < D; ++d) {
      double xd = st.x[d] + st.v[d] * (now_ - st.t);
      if (periodic_) {
        xd -= side_[d] * std::floor(xd / side_[d]);
        if (xd >= side_[d]) xd = 0.0;
      } else {
        xd = std::clamp(xd, radius_, side_[d] - radius_);  // round-off at a wall contact
      }
      x[d] = xd;
    }
  }
  return out;
}

template <int D>
std::vector<Vector3> ElasticGasIn<D>::velocities() const {
  std::vector<Vector3> out(state_.size(), Vector3{0, 0, 0});
  for (std::uint32_t s = 0; s < state_.size(); ++s)
    for (int d = 0; d < D; ++d) out[id_[s]][d] = state_[s].v[d];
  return out;
}

template <int D>
double ElasticGasIn<D>::kinetic_energy() const {
  double e = 0;
  for (const State& q : state_)
    for (int d = 0; d < D; ++d) e += 0.5 * q.v[d] * q.v[d];
  return e;
}

template <int D>
Vector3 ElasticGasIn<D>::momentum() const {
  Vector3 p{0, 0, 0};
  for (const State& q : state_)
    for (int d = 0; d < D; ++d) p[d] += q.v[d];
  return p;
}

template <int D>
double ElasticGasIn<D>::largest_overlap() const {
  double worst = 0;
  for (std::uint32_t i = 0; i < state_.size(); ++i) {
    const State& si = state_[i];
    double xi[D];
    for (int d = 0; d < D; ++d) xi[d] = si.x[d] + si.v[d] * (now_ - si.t);
    const std::uint32_t* blocks[stencil_size];
    std::int8_t image[stencil_size][D];
    const int nblocks = stencil_cells(next_[i].cell, -1, 0, blocks, image);
    for (int b = 0; b < nblocks; ++b) {
      const std::uint32_t* m = blocks[b];
      for (std::uint32_t k = 1; k <= m[0]; ++k) {
        const std::uint32_t j = m[k];
        if (j <= i) continue;
        const State& sj = state_[j];
        double r2 = 0;
        for (int d = 0; d < D; ++d) {
          const double dx = sj.x[d] + sj.v[d] * (now_ - sj.t) + image[b][d] * side_[d] - xi[d];
          r2 += dx * dx;
        }
        worst = std::max(worst, 1 - std::sqrt(r2) / sigma_);
      }
    }
  }
  return worst;
}

template class ElasticGasIn<2>;
template class ElasticGasIn<3>;

}  // namespace elastic_gas_detail

std::unique_ptr<ElasticGas> make_elastic_gas(const Box& box, double radius, std::span<const Vector3> positions,
                                             std::span<const Vector3> velocities, double particles_per_cell) {
  box.validate();
  if (box.dimension == 2) return std::make_unique<elastic_gas_detail::ElasticGasIn<2>>(box, radius, positions, velocities, particles_per_cell);
  return std::make_unique<elastic_gas_detail::ElasticGasIn<3>>(box, radius, positions, velocities, particles_per_cell);
}

}  // namespace aggkit
