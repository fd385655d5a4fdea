#include "validation/engines/sticky_spheres.hpp"

#include "analysis/input_error.hpp"

namespace aggkit {

void require_sticky_spheres(const ParticleSystem& system, const std::string& engine, const std::string& why_box,
                            const std::string& why_moving) {
  const std::string why = " (engine " + engine + " simulates equal hard discs/spheres of one mass)";
  if (!system.equal_radii())
    throw InputError("particles.radius",
                     system.start_kind() == ParticleSystem::StartKind::file ? "(from the start file)" : "a distribution",
                     "one radius for every particle" + why);
  if (!system.equal_masses()) throw InputError("particles.mass", "unequal masses", "one mass for every particle" + why);
  if (system.box.boundary == Boundary::open)
    throw InputError("particles.boundary", "\"open\"", "\"periodic\" or \"reflecting\" for engine " + engine + " (" + why_box + ")");
  if (system.cold())
    throw InputError("particles.initial.speed", "0", "a speed > 0 for engine " + engine + " (" + why_moving + ")");
}

OptionSpec cluster_stop_option() {
  return custom_option("stop", "at time.end",
                       "run until this many clusters remain (beyond time.end if needed); a stopped realization "
                       "holds its final state for the later output times",
                       "\"one_cluster\" or { clusters = K } with 1 <= K <= particles.count");
}

std::size_t cluster_stop_target(const EngineOptions& given, std::size_t particles) {
  if (!given.has("stop")) return 0;
  const nlohmann::json& stop = given.value("stop");
  const std::string forms =
      "\"one_cluster\" or { clusters = K } with 1 <= K <= particles.count = " + std::to_string(particles);
  if (stop.is_string() && stop.get<std::string>() == "one_cluster") return 1;
  if (stop.is_object() && stop.size() == 1 && stop.contains("clusters")) {
    const nlohmann::json& k = stop["clusters"];
    if (k.is_number_integer() && k.get<std::int64_t>() >= 1 && std::uint64_t(k.get<std::int64_t>()) <= particles)
      return std::size_t(k.get<std::int64_t>());
    throw InputError(given.key("stop") + ".clusters", option_text(k), forms);
  }
  given.fail("stop", forms);
}

}  // namespace aggkit
