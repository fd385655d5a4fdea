// [[engine]]: which engines run, in order; each kind reads its own options (engine_registry.cpp).
#include <algorithm>
#include <cctype>

#include "validation/scene/scene_sections.hpp"

namespace aggkit {

namespace {

// Labels name output folders: keep them to letters, digits, '-' and '_'.
bool is_folder_name(const std::string& label) {
  return !label.empty() && label.size() <= 64 && std::all_of(label.begin(), label.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '-' || c == '_';
  });
}

}  // namespace

void read_engines(const SceneTable& root, Scene& scene) {
  const std::vector<SceneTable> tables = root.tables("engine");
  if (tables.empty()) root.fail("engine", "at least one [[engine]] table");
  for (const SceneTable& table : tables) {
    const std::string name = table.string("name");
    const EngineType* type = find_engine_type(name);
    if (!type) table.fail("name", "one of " + join(engine_names()));
    if (type->needs_model && !scene.has_model)
      table.fail("name", "a scene with a [model] section (engine " + name + " solves the kinetic equations)");
    std::vector<std::string> allowed{"name", "label"};
    allowed.insert(allowed.end(), type->keys.begin(), type->keys.end());
    table.allow_only(allowed);

    const std::string label = table.optional_string("label").value_or(name);
    if (!is_folder_name(label))
      table.fail(table.contains("label") ? "label" : "name",
                 "an engine label of letters, digits, '-' and '_' (it names the output folder)");
    if (scene.find_engine(label))
      table.fail(table.contains("label") ? "label" : "name",
                 "engine labels must be unique; \"" + label + "\" is taken: give this engine a label = \"...\"");
    scene.engines.push_back(type->parse(table, label, scene));
  }
}

}  // namespace aggkit
