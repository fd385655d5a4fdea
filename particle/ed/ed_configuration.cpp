#include "particle/ed/ed_configuration.hpp"

#include "particle/common/box_configuration.hpp"

namespace aggkit {

ParticleConfiguration configuration(const EventDrivenAggregation& ed) {
  return configuration_in(ed.box(), ed.radius(), ed.positions());
}

}  // namespace aggkit
