// The engine kinds a scene can name. To add one: write engine_<name>.cpp defining <name>_engine_type()
// and list it here.
#include "validation/engines/engine.hpp"

namespace aggkit {

EngineType cvode_engine_type();
EngineType exact_engine_type();
EngineType dsmc_engine_type();
EngineType ed_engine_type();
EngineType snes_engine_type();

const std::vector<EngineType>& engine_types() {
  static const std::vector<EngineType> types{cvode_engine_type(), exact_engine_type(), dsmc_engine_type(),
                                             ed_engine_type(), snes_engine_type()};
  return types;
}

const EngineType* find_engine_type(std::string_view name) {
  for (const auto& type : engine_types())
    if (type.name == name) return &type;
  return nullptr;
}

std::vector<std::string> engine_names() {
  std::vector<std::string> names;
  for (const auto& type : engine_types()) names.push_back(type.name);
  return names;
}

}  // namespace aggkit
