#pragma once
// What the engines of ballistic aggregation (ED, TS) share in their engine files: equal hard discs or
// spheres of one mass that stick on contact, inside walls or a periodic box, moving from the start, and a
// stop rule on the number of clusters.
#include <cstddef>
#include <string>

#include "analysis/option_rows.hpp"
#include "particle/common/particle_system.hpp"
#include "validation/engines/option_table.hpp"

namespace aggkit {

// Refuses, naming the [particles] key, unequal radii or masses, an open boundary and a cold start;
// `engine` and the reasons go into the messages.
void require_sticky_spheres(const ParticleSystem& system, const std::string& engine, const std::string& why_box,
                            const std::string& why_moving);

// The option `stop` = "one_cluster" | { clusters = K }: the cluster count it asks for (0: stop at time.end),
// read from the option's value (InputError naming `key` for another form) and written back as the option.
std::size_t cluster_stop_from(const nlohmann::json& value, const std::string& key);
nlohmann::json cluster_stop_value(std::size_t target);
inline const char* const cluster_stop_forms = "\"one_cluster\" or { clusters = K } with 1 <= K <= particles.count";

// Its row, bound to the cluster target `field` of settings S.
template <class S>
OptionRow<S> cluster_stop_row(std::size_t S::*field) {
  return Bind<S>::custom(
      "stop", cluster_stop_forms,
      "run until this many clusters remain (beyond time.end if needed); a stopped realization holds its final "
      "state for the later output times",
      "at time.end", [field](const S& s) { return cluster_stop_value(s.*field); },
      [field](S& s, const nlohmann::json& value, const std::string& key) { s.*field = cluster_stop_from(value, key); });
}

// InputError (key `engine[i].stop`) for a cluster target beyond particles.count.
void check_cluster_stop(const EngineOptions& given, std::size_t target, std::size_t particles);

}  // namespace aggkit
