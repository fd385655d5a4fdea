#include "analysis/neighbour_grid.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "analysis/input_error.hpp"

namespace aggkit {

NeighbourGrid::NeighbourGrid(std::span<const std::array<double, 3>> points, int dimension, double cutoff,
                             const std::array<double, 3>& box, bool periodic)
    : dimension_(dimension), cutoff2_(cutoff * cutoff), box_(box), periodic_(periodic) {
  if (dimension != 2 && dimension != 3) throw InputError("dimension", std::to_string(dimension), "must be 2 or 3");
  if (!(cutoff > 0) || !std::isfinite(cutoff))
    throw InputError("cutoff", format_value(cutoff), "the neighbour cutoff must be positive and finite");
  std::array<double, 3> origin{}, side{1, 1, 1};
  for (int a = 0; a < dimension; ++a) {
    if (periodic) {
      if (!(box[a] > 0) || !std::isfinite(box[a]))
        throw InputError("box[" + std::to_string(a) + "]", format_value(box[a]), "a periodic box needs positive sides");
      side[a] = box[a];
    } else if (!points.empty()) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& p : points) lo = std::min(lo, p[a]), hi = std::max(hi, p[a]);
      origin[a] = lo;
      side[a] = std::max(hi - lo, cutoff);
    }
    cells_[a] = int(std::clamp(std::floor(side[a] / cutoff), 1.0, 1e6));
  }
  // Cap the number of cells near 2N + 8 so that memory and the sweep stay O(N) for sparse sets.
  const double cap = 2.0 * double(points.size()) + 8.0;
  double total = double(cells_[0]) * cells_[1] * cells_[2];
  if (total > cap) {
    const double shrink = std::pow(cap / total, 1.0 / dimension);
    for (int a = 0; a < dimension; ++a) cells_[a] = std::max(1, int(std::floor(cells_[a] * shrink)));
  }
  const std::size_t cell_total = std::size_t(cells_[0]) * cells_[1] * cells_[2];

  // Counting sort of the points by cell.
  std::vector<std::size_t> cell_of(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::size_t index = 0;
    for (int a = dimension - 1; a >= 0; --a) {
      double x = points[i][a] - origin[a];
      if (periodic) x -= side[a] * std::floor(x / side[a]);
      const int c = std::clamp(int(x / side[a] * cells_[a]), 0, cells_[a] - 1);
      index = index * std::size_t(cells_[a]) + std::size_t(c);
    }
    cell_of[i] = index;
  }
  cell_start_.assign(cell_total + 1, 0);
  for (std::size_t c : cell_of) ++cell_start_[c + 1];
  for (std::size_t c = 0; c < cell_total; ++c) cell_start_[c + 1] += cell_start_[c];
  order_.resize(points.size());
  std::vector<std::size_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) order_[fill[cell_of[i]]++] = i;
  // Cell-ordered copies (contiguous sweeps); periodic coordinates wrapped into [0, L) so that a neighbour
  // cell across the wall is reached by a shift of ±L (exact minimum image when the axis has >= 3 cells,
  // since the cutoff is then <= L/3).
  sorted_.resize(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    sorted_[p] = {0, 0, 0};
    for (int a = 0; a < dimension; ++a) {
      double x = points[order_[p]][a];
      if (periodic) x -= side[a] * std::floor(x / side[a]);
      sorted_[p][a] = x;
    }
  }
  for (int a = 0; a < dimension; ++a) nearest_image_[a] = periodic && cells_[a] < 3;
}

int NeighbourGrid::neighbours(int axis, int c, std::array<int, 3>& out, std::array<double, 3>& shift) const {
  const int n = cells_[axis];
  int count = 0;
  for (int offset = -1; offset <= 1; ++offset) {
    int other = c + offset;
    double image = 0;
    if (periodic_) {
      if (other < 0) other += n, image = -box_[axis];
      if (other >= n) other -= n, image = box_[axis];
      if (nearest_image_[axis] || axis >= dimension_) image = 0;  // reduced per pair instead / unused axis
    } else if (other < 0 || other >= n) {
      continue;
    }
    if (std::find(out.begin(), out.begin() + count, other) == out.begin() + count) {
      shift[count] = image;
      out[count++] = other;
    }
  }
  return count;
}

}  // namespace aggkit
