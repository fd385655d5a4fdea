#pragma once
// The event queue of the ED engine: a 4-ary min-heap on time with lazy invalidation. Each event carries the
// trajectory stamps of the clusters involved when it was predicted; a stamp changes whenever a cluster's
// velocity or membership changes, so a popped event whose stamps differ from the current ones is stale and
// skipped. The engine purges stale events (`compact`) whenever the queue has grown by half since the last
// purge.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "particle/common/checkpoint.hpp"

namespace aggkit {

enum class EventKind : std::uint8_t { collision, cell_crossing, wall, pair_check };

struct Event {
  long double time;          // absolute engine time
  std::uint64_t stamp_a;     // stamp of the cluster of `a` at prediction
  std::uint64_t stamp_b;     // stamp of the cluster of `b` (collisions only)
  std::uint32_t a;           // particle (collision) or cluster (crossing, wall, pair check)
  std::uint32_t b;           // partner particle (collision), partner cluster (pair check), face (crossing)
  EventKind kind;
  std::uint8_t axis;         // crossing / wall axis
  std::int8_t direction;     // crossing: +1 or -1
  std::uint8_t level = 0;    // crossing: broad-phase grid level
};

class EventQueue {
 public:
  void push(const Event& e) {
    heap_.push_back(e);
    sift_up(heap_.size() - 1);
  }
  bool empty() const { return heap_.empty(); }
  std::size_t size() const { return heap_.size(); }
  const Event& top() const { return heap_.front(); }
  void pop() {
    const Event last = heap_.back();
    heap_.pop_back();
    if (heap_.empty()) return;
    // The hole at the root goes down along the earliest children to a leaf, then `last` rises into it from
    // there: it belongs near the bottom, so this takes about half the comparisons of sifting it down.
    std::size_t hole = 0;
    const std::size_t n = heap_.size();
    for (;;) {
      const std::size_t first = arity * hole + 1;
      if (first >= n) break;
      const std::size_t end = std::min(first + arity, n);
      std::size_t best = first;
      for (std::size_t c = first + 1; c < end; ++c)
        if (heap_[c].time < heap_[best].time) best = c;
      heap_[hole] = heap_[best];
      hole = best;
    }
    heap_[hole] = last;
    sift_up(hole);
  }
  // Keeps only the events for which `valid(e)` holds.
  template <class Valid>
  void compact(Valid&& valid) {
    heap_.erase(std::remove_if(heap_.begin(), heap_.end(), [&](const Event& e) { return !valid(e); }), heap_.end());
    for (std::size_t i = heap_.size(); i-- > 0;) sift_down(i);
  }
  void clear() { heap_.clear(); }
  // Checkpoints: the heap as it is (a rebuilt heap could order events of equal times differently).
  void save(StateWriter& out) const { out.put(heap_); }
  void restore(StateReader& in) { in.get(heap_); }

 private:
  // A 4-ary min-heap on time: half the levels of a binary heap, the four children of a node adjacent in
  // memory. The queue of a large run holds millions of events, so each level is a cache miss and the depth,
  // not the comparisons, sets the cost of a pop.
  static constexpr std::size_t arity = 4;
  void sift_up(std::size_t i) {
    const Event e = heap_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / arity;
      if (!(e.time < heap_[parent].time)) break;
      heap_[i] = heap_[parent];
      i = parent;
    }
    heap_[i] = e;
  }
  void sift_down(std::size_t i) {
    const Event e = heap_[i];
    const std::size_t n = heap_.size();
    for (;;) {
      const std::size_t first = arity * i + 1;
      if (first >= n) break;
      const std::size_t end = std::min(first + arity, n);
      std::size_t best = first;
      for (std::size_t c = first + 1; c < end; ++c)
        if (heap_[c].time < heap_[best].time) best = c;
      if (!(heap_[best].time < e.time)) break;
      heap_[i] = heap_[best];
      i = best;
    }
    heap_[i] = e;
  }
  std::vector<Event> heap_;
};

}  // namespace aggkit
