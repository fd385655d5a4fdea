#include "particle/dem/near_pair_cells.hpp"

#include <algorithm>
#include <cmath>

namespace aggkit {

namespace {

// Cells per axis at least `range` wide over `extent`, refined until at most max(27, 4 n) in all.
std::array<std::int64_t, 3> cell_counts(const Vector3& extent, double range, bool periodic, std::size_t n) {
  double h = range;
  std::array<std::int64_t, 3> cells{1, 1, 1};
  for (int attempt = 0; attempt < 64; ++attempt) {
    double total = 1;
    for (int d = 0; d < 3; ++d) {
      cells[d] = std::max<std::int64_t>(1, std::int64_t(std::floor(extent[d] / h)));
      if (periodic && cells[d] < 3) cells[d] = 1;  // fewer than 3 cells: one cell, so no neighbour is met twice
      total *= double(cells[d]);
    }
    if (total <= std::max(27.0, 4.0 * double(n))) break;
    h *= std::cbrt(total / std::max(27.0, 4.0 * double(n))) * 1.01;  // sparse cloud: coarser cells
  }
  return cells;
}

std::vector<std::array<int, 3>> forward_offsets(const std::array<std::int64_t, 3>& cells) {
  std::vector<std::array<int, 3>> forward;
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const int off[3] = {ox, oy, oz};
        bool used = true;
        for (int d = 0; d < 3; ++d) used = used && !(cells[d] == 1 && off[d] != 0);
        // forward: the first non-zero offset (z, then y, then x) is positive
        const int lead = oz != 0 ? oz : oy != 0 ? oy : ox;
        if (used && lead > 0) forward.push_back({ox, oy, oz});
      }
  return forward;
}

}  // namespace

NearPairCells near_pair_cells(const std::vector<Vector3>& x, const Box& box, double range) {
  const std::size_t n = x.size();
  NearPairCells g;
  g.periodic = box.boundary == Boundary::periodic;
  // Grid region per axis: the box for periodic/reflecting, the particles' bounding box when open.
  Vector3 lo{0, 0, 0}, extent{0, 0, 0};
  if (box.boundary == Boundary::open) {
    Vector3 hi = x[0];
    lo = x[0];
    for (const Vector3& p : x)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
    extent = hi - lo;
  } else {
    extent = box.side;
  }
  g.cells = cell_counts(extent, range, g.periodic, n);
  const auto& cells = g.cells;
  std::array<double, 3> inverse{};
  for (int d = 0; d < 3; ++d) inverse[d] = extent[d] > 0 ? double(cells[d]) / extent[d] : 0.0;
  const std::size_t total = std::size_t(cells[0] * cells[1] * cells[2]);
  std::vector<std::uint32_t> cell_of(n);
  g.start.assign(total + 1, 0);
  g.order.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t c[3];
    for (int d = 0; d < 3; ++d) c[d] = std::clamp<std::int64_t>(std::int64_t(std::floor((x[i][d] - lo[d]) * inverse[d])), 0, cells[d] - 1);
    cell_of[i] = std::uint32_t((c[2] * cells[1] + c[1]) * cells[0] + c[0]);
    ++g.start[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < total; ++c) g.start[c + 1] += g.start[c];
  std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) g.order[fill[cell_of[i]]++] = std::uint32_t(i);
  g.forward = forward_offsets(cells);
  return g;
}

}  // namespace aggkit
