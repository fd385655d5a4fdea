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

std::size_t cluster_stop_from(const nlohmann::json& value, const std::string& key) {
  if (value.is_string() && value.get<std::string>() == "one_cluster") return 1;
  if (value.is_object() && value.size() == 1 && value.contains("clusters")) {
    const nlohmann::json& k = value["clusters"];
    if (k.is_number_integer() && k.get<std::int64_t>() >= 1) return std::size_t(k.get<std::int64_t>());
    throw InputError(key + ".clusters", option_text(k), cluster_stop_forms);
  }
  throw InputError(key, option_text(value), cluster_stop_forms);
}

nlohmann::json cluster_stop_value(std::size_t target) {
  if (target == 0) return nullptr;
  if (target == 1) return "one_cluster";
  return nlohmann::json{{"clusters", target}};
}

void check_cluster_stop(const EngineOptions& given, std::size_t target, std::size_t particles) {
  if (target <= particles) return;
  const std::string forms = "\"one_cluster\" or { clusters = K } with 1 <= K <= particles.count = " + std::to_string(particles);
  throw InputError(given.key("stop") + ".clusters", std::to_string(target), forms);
}

}  // namespace aggkit
