#include "validation/scene/scene.hpp"

#include "validation/io/text.hpp"
#include "validation/scene/scene_sections.hpp"

namespace aggkit {

const EngineSpec* Scene::find_engine(std::string_view label) const {
  for (const auto& engine : engines)
    if (engine.label == label) return &engine;
  return nullptr;
}

const Tolerance* ComparisonPlan::final_tolerance_for(std::string_view observable) const {
  for (const auto& t : final_tolerances)
    if (t.observable == observable) return &t;
  return nullptr;
}

const Tolerance* ComparisonPlan::tolerance_for(std::string_view observable) const {
  for (const auto& t : tolerances)
    if (t.observable == observable) return &t;
  return nullptr;
}

const char* to_string(SceneTier tier) { return tier == SceneTier::full ? "full" : "fast"; }

namespace {

Scene read_scene(const toml::table& document, const std::filesystem::path& folder) {
  const SceneTable root(document, "");
  root.allow_only({"name", "tier", "model", "particles", "time", "engine", "observe", "compare", "sweep"});
  // [sweep] belongs to `aggkit sweep` (validation/sweep/sweep_plan.hpp); a run runs the scene as written.
  if (root.contains("sweep") && !document.get("sweep")->is_table()) root.fail("sweep", "a table [sweep] (see aggkit sweep --help)");
  Scene scene;
  scene.name = root.string("name");
  if (scene.name.empty()) root.fail("name", "a non-empty name");
  if (scene.name.size() > 200 || printable_text(scene.name) != scene.name)
    root.fail("name", "a name of at most 200 characters without control characters (it titles the report)");
  if (const auto tier = root.optional_string("tier")) {
    if (*tier == "fast") scene.tier = SceneTier::fast;
    else if (*tier == "full") scene.tier = SceneTier::full;
    else root.fail("tier", "\"fast\" or \"full\"");
  }
  scene.time = read_time(root.table("time"));
  if (const auto model = root.optional_table("model")) {
    read_model(*model, scene);
    scene.has_model = true;
  }
  if (const auto particles = root.optional_table("particles")) scene.particles = read_particles(*particles, folder);
  read_engines(root, scene);
  scene.observe = read_observation(root.table("observe"), scene);
  if (const auto compare = root.optional_table("compare")) scene.compare = read_comparison(*compare, scene);
  return scene;
}

}  // namespace

Scene parse_scene(std::string_view text, const std::string& source) { return read_scene(parse_toml_text(text, source), {}); }

Scene parse_scene(std::string_view text, const std::string& source, const std::filesystem::path& folder) {
  return read_scene(parse_toml_text(text, source), folder);
}

Scene load_scene(const std::filesystem::path& path) {
  Scene scene = read_scene(parse_toml_text(read_scene_file(path), path.string()), path.parent_path());
  scene.path = path;
  return scene;
}

}  // namespace aggkit
