#pragma once
// A regular grid of cells over the box, each at least `min_side` wide along every axis, so that two
// particles closer than min_side always sit in the same or in neighbouring cells (the 3^d stencil).
// Periodic axes need at least 3 cells so that the stencil cells are distinct.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "particle/common/box.hpp"

namespace aggkit {

using CellCoords = std::array<int, 3>;

class CellGrid {
 public:
  // Cells of side >= max(min_side, (V/target_cells)^{1/d}); throws InputError for an open boundary (no box)
  // and when a periodic axis cannot hold 3 cells of side min_side.
  CellGrid(const Box& box, double min_side, std::size_t target_cells);

  const Box& box() const { return box_; }
  const CellCoords& counts() const { return counts_; }
  const Vector3& cell_side() const { return cell_side_; }
  std::size_t size() const { return size_; }

  // The cell of a position (wrapped onto periodic axes, clamped onto the grid along reflecting ones).
  CellCoords coords_of(const Vector3& position) const {  // inline: called per particle per step by the engines
    const Vector3 p = box_.boundary == Boundary::periodic ? box_.wrap(position) : position;
    CellCoords c{0, 0, 0};
    for (int d = 0; d < box_.dimension; ++d)
      c[d] = std::clamp(int(std::floor(p[d] / cell_side_[d])), 0, counts_[d] - 1);
    return c;
  }
  std::size_t index(const CellCoords& c) const { return std::size_t(c[0]) + std::size_t(counts_[0]) * (std::size_t(c[1]) + std::size_t(counts_[1]) * std::size_t(c[2])); }
  CellCoords coords(std::size_t index) const;
  // The cell at c + offset: wrapped along periodic axes, std::nullopt past a reflecting wall.
  std::optional<CellCoords> neighbour(const CellCoords& c, const CellCoords& offset) const;
  // The stencil offsets {-1,0,1}^d (with a 0 third component in 2-D).
  const std::vector<CellCoords>& stencil() const { return stencil_; }
  // The separation d from a point in some cell to one in the stencil cell at `offset` from it, as the
  // periodic image that offset stands for: along periodic axes d − kL nearest to offset · cell side (with
  // >= 3 cells per axis that is the contact image of any pair within a cell side). Unchanged otherwise.
  Vector3 stencil_image(Vector3 d, const CellCoords& offset) const {
    if (box_.boundary == Boundary::periodic)
      for (int a = 0; a < box_.dimension; ++a)
        d[a] -= box_.side[a] * std::nearbyint((d[a] - offset[a] * cell_side_[a]) / box_.side[a]);
    return d;
  }

 private:
  Box box_;
  CellCoords counts_{1, 1, 1};
  Vector3 cell_side_{};
  std::size_t size_ = 1;
  std::vector<CellCoords> stencil_;
};

}  // namespace aggkit
