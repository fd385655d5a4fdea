#pragma once
// Broad phase of the cluster-level ED engine: a hierarchy of grids over the box [Ogarko2012] with nested
// cells, 2^level times the finest side along each axis. A cluster lives at the finest level whose cells are
// at least as wide as its (inflated) bounding box, so it covers at most 2 cells per axis there, and it is
// registered at its own level (an owner) and at coarser ones below the top (a passenger: the engine registers
// passengers up to the coarsest level where an owner lives, since only owners are met there).
// The top level (one cell: clusters wider than half the box) is not stored: its clusters are candidates of
// everyone. Two clusters are candidates when they share a cell at the coarser of their two levels.
// Registration: each (cluster, level) keeps its cell-index range per axis (unwrapped integers) and, per
// occupied cell, its position in that cell's list, so registering and removing are O(1).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/box.hpp"
#include "particle/common/checkpoint.hpp"

namespace aggkit {

class HierarchicalGrid {
 public:
  static constexpr std::uint32_t none = 0xffffffffu;
  struct Range {
    std::array<std::int32_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
  };
  struct Entry {
    std::uint32_t cluster, slot;
  };

  // Finest cells at least `min_side` wide and about box volume / target_cells in size, a power-of-two count
  // per axis; room for `clusters` cluster ids.
  HierarchicalGrid(const Box& box, double min_side, std::size_t target_cells, std::size_t clusters);

  int top() const { return top_; }  // levels 0 .. top-1 are stored; `top` is the whole box
  int count(int level, int axis) const { return counts_[level][axis]; }
  double side(int level, int axis) const { return side_[level][axis]; }
  // The finest level whose cells hold an extent (per axis), top() if none.
  int level_for(const Vector3& extent) const;
  // Cell-index range of the interval [low, high] per axis at a level.
  Range range_of(int level, const Vector3& low, const Vector3& high) const;
  const Range& range(std::uint32_t cluster, int level) const { return range_[cluster * std::size_t(top_) + level]; }

  // (Re)registers at `level`, as an owner (the cluster's own level) or a passenger (a coarser level); a
  // re-registration keeps the role it had there.
  void place(std::uint32_t cluster, int level, const Range& r, bool owner);
  void remove(std::uint32_t cluster, int level, bool owner);  // no-op if not registered there

  // Distinct cell indices covered by a range at a level; returns their number (<= 2^d).
  int cells(int level, const Range& r, std::array<std::uint32_t, 8>& out) const;
  bool share_cell(int level, const Range& a, const Range& b) const;
  // Clusters living at `level` (owners) or at a finer level (passengers) in a cell.
  const std::vector<Entry>& owners(int level, std::uint32_t cell) const { return cells_[level][cell].owners; }
  const std::vector<Entry>& passengers(int level, std::uint32_t cell) const { return cells_[level][cell].passengers; }

  // Checkpoints: the cells' owners and passengers, every cluster's ranges and slots (the shape is the
  // constructor's).
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  int wrap(int level, int axis, std::int64_t i) const;
  std::uint32_t cell_at(int level, const Range& r, int slot, bool& valid) const;
  // Takes the entry at position `at` out of a cell's list (the last entry fills the hole).
  void erase(int level, std::uint32_t cell, bool owner, std::uint32_t at);

  Box box_;
  int slots_;  // 2^d
  int top_ = 0;
  std::vector<std::array<int, 3>> counts_;
  std::vector<Vector3> side_;
  struct Cell {
    std::vector<Entry> owners, passengers;
  };
  std::vector<std::vector<Cell>> cells_;  // [level][cell]
  std::vector<Range> range_;                             // [cluster * top + level]
  std::vector<std::uint32_t> where_;                     // [(cluster * top + level) * slots + slot]
};

}  // namespace aggkit
