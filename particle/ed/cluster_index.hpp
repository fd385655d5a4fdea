#pragma once
// Static spatial index of each rigid cluster's members in the cluster's own frame: members are hashed by
// (cluster, cell of their offset), cells at least one contact distance wide (the CellGrid of the box), so a
// point's contacts within a cluster lie in the 3^d stencil of its cell. Along periodic axes the cell is taken
// modulo the grid (offsets wrapped into the box), so clusters larger than the box are indexed too and
// distances are taken by minimum image. A merge moves the smaller cluster's members only: O(small).
// Open addressing with linear probing and backward-shift deletion; one intrusive list of members per key.
// A cast through a large, sparse (fractal) cluster mostly asks for empty cells, and every probe of the
// table is a cache miss at 10^5–10^6 particles. A counting filter in front of it — one small counter per
// bucket of another hash of the key, the number of occupied keys there — answers most of those questions
// from an array several times smaller than the table: a zero counter means no member there.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/checkpoint.hpp"

#include "particle/common/cell_grid.hpp"

namespace aggkit {

class ClusterIndex {
 public:
  static constexpr std::uint32_t none = 0xffffffffu;

  ClusterIndex(const Box& box, double contact, std::size_t particles);

  const CellGrid& grid() const { return grid_; }
  // Unwrapped integer cell of an offset: floor(offset / cell side) per axis (0 beyond the dimension).
  CellCoords cell_of(const Vector3& offset) const;
  void insert(std::uint32_t cluster, std::uint32_t particle, const Vector3& offset);
  void erase(std::uint32_t cluster, std::uint32_t particle, const Vector3& offset);
  // First member of `cluster` in `cell` (unwrapped; wrapped here along periodic axes), none if empty.
  std::uint32_t first(std::uint32_t cluster, const CellCoords& cell) const;
  std::uint32_t next(std::uint32_t particle) const { return next_[particle]; }

  // Checkpoints: the hash table and member lists as they are.
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  struct Slot {
    std::uint64_t k1 = 0, k2 = 0;
    std::uint32_t head = none;  // none: empty slot
  };
  void key(std::uint32_t cluster, CellCoords c, std::uint64_t& k1, std::uint64_t& k2) const;
  std::size_t home(std::uint64_t k1, std::uint64_t k2) const;
  std::size_t bucket(std::uint64_t k1, std::uint64_t k2) const;  // the filter's counter of a key
  void count(std::size_t b, int change);                          // saturating: a full counter stays full
  void refilter();                                                // the filter from the table
  std::size_t find(std::uint64_t k1, std::uint64_t k2) const;  // slot holding the key or the empty slot ending its run
  void grow();

  CellGrid grid_;
  bool periodic_;
  int dimension_;
  std::vector<Slot> slots_;
  std::size_t used_ = 0;
  std::vector<std::uint32_t> next_;
  std::vector<std::uint8_t> filter_;  // occupied keys per bucket (a power of two, >= 4 per particle)
};

}  // namespace aggkit
