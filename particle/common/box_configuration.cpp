#include "particle/common/box_configuration.hpp"

namespace aggkit {

ParticleConfiguration configuration_in(const Box& box, double radius, std::vector<Vector3> positions) {
  ParticleConfiguration config;
  config.dimension = box.dimension;
  config.radius = radius;
  if (box.boundary != Boundary::open) config.box = box.side;
  config.periodic = box.boundary == Boundary::periodic;
  config.positions = std::move(positions);
  return config;
}

}  // namespace aggkit
