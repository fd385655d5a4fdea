#include "particle/ed/cluster_index.hpp"

#include <cmath>

namespace aggkit {

namespace {
std::uint64_t mix(std::uint64_t x) {  // SplitMix64 finaliser [Steele2014]
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
}  // namespace

ClusterIndex::ClusterIndex(const Box& box, double contact, std::size_t particles)
    : grid_(box, contact, std::size_t(-1)),
      periodic_(box.boundary == Boundary::periodic),
      dimension_(box.dimension),
      next_(particles, none) {
  std::size_t capacity = 16;
  while (capacity < 2 * particles) capacity *= 2;
  slots_.resize(capacity);
  std::size_t buckets = 64;
  while (buckets < 4 * particles) buckets *= 2;
  filter_.assign(buckets, 0);
}

CellCoords ClusterIndex::cell_of(const Vector3& offset) const {
  CellCoords c{0, 0, 0};
  for (int a = 0; a < dimension_; ++a) c[a] = int(std::floor(offset[a] / grid_.cell_side()[a]));
  return c;
}

void ClusterIndex::key(std::uint32_t cluster, CellCoords c, std::uint64_t& k1, std::uint64_t& k2) const {
  if (periodic_)
    for (int a = 0; a < dimension_; ++a) {
      const int n = grid_.counts()[a];
      c[a] %= n;
      if (c[a] < 0) c[a] += n;
    }
  k1 = (std::uint64_t(cluster) << 32) | std::uint32_t(c[0]);
  k2 = (std::uint64_t(std::uint32_t(c[1])) << 32) | std::uint32_t(c[2]);
}

std::size_t ClusterIndex::home(std::uint64_t k1, std::uint64_t k2) const {
  return std::size_t(mix(k1 ^ mix(k2))) & (slots_.size() - 1);
}

std::size_t ClusterIndex::bucket(std::uint64_t k1, std::uint64_t k2) const {
  // Neighbouring cells of one cluster in neighbouring counters (a cast walks neighbouring cells, so its
  // questions mostly fall on a cache line already loaded); the cluster picks where its run starts.
  const std::uint64_t cluster = k1 >> 32;
  const std::uint64_t x = std::uint32_t(k1), y = std::uint32_t(k2 >> 32), z = std::uint32_t(k2);
  return std::size_t(mix(cluster) + x + 1021 * y + 1048573 * z) & (filter_.size() - 1);
}

void ClusterIndex::count(std::size_t b, int change) {
  std::uint8_t& n = filter_[b];
  if (n == 0xff) return;
  n = std::uint8_t(int(n) + change);
}

void ClusterIndex::refilter() {
  std::fill(filter_.begin(), filter_.end(), std::uint8_t(0));
  for (const Slot& s : slots_)
    if (s.head != none) count(bucket(s.k1, s.k2), +1);
}

std::size_t ClusterIndex::find(std::uint64_t k1, std::uint64_t k2) const {
  const std::size_t mask = slots_.size() - 1;
  std::size_t i = home(k1, k2);
  while (slots_[i].head != none && (slots_[i].k1 != k1 || slots_[i].k2 != k2)) i = (i + 1) & mask;
  return i;
}

void ClusterIndex::grow() {
  std::vector<Slot> old(slots_.size() * 2);
  old.swap(slots_);
  for (const Slot& s : old)
    if (s.head != none) slots_[find(s.k1, s.k2)] = s;
}

void ClusterIndex::insert(std::uint32_t cluster, std::uint32_t particle, const Vector3& offset) {
  std::uint64_t k1, k2;
  key(cluster, cell_of(offset), k1, k2);
  std::size_t i = find(k1, k2);
  if (slots_[i].head == none) {
    if (2 * (used_ + 1) > slots_.size()) {
      grow();
      i = find(k1, k2);
    }
    slots_[i] = {k1, k2, none};
    ++used_;
    count(bucket(k1, k2), +1);
  }
  next_[particle] = slots_[i].head;
  slots_[i].head = particle;
}

void ClusterIndex::erase(std::uint32_t cluster, std::uint32_t particle, const Vector3& offset) {
  std::uint64_t k1, k2;
  key(cluster, cell_of(offset), k1, k2);
  std::size_t i = find(k1, k2);
  if (slots_[i].head == none) return;
  if (slots_[i].head == particle) {
    slots_[i].head = next_[particle];
  } else {
    std::uint32_t p = slots_[i].head;
    while (next_[p] != none && next_[p] != particle) p = next_[p];
    if (next_[p] == particle) next_[p] = next_[particle];
  }
  next_[particle] = none;
  if (slots_[i].head != none) return;
  count(bucket(k1, k2), -1);
  // Backward-shift deletion keeps every probe run unbroken.
  const std::size_t mask = slots_.size() - 1;
  std::size_t j = i;
  while (true) {
    j = (j + 1) & mask;
    if (slots_[j].head == none) break;
    const std::size_t k = home(slots_[j].k1, slots_[j].k2);
    const bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
    if (stays) continue;
    slots_[i] = slots_[j];
    i = j;
  }
  slots_[i].head = none;
  --used_;
}

std::uint32_t ClusterIndex::first(std::uint32_t cluster, const CellCoords& cell) const {
  std::uint64_t k1, k2;
  key(cluster, cell, k1, k2);
  if (filter_[bucket(k1, k2)] == 0) return none;
  return slots_[find(k1, k2)].head;
}

}  // namespace aggkit
