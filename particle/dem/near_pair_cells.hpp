#pragma once
// The cell binning behind Dem::for_each_near_pair (dem_inline.hpp): cells at least `range` wide over the box
// (or, in open space, over the particles' bounding box), the particles sorted by cell, and the forward half
// of the 3^3 stencil.
#include <array>
#include <cstdint>
#include <vector>

#include "particle/common/box.hpp"

namespace aggkit {

struct NearPairCells {
  std::array<std::int64_t, 3> cells{1, 1, 1};  // per axis; periodic axes have 1 or at least 3
  bool periodic = false;
  std::vector<std::uint32_t> start;  // per cell c: its particles are order[start[c]] .. order[start[c + 1] - 1]
  std::vector<std::uint32_t> order;  // the particles by cell, increasing within a cell
  // The neighbour offsets whose first non-zero component (z, then y, then x) is positive, along axes of more
  // than one cell: each neighbouring pair of cells once.
  std::vector<std::array<int, 3>> forward;
};

// At most max(27, 4 N) cells (coarser cells for a sparse cloud).
NearPairCells near_pair_cells(const std::vector<Vector3>& x, const Box& box, double range);

}  // namespace aggkit
