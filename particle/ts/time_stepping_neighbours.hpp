#pragma once
// The neighbour walk shared by contact detection and the minimisation of the time-stepping engine.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "particle/common/cell_grid.hpp"
#include "particle/common/cell_list.hpp"

namespace aggkit {

// f(j) for every sphere j != i of the cell list within `reach` cells' span of sphere i (at x[i]).
template <class F>
void for_near(const CellGrid& grid, const CellList& cells, const std::vector<Vector3>& x, std::uint32_t i, double reach,
              F&& f) {
  const CellCoords c = grid.coords_of(x[i]);
  int k[3] = {0, 0, 0};
  for (int d = 0; d < grid.box().dimension; ++d) k[d] = int(std::ceil(reach / grid.cell_side()[d] - 1e-12));
  // A small sorted set of cells: periodic axes with fewer than 2k+1 cells would visit a cell twice.
  thread_local std::vector<std::size_t> visit;
  visit.clear();
  for (int z = -k[2]; z <= k[2]; ++z)
    for (int y = -k[1]; y <= k[1]; ++y)
      for (int xo = -k[0]; xo <= k[0]; ++xo)
        if (const auto n = grid.neighbour(c, {xo, y, z})) visit.push_back(grid.index(*n));
  std::sort(visit.begin(), visit.end());
  visit.erase(std::unique(visit.begin(), visit.end()), visit.end());
  for (const std::size_t cell : visit)
    for (std::uint32_t j = cells.first(cell); j != CellList::none; j = cells.next(j))
      if (j != i) f(j);
}

}  // namespace aggkit
