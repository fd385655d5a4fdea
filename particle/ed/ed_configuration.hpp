#pragma once
// The ED engine's current configuration in the form the analysis functions take (analysis/).
#include "analysis/particle_configuration.hpp"
#include "particle/ed/event_driven_aggregation.hpp"

namespace aggkit {

// All particles, wrapped into the box; periodic if the box is.
ParticleConfiguration configuration(const EventDrivenAggregation& ed);

}  // namespace aggkit
