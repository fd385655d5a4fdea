#pragma once
// The event calendar of an event-driven simulation with one event time per slot (per particle, holding
// only its next event: Marín, Risso & Cordero, J. Comput. Phys. 109 (1993) 306). The queue never holds
// stale copies and stays N entries long.
//
// Layout for cache: slots are grouped in blocks of 16 consecutive slots with each block's earliest entry
// cached; a tournament (winner) tree runs over the blocks only. Changing a slot's time rescans its block
// (two cache lines) only when the block's earliest slot got later, then walks the block tree, which
// for 10^6 slots is 65 536 leaves (1 MB, cache resident) — instead of a 20-level walk through a 32 MB
// tree with a cache miss per level.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "particle/common/huge_page_allocator.hpp"

namespace aggkit {

class TournamentTree {
 public:
  static constexpr double never = std::numeric_limits<double>::infinity();
  static constexpr std::size_t block = 16;

  explicit TournamentTree(std::size_t slots = 0) { reset(slots); }

  // `slots` slots, all at time `never`.
  void reset(std::size_t slots) {
    slots_ = slots;
    const std::size_t blocks = (slots + block - 1) / block;
    leaves_ = 1;
    while (leaves_ < blocks) leaves_ *= 2;
    times_.assign(leaves_ * block, never);
    nodes_.assign(2 * leaves_, Node{never, 0});
    for (std::size_t b = 0; b < leaves_; ++b) nodes_[leaves_ + b].slot = std::uint32_t(b * block);
    for (std::size_t n = leaves_ - 1; n >= 1; --n) nodes_[n] = nodes_[2 * n];
  }

  std::size_t slots() const { return slots_; }
  double time(std::uint32_t slot) const { return times_[slot]; }
  double top_time() const { return nodes_[1].time; }
  // The earliest slot of each of the 2^depth subtrees at that depth (fewer when the tree is smaller): the
  // next few events are most likely among them, so their data can be fetched ahead.
  template <class F>
  void for_each_subtree_winner(int depth, F&& f) const {
    std::size_t first = std::size_t(1) << depth;
    if (first >= 2 * leaves_) first = leaves_;
    for (std::size_t n = first; n < 2 * first && n < 2 * leaves_; ++n)
      if (nodes_[n].time != never) f(nodes_[n].slot);
  }
  std::uint32_t top_slot() const { return nodes_[1].slot; }
  // Starts fetching what set(slot, ·) will read: the slot's block of times and its leaf.
  void prefetch(std::uint32_t slot) const {
    __builtin_prefetch(&times_[slot & ~std::uint32_t(block - 1)]);
    __builtin_prefetch(&nodes_[leaves_ + slot / block]);
  }

  void set(std::uint32_t slot, double time) {
    times_[slot] = time;
    const std::size_t b = slot / block;
    Node& leaf = nodes_[leaves_ + b];
    if (time < leaf.time || (time == leaf.time && slot == leaf.slot)) {
      leaf = {time, slot};
    } else if (leaf.slot == slot) {
      // The block's earliest slot got later: rescan the block.
      const double* t = &times_[b * block];
      std::size_t best = 0;
      for (std::size_t k = 1; k < block; ++k)
        if (t[k] < t[best]) best = k;
      leaf = {t[best], std::uint32_t(b * block + best)};
    } else {
      return;  // neither the block's earliest nor earlier than it: nothing above changes
    }
    for (std::size_t n = (leaves_ + b) >> 1; n >= 1; n >>= 1) {
      const Node& left = nodes_[2 * n];
      const Node& right = nodes_[2 * n + 1];
      const Node& winner = right.time < left.time ? right : left;
      if (nodes_[n].slot == winner.slot && nodes_[n].time == winner.time) break;
      nodes_[n] = winner;
    }
  }

  // Subtracts `shift` from every time (renormalising the clock); O(N).
  void shift_times(double shift) {
    for (double& t : times_) t -= shift;
    for (Node& n : nodes_) n.time -= shift;
  }

 private:
  struct Node {
    double time;
    std::uint32_t slot;
  };
  std::size_t slots_ = 0, leaves_ = 1;
  std::vector<double, HugePageAllocator<double>> times_;  // per slot, blocks of `block`
  std::vector<Node, HugePageAllocator<Node>> nodes_;    // winner tree over the blocks; leaves_ + b is block b
};

}  // namespace aggkit
