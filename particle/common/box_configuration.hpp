#pragma once
// A particle engine's configuration in the form the analysis functions take (analysis/): the box's
// dimension, sides (none for an open boundary) and periodicity, one radius and the wrapped positions.
#include <vector>

#include "analysis/particle_configuration.hpp"
#include "particle/common/box.hpp"

namespace aggkit {

ParticleConfiguration configuration_in(const Box& box, double radius, std::vector<Vector3> positions);

}  // namespace aggkit
