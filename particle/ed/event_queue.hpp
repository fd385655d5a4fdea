#pragma once
// The event queue of the ED engine: a binary min-heap on time with lazy invalidation. Each event carries the
// trajectory stamps of the clusters involved when it was predicted; a stamp changes whenever a cluster's
// velocity or membership changes, so a popped event whose stamps differ from the current ones is stale and
// skipped. Stale events are purged when they outnumber the live ones (`compact`).
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
    std::push_heap(heap_.begin(), heap_.end(), later);
  }
  bool empty() const { return heap_.empty(); }
  std::size_t size() const { return heap_.size(); }
  const Event& top() const { return heap_.front(); }
  void pop() {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    heap_.pop_back();
  }
  // Keeps only the events for which `valid(e)` holds.
  template <class Valid>
  void compact(Valid&& valid) {
    heap_.erase(std::remove_if(heap_.begin(), heap_.end(), [&](const Event& e) { return !valid(e); }), heap_.end());
    std::make_heap(heap_.begin(), heap_.end(), later);
  }
  void clear() { heap_.clear(); }
  // Checkpoints: the heap as it is (a rebuilt heap could order events of equal times differently).
  void save(StateWriter& out) const { out.put(heap_); }
  void restore(StateReader& in) { in.get(heap_); }

 private:
  static bool later(const Event& x, const Event& y) { return x.time > y.time; }
  std::vector<Event> heap_;
};

}  // namespace aggkit
