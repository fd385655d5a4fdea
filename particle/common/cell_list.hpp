#pragma once
// Which particles are in which cell: intrusive doubly linked lists, O(1) insertion and removal.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/checkpoint.hpp"

namespace aggkit {

class CellList {
 public:
  static constexpr std::uint32_t none = 0xffffffffu;

  CellList(std::size_t cells, std::size_t particles)
      : head_(cells, none), next_(particles, none), prev_(particles, none), cell_(particles, none) {}

  void insert(std::uint32_t particle, std::size_t cell) {
    cell_[particle] = std::uint32_t(cell);
    prev_[particle] = none;
    next_[particle] = head_[cell];
    if (head_[cell] != none) prev_[head_[cell]] = particle;
    head_[cell] = particle;
  }
  void remove(std::uint32_t particle) {
    const std::uint32_t p = prev_[particle], n = next_[particle];
    if (p != none) next_[p] = n;
    else head_[cell_[particle]] = n;
    if (n != none) prev_[n] = p;
    cell_[particle] = none;
  }
  void move(std::uint32_t particle, std::size_t cell) {
    remove(particle);
    insert(particle, cell);
  }

  std::uint32_t first(std::size_t cell) const { return head_[cell]; }
  std::uint32_t next(std::uint32_t particle) const { return next_[particle]; }
  std::size_t cell_of(std::uint32_t particle) const { return cell_[particle]; }

  // Checkpoints: the lists as they are (their order depends on the history of moves).
  void save(StateWriter& out) const {
    out.put(head_);
    out.put(next_);
    out.put(prev_);
    out.put(cell_);
  }
  void restore(StateReader& in) {
    const std::size_t cells = head_.size(), particles = next_.size();
    in.get(head_);
    in.get(next_);
    in.get(prev_);
    in.get(cell_);
    if (head_.size() != cells || next_.size() != particles || prev_.size() != particles || cell_.size() != particles)
      throw CheckpointError("the checkpoint's cell list has another number of cells or particles");
  }

 private:
  std::vector<std::uint32_t> head_, next_, prev_, cell_;
};

}  // namespace aggkit
