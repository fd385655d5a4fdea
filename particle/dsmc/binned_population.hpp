#pragma once
// The particles of one realisation, grouped for O(1)-storage shattering and O(log B) uniform selection
// within a size bin (size_bins.hpp): sizes <= B are counts per size (buckets), larger particles are stored
// one by one in the list of their bin. Shattering into m monomers is one bucket update, whatever m is.
// A bin of more than 16 bucketed sizes (sizes >= 64) has its own Fenwick tree over its sizes [Fenwick1994],
// so selecting in it is one descent of log2(width) steps; the narrower bins (sizes < 64, where nearly every
// event happens) keep only their bucket counts and are selected by a short scan, so most bucket updates
// touch no tree at all. The particle of a given rank is the same as under one tree over all sizes
// (the rank-th of the bin in increasing size), so the random stream of a run does not depend on this layout.
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
  std::uint64_t limit_;
  std::vector<std::uint64_t> bucket_;  // bucket_[s], s = 1..B
  std::vector<std::optional<Fenwick>> trees_;  // per bin with bucketed sizes: its tree over [low, min(high, B)]
  std::vector<Bin> bins_;
  std::uint64_t particles_ = 0;
};

}  // namespace aggkit::dsmc
