#pragma once
// One realization's starting configuration of a particle system: every particle's position, velocity,
// radius and mass (the vectors have one entry per particle; in 2-D the third components are 0).
#include <vector>

#include "particle/common/vector3.hpp"

namespace aggkit {

struct ParticleStart {
  std::vector<Vector3> positions, velocities;
  std::vector<double> radii, masses;

  std::size_t size() const { return positions.size(); }
};

}  // namespace aggkit
