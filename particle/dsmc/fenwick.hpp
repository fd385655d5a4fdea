#pragma once
// Binary indexed tree [Fenwick1994] of particle counts per size 1..B:
// O(log B) count updates and selection of the r-th particle in size order.
#include <cstdint>
#include <vector>

namespace aggkit::dsmc {

class Fenwick {
 public:
  explicit Fenwick(std::uint64_t n) : tree_(n + 1, 0) {
    while ((top_ << 1) <= n) top_ <<= 1;
  }
  void add(std::uint64_t index, std::int64_t delta) {  // index 1..n
    for (; index < tree_.size(); index += index & (~index + 1)) tree_[index] += std::uint64_t(delta);
  }
  std::uint64_t prefix(std::uint64_t index) const {  // Σ counts[1..index]
    std::uint64_t sum = 0;
    for (; index > 0; index &= index - 1) sum += tree_[index];
    return sum;
  }
  // The smallest index whose prefix sum exceeds `rank` (rank < total).
  std::uint64_t select(std::uint64_t rank) const {
    std::uint64_t position = 0;
    for (std::uint64_t step = top_; step > 0; step >>= 1) {
      const std::uint64_t next = position + step;
      if (next >= tree_.size()) continue;  // only past the last power of two below n
      // Without a branch on the count (a coin flip per level): take the step where its count <= rank.
      const std::uint64_t count = tree_[next], take = ~std::uint64_t(0) * std::uint64_t(count <= rank);
      position += step & take;
      rank -= count & take;
    }
    return position + 1;
  }
  // Rebuilds the tree from counts[1..n] (counts[0] unused) in O(n).
  void assign(const std::vector<std::uint64_t>& counts) { assign(counts.data()); }
  void assign(const std::uint64_t* counts) {  // counts[1..n] readable
    for (std::size_t i = 1; i < tree_.size(); ++i) tree_[i] = counts[i];
    for (std::size_t i = 1; i < tree_.size(); ++i) {
      const std::size_t parent = i + (i & (~i + 1));
      if (parent < tree_.size()) tree_[parent] += tree_[i];
    }
  }
  void scale(std::uint64_t factor) {  // every count multiplied (the tree is linear in the counts)
    for (auto& entry : tree_) entry *= factor;
  }

 // Checkpoints (particle/common/checkpoint.hpp).
  template <class Writer> void save(Writer& out) const { out.put(tree_), out.put(top_); }
  template <class Reader> void restore(Reader& in) { in.get(tree_), in.get(top_); }

 private:
  std::vector<std::uint64_t> tree_;
  std::uint64_t top_ = 1;
};

}  // namespace aggkit::dsmc
