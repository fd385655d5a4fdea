#include "particle/ed/ed_configuration.hpp"

namespace aggkit {

ParticleConfiguration configuration(const EventDrivenAggregation& ed) {
  ParticleConfiguration config;
  config.dimension = ed.box().dimension;
  config.radius = ed.radius();
  config.box = ed.box().side;
  config.periodic = ed.box().boundary == Boundary::periodic;
  config.positions = ed.positions();
  return config;
}

}  // namespace aggkit
