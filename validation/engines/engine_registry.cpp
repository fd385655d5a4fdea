// The engine kinds a scene can name: one line each in AGGKIT_ENGINES. To add one, write
// engine_<name>.cpp defining <name>_engine_type() and add its name here.
#include <algorithm>

#include "analysis/input_error.hpp"
#include "validation/engines/engine.hpp"
#include "validation/io/text.hpp"

#define AGGKIT_ENGINES(X) \
  X(cvode)                \
  X(exact)                \
  X(dsmc)                 \
  X(ed)                   \
  X(ts)                   \
  X(dem)                  \
  X(snes)

namespace aggkit {

#define AGGKIT_DECLARE(name) EngineType name##_engine_type();
AGGKIT_ENGINES(AGGKIT_DECLARE)
#undef AGGKIT_DECLARE

const std::vector<EngineType>& engine_types() {
#define AGGKIT_LIST(name) name##_engine_type(),
  static const std::vector<EngineType> types{AGGKIT_ENGINES(AGGKIT_LIST)};
#undef AGGKIT_LIST
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

namespace {

// Every observable the engine must give: the series, and for an engine of particles the final ones.
void check_observables(const Scene& scene, const EngineSpec& spec, const EngineType& type) {
  const auto check = [&](const std::string& key, const Observable& o) {
    const unsigned missing = o.needs() & ~type.provides;
    if (missing)
      throw InputError(key, "\"" + o.name() + "\"",
                       "an observable engine " + spec.label + " (" + type.name + ") can give: it needs " +
                           describe_needs(missing) + ", which " + type.name + " does not have (it gives " +
                           describe_needs(type.provides) + ")");
  };
  for (std::size_t i = 0; i < scene.observe.series.size(); ++i)
    check("observe.series[" + std::to_string(i) + "]", scene.observe.series[i]);
  if (type.needs_model) return;  // only particle engines write final states
  for (std::size_t i = 0; i < scene.observe.final_state.size(); ++i)
    check("observe.final[" + std::to_string(i) + "]", *Observable::from_name(scene.observe.final_state[i]));
}

}  // namespace

std::unique_ptr<Engine> build_engine(const Scene& scene, std::size_t index) {
  const EngineSpec& spec = scene.engines.at(index);
  const EngineType* type = find_engine_type(spec.name);
  if (!type) throw InputError(spec.key + ".name", "\"" + spec.name + "\"", "one of " + join(engine_names()));
  if (type->needs_model && !scene.has_model)
    throw InputError(spec.key + ".name", "\"" + spec.name + "\"",
                     "a scene with a [model] section (engine " + spec.name + " solves the kinetic equations)");
  if (!type->needs_model && !scene.particles)
    throw InputError(spec.key + ".name", "\"" + spec.name + "\"",
                     "a scene with a [particles] section (engine " + spec.name + " simulates particles)");
  const EngineOptions options(type->options, spec.options, spec.key);
  check_observables(scene, spec, *type);
  return type->build(options, spec, scene);
}

std::vector<std::unique_ptr<Engine>> build_engines(const Scene& scene) {
  std::vector<std::unique_ptr<Engine>> engines;
  for (std::size_t i = 0; i < scene.engines.size(); ++i) engines.push_back(build_engine(scene, i));
  return engines;
}

std::function<std::string(const std::string&)> solver_keys(const EngineSpec& spec, const OptionTable& options) {
  std::vector<std::string> names;
  for (const OptionSpec& o : options) names.push_back(o.key);
  return [key = spec.key, names](const std::string& parameter) {
    const std::string head = parameter.substr(0, parameter.find_first_of(".["));
    if (std::find(names.begin(), names.end(), head) != names.end()) return key + "." + parameter;
    if (head == "output_times") return "time.outputs" + parameter.substr(head.size());
    return "model." + parameter;
  };
}

std::string engines_help() {
  std::string help = "Engines ([[engine]] name = ..., then its options):\n";
  for (const auto& type : engine_types()) {
    help += "  " + type.name + ": " + type.description + "\n";
    for (const OptionSpec& o : type.options)
      help += "    " + o.key + " (default " + o.default_text() + "; " + o.allowed() + "): " + o.doc + "\n";
  }
  return help;
}

std::string observables_help() {
  std::string help = "Observables (observe.series; observe.final for particle engines):\n";
  for (const ObservableType& type : observable_types())
    help += "  " + type.form + ": " + type.description + " [needs " + describe_needs(type.needs) + "]\n";
  return help;
}

}  // namespace aggkit
