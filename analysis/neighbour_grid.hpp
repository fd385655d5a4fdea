#pragma once
// Cell list for finding every pair of points closer than a cutoff in O(N) (cells of side >= cutoff, so a
// pair within the cutoff lies in the same or adjacent cells). Periodic boxes use minimum-image
// separations; with fewer than three cells along an axis each neighbouring cell is still visited once.
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

namespace aggkit {

class NeighbourGrid {
 public:
  // The grid keeps its own copy of the points. Only the first `dimension` coordinates are used. If `periodic`, the
  // box is [0, box[d]) per axis (points outside are wrapped for binning); otherwise the grid spans the
  // points' bounding box. The number of cells is capped near 2N (cells then grow beyond the cutoff).
  NeighbourGrid(std::span<const std::array<double, 3>> points, int dimension, double cutoff,
                const std::array<double, 3>& box = {}, bool periodic = false);

  // Calls visit(i, j, delta, distance²) once for every unordered pair i != j with |X_j - X_i| <= cutoff,
  // where delta = X_j - X_i (minimum image if periodic).
  template <class Visit>
  void for_each_pair(Visit&& visit) const;

  std::size_t cell_count() const { return cell_start_.size() - 1; }

 private:
  // The distinct cells adjacent to (and including) coordinate c along `axis`, with the shift that takes a
  // point of that cell to its image next to cell c; returns how many.
  int neighbours(int axis, int c, std::array<int, 3>& out, std::array<double, 3>& shift) const;

  int dimension_;
  double cutoff2_;
  std::array<double, 3> box_;
  bool periodic_;
  std::array<int, 3> cells_{1, 1, 1};
  std::vector<std::size_t> cell_start_;  // members of cell c: order_[cell_start_[c] .. cell_start_[c+1])
  std::vector<std::size_t> order_;
  std::vector<std::array<double, 3>> sorted_;  // the points in cell order (wrapped into the box if periodic)
  std::array<bool, 3> nearest_image_{};        // periodic axis with < 3 cells: reduce each separation
};

template <class Visit>
void NeighbourGrid::for_each_pair(Visit&& visit) const {
  const int nx = cells_[0], ny = cells_[1], nz = cells_[2];
  std::array<std::array<int, 3>, 3> adjacent{};
  std::array<std::array<double, 3>, 3> shift{};
  std::array<int, 3> count{1, 1, 1};
  const bool reduce = nearest_image_[0] || nearest_image_[1] || nearest_image_[2];
  for (int cz = 0; cz < nz; ++cz) {
    count[2] = neighbours(2, cz, adjacent[2], shift[2]);
    for (int cy = 0; cy < ny; ++cy) {
      count[1] = neighbours(1, cy, adjacent[1], shift[1]);
      for (int cx = 0; cx < nx; ++cx) {
        count[0] = neighbours(0, cx, adjacent[0], shift[0]);
        const std::size_t cell = std::size_t(cx) + std::size_t(nx) * (std::size_t(cy) + std::size_t(ny) * cz);
        const std::size_t begin = cell_start_[cell], end = cell_start_[cell + 1];
        if (begin == end) continue;
        for (int a = 0; a < count[2]; ++a)
          for (int b = 0; b < count[1]; ++b)
            for (int c = 0; c < count[0]; ++c) {
              const std::size_t other =
                  std::size_t(adjacent[0][c]) + std::size_t(nx) * (std::size_t(adjacent[1][b]) + std::size_t(ny) * adjacent[2][a]);
              if (other < cell) continue;  // each unordered pair of cells once
              const std::array<double, 3> offset{shift[0][c], shift[1][b], shift[2][a]};
              const std::size_t other_end = cell_start_[other + 1];
              for (std::size_t p = begin; p < end; ++p) {
                const std::array<double, 3> xi = sorted_[p];
                for (std::size_t q = other == cell ? p + 1 : cell_start_[other]; q < other_end; ++q) {
                  std::array<double, 3> d{sorted_[q][0] + offset[0] - xi[0], sorted_[q][1] + offset[1] - xi[1],
                                          sorted_[q][2] + offset[2] - xi[2]};
                  if (reduce)
                    for (int k = 0; k < dimension_; ++k)
                      if (nearest_image_[k]) d[k] -= box_[k] * std::nearbyint(d[k] / box_[k]);
                  const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                  if (d2 <= cutoff2_) visit(order_[p], order_[q], d, d2);
                }
              }
            }
      }
    }
  }
}

}  // namespace aggkit
