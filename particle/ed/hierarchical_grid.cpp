#include "particle/ed/hierarchical_grid.hpp"

#include <algorithm>
#include <cmath>

namespace aggkit {

HierarchicalGrid::HierarchicalGrid(const Box& box, double min_side, std::size_t target_cells, std::size_t clusters)
    : box_(box), slots_(1 << box.dimension) {
  const double wanted = std::max(min_side, std::pow(box.volume() / double(std::max<std::size_t>(target_cells, 1)),
                                                    1.0 / box.dimension));
  std::array<int, 3> n{1, 1, 1};
  for (int a = 0; a < box.dimension; ++a)
    while (box.side[a] / (2.0 * n[a]) >= wanted && n[a] < (1 << 20)) n[a] *= 2;
  while (true) {
    const bool single = n[0] == 1 && n[1] == 1 && n[2] == 1;
    if (single) break;
    counts_.push_back(n);
    Vector3 s{0, 0, 0};
    for (int a = 0; a < box.dimension; ++a) s[a] = box.side[a] / n[a];
    side_.push_back(s);
    for (int a = 0; a < 3; ++a) n[a] = std::max(1, n[a] / 2);
  }
  top_ = int(counts_.size());
  cells_.resize(top_);
  for (int l = 0; l < top_; ++l)
    cells_[l].resize(std::size_t(counts_[l][0]) * std::size_t(counts_[l][1]) * std::size_t(counts_[l][2]));
  range_.resize(clusters * std::size_t(top_));
  where_.assign(clusters * std::size_t(top_) * std::size_t(slots_), none);
}

int HierarchicalGrid::level_for(const Vector3& extent) const {
  for (int l = 0; l < top_; ++l) {
    bool fits = true;
    for (int a = 0; a < box_.dimension; ++a)
      if (counts_[l][a] > 1 && extent[a] * (1 + 1e-9) > side_[l][a]) fits = false;
    if (fits) return l;
  }
  return top_;
}

HierarchicalGrid::Range HierarchicalGrid::range_of(int level, const Vector3& low, const Vector3& high) const {
  Range r;
  for (int a = 0; a < box_.dimension; ++a) {
    r.lo[a] = std::int32_t(std::floor(low[a] / side_[level][a]));
    r.hi[a] = std::int32_t(std::floor(high[a] / side_[level][a]));
  }
  return r;
}

int HierarchicalGrid::wrap(int level, int axis, std::int64_t i) const {
  const int n = counts_[level][axis];
  if (box_.boundary == Boundary::periodic) {
    std::int64_t m = i % n;
    return int(m < 0 ? m + n : m);
  }
  return int(std::clamp<std::int64_t>(i, 0, n - 1));
}

// Slot bit a picks the low (0) or high (1) index along axis a; a high index equal to the low one after
// wrapping/clamping is a duplicate and not a valid slot.
std::uint32_t HierarchicalGrid::cell_at(int level, const Range& r, int slot, bool& valid) const {
  valid = true;
  std::array<int, 3> c{0, 0, 0};
  for (int a = 0; a < box_.dimension; ++a) {
    const int lo = wrap(level, a, r.lo[a]);
    if (slot >> a & 1) {
      const int hi = wrap(level, a, r.hi[a]);
      if (hi == lo) valid = false;
      c[a] = hi;
    } else {
      c[a] = lo;
    }
  }
  const auto& n = counts_[level];
  return std::uint32_t(c[0] + n[0] * (c[1] + n[1] * c[2]));
}

int HierarchicalGrid::cells(int level, const Range& r, std::array<std::uint32_t, 8>& out) const {
  int k = 0;
  for (int s = 0; s < slots_; ++s) {
    bool valid;
    const std::uint32_t c = cell_at(level, r, s, valid);
    if (valid) out[k++] = c;
  }
  return k;
}

bool HierarchicalGrid::share_cell(int level, const Range& a, const Range& b) const {
  std::array<std::uint32_t, 8> ca, cb;
  const int na = cells(level, a, ca), nb = cells(level, b, cb);
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j)
      if (ca[i] == cb[j]) return true;
  return false;
}

void HierarchicalGrid::place(std::uint32_t cluster, int level, const Range& r, bool owner) {
  // Slot by slot: an entry whose cell does not change stays where it is (a crossing moves half the slots
  // of one axis), the others leave their old cell and join the new one.
  const std::size_t base = cluster * std::size_t(top_) + level;
  for (int s = 0; s < slots_; ++s) {
    bool valid;
    const std::uint32_t c = cell_at(level, r, s, valid);
    std::uint32_t& w = where_[base * slots_ + s];
    if (w != none) {
      bool was_valid;
      const std::uint32_t old = cell_at(level, range_[base], s, was_valid);
      if (valid && old == c) continue;
      erase(level, old, owner, w);
      w = none;
    }
    if (!valid) continue;
    auto& list = owner ? cells_[level][c].owners : cells_[level][c].passengers;
    w = std::uint32_t(list.size());
    list.push_back({cluster, std::uint32_t(s)});
  }
  range_[base] = r;
}

void HierarchicalGrid::erase(int level, std::uint32_t cell, bool owner, std::uint32_t at) {
  auto& list = owner ? cells_[level][cell].owners : cells_[level][cell].passengers;
  const Entry moved = list.back();
  list[at] = moved;
  where_[(moved.cluster * std::size_t(top_) + level) * slots_ + moved.slot] = at;
  list.pop_back();
}

void HierarchicalGrid::remove(std::uint32_t cluster, int level, bool owner) {
  const std::size_t base = cluster * std::size_t(top_) + level;
  for (int s = 0; s < slots_; ++s) {
    std::uint32_t& w = where_[base * slots_ + s];
    if (w == none) continue;
    bool valid;
    erase(level, cell_at(level, range_[base], s, valid), owner, w);
    w = none;
  }
}

}  // namespace aggkit
