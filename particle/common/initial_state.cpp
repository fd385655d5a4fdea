#include "particle/common/initial_state.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include "analysis/input_error.hpp"

namespace aggkit {

std::vector<Vector3> lattice_positions(const Box& box, std::size_t count, double radius) {
  box.validate();
  std::size_t per_axis = std::size_t(std::ceil(std::pow(double(count), 1.0 / box.dimension) - 1e-9));
  while (std::pow(double(per_axis), box.dimension) < double(count)) ++per_axis;
  Vector3 spacing{0, 0, 0};
  for (int d = 0; d < box.dimension; ++d) {
    spacing[d] = box.side[d] / double(per_axis);
    // Neighbours at distance a_d must not overlap (a_d >= 2R); along reflecting walls the first and last
    // sites at a_d/2 must be at least R from the wall, which is the same condition.
    if (spacing[d] < 2 * radius)
      throw InputError("volume_fraction", format_value(volume_fraction(box, count, radius)),
                       "a volume fraction at which " + std::to_string(count) + " particles fit on a lattice of " +
                           std::to_string(per_axis) + " sites per axis without overlapping (spacing >= 2R)");
  }
  std::vector<Vector3> positions;
  positions.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    std::size_t rest = k;
    Vector3 x{0, 0, 0};
    for (int d = 0; d < box.dimension; ++d) {
      x[d] = (double(rest % per_axis) + 0.5) * spacing[d];
      rest /= per_axis;
    }
    positions.push_back(x);
  }
  return positions;
}

std::vector<Vector3> initial_velocities(int dimension, std::size_t count, VelocityLaw law, double speed,
                                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vector3> v(count, Vector3{0, 0, 0});
  if (law == VelocityLaw::fixed_speed) {
    std::uniform_real_distribution<double> angle(0.0, 2 * std::numbers::pi);
    std::uniform_real_distribution<double> cosine(-1.0, 1.0);
    for (auto& u : v) {
      const double phi = angle(rng);
      if (dimension == 2) {
        u = {speed * std::cos(phi), speed * std::sin(phi), 0.0};
      } else {  // uniform on the sphere: cos θ uniform in [-1, 1]
        const double c = cosine(rng), s = std::sqrt(std::max(0.0, 1 - c * c));
        u = {speed * s * std::cos(phi), speed * s * std::sin(phi), speed * c};
      }
    }
    return v;
  }
  std::uniform_real_distribution<double> component(-speed, speed);
  Vector3 mean{0, 0, 0};
  for (auto& u : v)
    for (int d = 0; d < dimension; ++d) mean[d] += (u[d] = component(rng)) / double(count);
  for (auto& u : v) u = u - mean;
  return v;
}

}  // namespace aggkit
