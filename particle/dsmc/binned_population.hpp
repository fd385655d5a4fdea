#pragma once
// The particles of one realisation, grouped for O(1)-storage shattering and O(log B) uniform selection
// within a size bin (size_bins.hpp): sizes <= B are counts per size (buckets), larger particles are stored
// one by one in the list of their bin. Shattering into m monomers is one bucket update, whatever m is.
// A bin of more than 16 bucketed sizes (sizes >= 64) has its own Fenwick tree over its sizes [Fenwick1994],
// so selecting in it is one descent of log2(width) steps; the narrower bins (sizes < 64, where nearly every
// event happens) keep only their bucket counts and are selected by a short scan, so most bucket updates
// touch no tree at all. The particle of a given rank is the same as under one tree over all sizes
// (the rank-th of the bin in increasing size), so the random stream of a run does not depend on this layout.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "particle/common/checkpoint.hpp"
#include "particle/dsmc/fenwick.hpp"
#include "particle/dsmc/random.hpp"
#include "particle/dsmc/size_bins.hpp"

namespace aggkit::dsmc {

class BinnedPopulation {
 public:
  explicit BinnedPopulation(std::uint64_t bucket_limit);

  // A particle chosen in a bin: its size and, for an individually stored one, its place in the bin's list.
  struct Pick {
    std::size_t bin;
    std::uint64_t size;
    std::size_t large_index;  // npos for a bucketed particle
  };
  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();

  std::size_t bins() const { return bins_.size(); }  // 1 + the largest bin ever occupied
  std::uint64_t count(std::size_t bin) const { return bins_[bin].count; }
  std::uint64_t particles() const { return particles_; }

  void add(std::uint64_t size, std::uint64_t copies = 1);
  // The particle of rank `rank` (0 <= rank < count(bin)) in a fixed order within the bin.
  Pick pick(std::size_t bin, std::uint64_t rank) const;
  // Removes picked particles; two large ones from the same bin must be removed higher index first.
  void remove(const Pick& particle);
  void duplicate();  // every particle doubled (population control)
  void halve(Random& random);  // equal sizes paired, one of each pair removed (population_control.hpp)
  void for_each_group(const std::function<void(std::uint64_t size, std::uint64_t count)>& f) const;

  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  struct Bin {
    std::uint64_t count = 0;  // all particles in the bin
    std::uint64_t small = 0;  // of which bucketed (size <= B)
    std::vector<std::uint64_t> large;
  };
  // Bin `bin`'s tree, or nullptr for a bin selected by scanning its buckets (or holding no bucketed size).
  Fenwick* tree_of(std::size_t bin) { return bin < trees_.size() && trees_[bin] ? &*trees_[bin] : nullptr; }
  void rebuild_trees();  // every bin tree from bucket_
  // Bins of at most this many bucketed sizes (sizes below 64, or a bin cut short by B) pick a bucketed
  // particle by scanning the bin's buckets; the wider ones have a tree.
  static constexpr std::uint64_t narrow_bin = 16;
  std::uint64_t bucketed_high(std::size_t bin) const { return std::min(bin_high(bin), limit_); }
  std::uint64_t limit_;
  std::vector<std::uint64_t> bucket_;  // bucket_[s], s = 1..B
  std::vector<std::optional<Fenwick>> trees_;  // per bin with bucketed sizes: its tree over [low, min(high, B)]
  std::vector<Bin> bins_;
  std::uint64_t particles_ = 0;
};

// The per-event operations, inline: each trial calls them (a call into the shared library costs as much as
// a monomer's pick).
inline void BinnedPopulation::add(std::uint64_t size, std::uint64_t copies) {
  if (copies == 0) return;
  const std::size_t b = bin_of(size);
  if (b >= bins_.size()) bins_.resize(b + 1);
  Bin& bin = bins_[b];
  bin.count += copies;
  particles_ += copies;
  if (size <= limit_) {
    bin.small += copies;
    bucket_[size] += copies;
    if (Fenwick* tree = tree_of(b)) tree->add(size - bin_low(b) + 1, std::int64_t(copies));
  } else {
    bin.large.insert(bin.large.end(), copies, size);
  }
}

inline BinnedPopulation::Pick BinnedPopulation::pick(std::size_t b, std::uint64_t rank) const {
  const Bin& bin = bins_[b];
  if (rank < bin.small) {
    const std::uint64_t low = bin_low(b), high = bucketed_high(b);
    if (low == high) return {b, low, npos};
    if (high - low < narrow_bin) {  // a short scan of the bin's buckets, all of them: no exit to mispredict
      std::uint64_t s = low, seen = 0;
      for (std::uint64_t t = low; t < high; ++t) {
        seen += bucket_[t];
        s += seen <= rank ? 1 : 0;  // the size holding `rank` lies beyond t
      }
      return {b, s, npos};
    }
    return {b, low - 1 + trees_[b]->select(rank), npos};
  }
  const std::size_t index = std::size_t(rank - bin.small);
  return {b, bin.large[index], index};
}

inline void BinnedPopulation::remove(const Pick& particle) {
  Bin& bin = bins_[particle.bin];
  --bin.count;
  --particles_;
  if (particle.large_index == npos) {
    --bin.small;
    --bucket_[particle.size];
    if (Fenwick* tree = tree_of(particle.bin)) tree->add(particle.size - bin_low(particle.bin) + 1, -1);
  } else {
    bin.large[particle.large_index] = bin.large.back();
    bin.large.pop_back();
  }
}

}  // namespace aggkit::dsmc
