#pragma once
// A configuration of spheres (3-D) or discs (2-D) in a box, as the particle engines (ED, TS, DEM) hand it to
// the observables (clusters, shape, fractal dimension); plus the geometric primitives every observable
// shares. One radius for every particle, or each its own (`radii`): contact ranges are then those of the
// pair (R_i + R_j), the equal-radius results the special case.
#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "analysis/neighbour_grid.hpp"

namespace aggkit {

struct ParticleConfiguration {
  int dimension = 2;                             // 2 or 3
  double radius = 0;                             // equal radii R; with `radii` their mean, the reference radius
  std::vector<double> radii;                     // per-particle radii R_i, or empty: every particle has `radius`
  std::array<double, 3> box{};                   // box sides; the box is [0, box[d]) per axis
  bool periodic = false;                         // minimum-image distances if true
  std::vector<std::array<double, 3>> positions;  // z = 0 (ignored) in 2-D

  double radius_of(std::size_t i) const { return radii.empty() ? radius : radii[i]; }
  double largest_radius() const;
};

// Contact ranges. A range `contact_distance` is given for two spheres of the reference radius (2.1 R: the
// contacts of [Degond2024]); a pair of radii R_i, R_j is in contact within contact_distance (R_i + R_j)/(2R),
// i.e. R_i + R_j plus the same relative tolerance. Calls visit(i, j, delta, distance²) once for every pair in
// contact (a neighbour grid, O(N); minimum image when periodic) among `points`, whose radii are
// `point_radii` (empty: all `config.radius`).
template <class Visit>
void for_each_contact(const ParticleConfiguration& config, std::span<const std::array<double, 3>> points,
                      std::span<const double> point_radii, double contact_distance, Visit&& visit);

// Throws InputError (analysis/input_error.hpp) naming the offending field unless: dimension is 2 or 3,
// radius > 0 and finite, radii empty or one per position, each > 0 and finite, every used box side > 0 and
// finite when periodic, positions finite.
void check_configuration(const ParticleConfiguration& config);

// E = ½ Σ m_i |v_i|^2 (all three components; z is 0 in 2-D). Sizes must agree (InputError otherwise).
double kinetic_energy(std::span<const double> mass, std::span<const std::array<double, 3>> velocity);

// X_j - X_i, reduced to the minimum image along each of the first `dimension` axes when periodic.
std::array<double, 3> separation(const ParticleConfiguration& config, const std::array<double, 3>& from,
                                 const std::array<double, 3>& to);

inline double squared_norm(const std::array<double, 3>& v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; }

template <class Visit>
void for_each_contact(const ParticleConfiguration& config, std::span<const std::array<double, 3>> points,
                      std::span<const double> point_radii, double contact_distance, Visit&& visit) {
  if (point_radii.empty()) {  // one radius: the grid's cutoff is the contact range
    NeighbourGrid grid(points, config.dimension, contact_distance, config.box, config.periodic);
    grid.for_each_pair(visit);
    return;
  }
  double largest = 0;
  for (double r : point_radii) largest = std::max(largest, r);
  const double scale = contact_distance / (2 * config.radius);
  // The grid reports every pair within the largest range (with a margin against its rounding); each pair
  // is then held to its own.
  NeighbourGrid grid(points, config.dimension, scale * 2 * largest * (1 + 1e-12), config.box, config.periodic);
  grid.for_each_pair([&](std::size_t i, std::size_t j, const auto& delta, double d2) {
    const double reach = scale * (point_radii[i] + point_radii[j]);
    if (d2 <= reach * reach) visit(i, j, delta, d2);
  });
}

}  // namespace aggkit
