#pragma once
// A configuration of equal spheres (3-D) or discs (2-D) in a box, as the particle engines (ED, TS, DEM)
// hand it to the observables (clusters, shape, fractal dimension); plus the geometric primitives every
// observable shares.
#include <array>
#include <span>
#include <vector>

namespace aggkit {

struct ParticleConfiguration {
  int dimension = 2;                             // 2 or 3
  double radius = 0;                             // equal radii R
  std::array<double, 3> box{};                   // box sides; the box is [0, box[d]) per axis
  bool periodic = false;                         // minimum-image distances if true
  std::vector<std::array<double, 3>> positions;  // z = 0 (ignored) in 2-D
};

// Throws InputError (analysis/input_error.hpp) naming the offending field unless: dimension is 2 or 3,
// radius > 0 and finite, every used box side > 0 and finite when periodic, positions finite.
void check_configuration(const ParticleConfiguration& config);

// E = ½ Σ m_i |v_i|^2 (all three components; z is 0 in 2-D). Sizes must agree (InputError otherwise).
double kinetic_energy(std::span<const double> mass, std::span<const std::array<double, 3>> velocity);

// X_j - X_i, reduced to the minimum image along each of the first `dimension` axes when periodic.
std::array<double, 3> separation(const ParticleConfiguration& config, const std::array<double, 3>& from,
                                 const std::array<double, 3>& to);

inline double squared_norm(const std::array<double, 3>& v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; }

}  // namespace aggkit
