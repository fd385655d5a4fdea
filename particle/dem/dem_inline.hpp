#pragma once
// Member templates and the minimum-image separation of the DEM engine, shared by its source files (dem.cpp,
// dem_contacts.cpp, dem_integration.cpp).
#include <algorithm>
#include <cmath>

#include "particle/dem/dem.hpp"
#include "particle/dem/near_pair_cells.hpp"

namespace aggkit {

inline Vector3 Dem::separation(std::size_t i, std::size_t j) const {
  Vector3 d = x_[j] - x_[i];
  if (periodic_)  // positions lie in [0, L): |d| < L, one image shift at most
    for (int k = 0; k < 3; ++k) d[k] += d[k] > half_side_[k] ? -side_[k] : d[k] < -half_side_[k] ? side_[k] : 0.0;
  return d;
}

template <class Visit>
void Dem::for_each_near_pair(double range, std::size_t parts, Visit&& visit) const {
  const NearPairCells grid = near_pair_cells(x_, box_, range);
  const std::array<std::int64_t, 3>& cells = grid.cells;
  const std::vector<std::uint32_t>& start = grid.start;
  const std::vector<std::uint32_t>& order = grid.order;
  const std::vector<std::array<int, 3>>& forward = grid.forward;
  const bool periodic = grid.periodic;
  // Each pair of particles once: the pairs within a cell, then those with the 13 neighbour cells of the
  // forward half of the stencil (the other 13 meet this cell from their side). With periodic images every
  // axis has 1 or at least 3 cells, so no neighbour cell is met twice. Slabs of z cells as parts (on the worker pool when there is one).
  parts = std::clamp<std::size_t>(parts, 1, std::size_t(cells[2]));
  auto slab = [&](std::size_t part) {
    const std::int64_t z0 = std::int64_t(part) * cells[2] / std::int64_t(parts), z1 = std::int64_t(part + 1) * cells[2] / std::int64_t(parts);
    for (std::int64_t cz = z0; cz < z1; ++cz)
      for (std::int64_t cy = 0; cy < cells[1]; ++cy)
        for (std::int64_t cx = 0; cx < cells[0]; ++cx) {
          const std::size_t c = std::size_t((cz * cells[1] + cy) * cells[0] + cx);
          if (start[c] == start[c + 1]) continue;
          for (std::uint32_t a = start[c]; a < start[c + 1]; ++a)
            for (std::uint32_t b = a + 1; b < start[c + 1]; ++b) visit(part, std::min(order[a], order[b]), std::max(order[a], order[b]));
          const std::int64_t own[3] = {cx, cy, cz};
          for (const std::array<int, 3>& off : forward) {
            std::int64_t other[3];
            bool skip = false;
            for (int d = 0; d < 3 && !skip; ++d) {
              other[d] = own[d] + off[d];
              if (periodic) other[d] = (other[d] + cells[d]) % cells[d];
              else if (other[d] < 0 || other[d] >= cells[d]) skip = true;
            }
            if (skip) continue;
            const std::size_t c2 = std::size_t((other[2] * cells[1] + other[1]) * cells[0] + other[0]);
            for (std::uint32_t a = start[c]; a < start[c + 1]; ++a)
              for (std::uint32_t b = start[c2]; b < start[c2 + 1]; ++b) visit(part, std::min(order[a], order[b]), std::max(order[a], order[b]));
          }
        }
  };
  if (pool_ && parts > 1) pool_->run(parts, slab);
  else
    for (std::size_t part = 0; part < parts; ++part) slab(part);
}

template <class Job>
void Dem::parallel(std::size_t jobs, Job&& job) {
  if (pool_) pool_->run(jobs, job);
  else
    for (std::size_t k = 0; k < jobs; ++k) job(k);
}

}  // namespace aggkit
