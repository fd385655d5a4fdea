#pragma once
// What the engines of ballistic aggregation (ED, TS) share in their engine files: equal hard discs or
// spheres of one mass that stick on contact, inside walls or a periodic box, moving from the start, and a
// stop rule on the number of clusters.
#include <cstddef>
#include <string>

#include "particle/common/particle_system.hpp"
#include "validation/engines/option_table.hpp"

namespace aggkit {

// Refuses, naming the [particles] key, unequal radii or masses, an open boundary and a cold start;
// `engine` and the reasons go into the messages.
void require_sticky_spheres(const ParticleSystem& system, const std::string& engine, const std::string& why_box,
                            const std::string& why_moving);

// The option `stop` = "one_cluster" | { clusters = K }: its table row, and the cluster count it asks for
// (0: stop at time.end), checked against particles.count.
OptionSpec cluster_stop_option();
std::size_t cluster_stop_target(const EngineOptions& given, std::size_t particles);

}  // namespace aggkit
