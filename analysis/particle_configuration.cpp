#include "analysis/particle_configuration.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/input_error.hpp"

namespace aggkit {

void check_configuration(const ParticleConfiguration& config) {
  if (config.dimension != 2 && config.dimension != 3)
    throw InputError("dimension", std::to_string(config.dimension), "must be 2 or 3");
  if (!(config.radius > 0) || !std::isfinite(config.radius))
    throw InputError("radius", format_value(config.radius), "must be positive and finite");
  if (!config.radii.empty() && config.radii.size() != config.positions.size())
    throw InputError("radii", std::to_string(config.radii.size()) + " radii",
                     "one per particle (" + std::to_string(config.positions.size()) + "), or none");
  for (std::size_t i = 0; i < config.radii.size(); ++i)
    if (!(config.radii[i] > 0) || !std::isfinite(config.radii[i]))
      throw InputError("radii[" + std::to_string(i) + "]", format_value(config.radii[i]), "must be positive and finite");
  if (config.periodic)
    for (int d = 0; d < config.dimension; ++d)
      if (!(config.box[d] > 0) || !std::isfinite(config.box[d]))
        throw InputError("box[" + std::to_string(d) + "]", format_value(config.box[d]),
                         "a periodic box needs positive, finite sides");
  for (std::size_t i = 0; i < config.positions.size(); ++i)
    for (int d = 0; d < config.dimension; ++d)
      if (!std::isfinite(config.positions[i][d]))
        throw InputError("positions[" + std::to_string(i) + "]", format_value(config.positions[i][d]),
                         "coordinates must be finite");
}

double ParticleConfiguration::largest_radius() const {
  return radii.empty() ? radius : *std::max_element(radii.begin(), radii.end());
}

double kinetic_energy(std::span<const double> mass, std::span<const std::array<double, 3>> velocity) {
  if (mass.size() != velocity.size())
    throw InputError("mass", std::to_string(mass.size()) + " values",
                     "needs one mass per velocity (" + std::to_string(velocity.size()) + ")");
  double energy = 0;
  for (std::size_t i = 0; i < mass.size(); ++i) energy += 0.5 * mass[i] * squared_norm(velocity[i]);
  return energy;
}

std::array<double, 3> separation(const ParticleConfiguration& config, const std::array<double, 3>& from,
                                 const std::array<double, 3>& to) {
  std::array<double, 3> delta{};
  for (int d = 0; d < config.dimension; ++d) {
    delta[d] = to[d] - from[d];
    if (config.periodic) delta[d] -= config.box[d] * std::nearbyint(delta[d] / config.box[d]);
  }
  return delta;
}

}  // namespace aggkit
