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

// A TOML value as JSON; dates and times, which no engine takes, are refused under `key`.
nlohmann::json to_json(const toml::node& node, const std::string& key) {
  if (const auto* t = node.as_table()) {
    nlohmann::json object = nlohmann::json::object();
    for (auto&& [k, v] : *t) object[std::string(k.str())] = to_json(v, key + "." + std::string(k.str()));
    return object;
  }
  if (const auto* a = node.as_array()) {
    nlohmann::json array = nlohmann::json::array();
    for (std::size_t i = 0; i < a->size(); ++i) array.push_back(to_json(*a->get(i), key + "[" + std::to_string(i) + "]"));
    return array;
  }
  if (const auto* s = node.as_string()) return s->get();
  if (const auto* i = node.as_integer()) return i->get();
  if (const auto* f = node.as_floating_point()) return f->get();
  if (const auto* b = node.as_boolean()) return b->get();
  throw InputError(key, scene_text(node), "a number, string, boolean, array or table");
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
      if (key.str() != "name" && key.str() != "label") spec.options[std::string(key.str())] = to_json(value, table.key(key.str()));
    scene.engines.push_back(std::move(spec));
  }
}

}  // namespace aggkit
