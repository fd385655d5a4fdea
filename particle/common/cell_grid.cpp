#include "particle/common/cell_grid.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/input_error.hpp"

namespace aggkit {

CellGrid::CellGrid(const Box& box, double min_side, std::size_t target_cells) : box_(box) {
  box.validate();
  if (box.boundary == Boundary::open)
    throw InputError("boundary", "\"open\"", "\"periodic\" or \"reflecting\": a cell grid covers a finite box");
  const double wanted = std::max(min_side, std::pow(box.volume() / double(std::max<std::size_t>(target_cells, 1)),
                                                    1.0 / box.dimension));
  for (int d = 0; d < 3; ++d) {
    if (d >= box.dimension) {
      counts_[d] = 1;
      cell_side_[d] = 0.0;
      continue;
    }
    const double n = std::floor(box.side[d] / wanted);
    counts_[d] = int(std::clamp(n, 1.0, 1.0e6));
    if (box.boundary == Boundary::periodic && box.side[d] < 3 * min_side)
      throw InputError("box", format_value(box.side[d]),
                       "a periodic box side of at least 3 contact distances (" + format_value(3 * min_side) + ")");
    if (box.boundary == Boundary::periodic) counts_[d] = std::max(counts_[d], 3);
    cell_side_[d] = box.side[d] / counts_[d];
  }
  size_ = std::size_t(counts_[0]) * std::size_t(counts_[1]) * std::size_t(counts_[2]);
  const int reach_z = box.dimension == 3 ? 1 : 0;
  for (int z = -reach_z; z <= reach_z; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x) stencil_.push_back({x, y, z});
}

CellCoords CellGrid::coords(std::size_t index) const {
  CellCoords c;
  c[0] = int(index % std::size_t(counts_[0]));
  index /= std::size_t(counts_[0]);
  c[1] = int(index % std::size_t(counts_[1]));
  c[2] = int(index / std::size_t(counts_[1]));
  return c;
}

std::optional<CellCoords> CellGrid::neighbour(const CellCoords& c, const CellCoords& offset) const {
  CellCoords n;
  for (int d = 0; d < 3; ++d) {
    n[d] = c[d] + offset[d];
    if (n[d] >= 0 && n[d] < counts_[d]) continue;
    if (box_.boundary != Boundary::periodic || d >= box_.dimension) return std::nullopt;
    n[d] = (n[d] + counts_[d]) % counts_[d];
  }
  return n;
}

}  // namespace aggkit
