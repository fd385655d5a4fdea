// [[engine]]: which engines run, in order, each with its options as written. The kinds and their option
// tables belong to validation/engines/, which builds the engines and checks the options; here the tables
// are only read: a name, a unique label that can name a folder, and values TOML and JSON share.
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
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const SceneTable& table = tables[i];
    EngineSpec spec;
    spec.name = table.string("name");
    spec.key = table.path();
    spec.label = table.optional_string("label").value_or(spec.name);
    if (!is_folder_name(spec.label))
      table.fail(table.contains("label") ? "label" : "name",
                 "an engine label of letters, digits, '-' and '_' (it names the output folder)");
    if (scene.find_engine(spec.label))
      table.fail(table.contains("label") ? "label" : "name",
                 "engine labels must be unique; \"" + spec.label + "\" is taken: give this engine a label = \"...\"");
    spec.options = nlohmann::json::object();
    for (auto&& [key, value] : table.raw())
      if (key.str() != "name" && key.str() != "label") spec.options[std::string(key.str())] = toml_json(value, table.key(key.str()));
    scene.engines.push_back(std::move(spec));
  }
}

}  // namespace aggkit
