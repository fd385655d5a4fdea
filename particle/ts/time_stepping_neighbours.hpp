#pragma once
// The neighbour walk shared by contact detection and the minimisation of the time-stepping engine, and the
// split of a loop over the workers (member templates of TimeSteppingAggregation, defined here for the
// source files that use them).
#include <algorithm>
#include <cmath>
#include <vector>

#include "particle/ts/time_stepping_aggregation.hpp"

namespace aggkit {

template <class F>
void TimeSteppingAggregation::for_near(std::uint32_t i, double reach, F&& f) const {
  const CellCoords c = grid_.coords_of(x_[i]);
  int k[3] = {0, 0, 0};
  for (int d = 0; d < box_.dimension; ++d) k[d] = int(std::ceil(reach / grid_.cell_side()[d] - 1e-12));
  // A small sorted set of cells: periodic axes with fewer than 2k+1 cells would visit a cell twice.
  thread_local std::vector<std::size_t> visit;
  visit.clear();
  for (int z = -k[2]; z <= k[2]; ++z)
    for (int y = -k[1]; y <= k[1]; ++y)
      for (int xo = -k[0]; xo <= k[0]; ++xo)
        if (const auto n = grid_.neighbour(c, {xo, y, z})) visit.push_back(grid_.index(*n));
  std::sort(visit.begin(), visit.end());
  visit.erase(std::unique(visit.begin(), visit.end()), visit.end());
  for (const std::size_t cell : visit)
    for (std::uint32_t j = cells_.first(cell); j != CellList::none; j = cells_.next(j))
      if (j != i) f(j);
}

template <class F>
void TimeSteppingAggregation::for_stencil(std::uint32_t i, F&& f) const {
  const std::uint32_t* row = &neighbours_[cells_.cell_of(i) * stencil_.size()];
  for (std::size_t k = 0; k < stencil_.size(); ++k)
    if (row[k] != no_cell)
      for (std::uint32_t j = cells_.first(row[k]); j != CellList::none; j = cells_.next(j))
        if (j != i) f(j, grid_.stencil_image(x_[j] - x_[i], stencil_[k]));
}

template <class F>
void TimeSteppingAggregation::for_ranges(std::size_t n, F&& f) const {
  const std::size_t workers = n >= parallel_cells ? thread_count() : 1;
  if (workers <= 1) return f(std::size_t(0), n, std::size_t(0));
  // Range w on thread w, phase after phase: each range stays in one core's cache (worker_pool.hpp).
  pool_->run_each([&](std::size_t w) { f(n * w / workers, n * (w + 1) / workers, w); });
}

}  // namespace aggkit
