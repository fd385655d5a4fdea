#pragma once
// Point sets of known geometry for the configuration-analysis tests: lattices, lines, Sierpinski
// triangles and hexagonal patches made of touching discs of radius R (centre spacing 2R).
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace aggkit::testing {

using Points = std::vector<std::array<double, 3>>;

// nx × ny (× nz) simple square/cubic lattice of spacing 2R, lower corner at `origin`.
inline Points cubic_lattice(int nx, int ny, int nz, double radius, std::array<double, 3> origin = {}) {
  Points p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        p.push_back({origin[0] + 2 * radius * i, origin[1] + 2 * radius * j, origin[2] + 2 * radius * k});
  return p;
}

// n touching discs on a straight line through the origin at angle `angle` to x.
inline Points line(int n, double radius, double angle = 0) {
  Points p;
  for (int i = 0; i < n; ++i)
    p.push_back({2 * radius * i * std::cos(angle), 2 * radius * i * std::sin(angle), 0});
  return p;
}

// Sierpinski triangle of generation g (3^g discs): the lattice points (i, j), 0 <= i, j < 2^g, with
// i AND j = 0 (Pascal's triangle mod 2). Right-angled: the points sit on the square lattice of spacing 2R;
// equilateral: on the triangular lattice (x = 2R(i + j/2), y = 2R j √3/2), so neighbours touch.
inline Points sierpinski(int generation, double radius, bool equilateral) {
  Points p;
  const int n = 1 << generation;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if ((i & j) == 0) {
        if (equilateral) p.push_back({2 * radius * (i + 0.5 * j), 2 * radius * j * std::sqrt(3.0) / 2, 0});
        else p.push_back({2 * radius * i, 2 * radius * j, 0});
      }
  return p;
}

// Hexagon-shaped patch of the triangular lattice (spacing 2R) with `side` particles per edge:
// 3 side (side - 1) + 1 particles, centred at `centre`.
inline Points hexagonal_patch(int side, double radius, std::array<double, 3> centre = {}) {
  Points p;
  const int m = side - 1;
  for (int j = -m; j <= m; ++j)
    for (int i = -m; i <= m; ++i)
      if (std::abs(i + j) <= m)  // axial coordinates (i, j) within hexagonal distance m
        p.push_back({centre[0] + 2 * radius * (i + 0.5 * j), centre[1] + 2 * radius * j * std::sqrt(3.0) / 2, 0});
  return p;
}

}  // namespace aggkit::testing
