// Reading a sweep scene (sweep_plan.hpp): the [sweep] section here; every point through the run-scene parser
// and the engine builders, so that a swept key is validated exactly as `aggkit run` validates the scene.
#include "validation/sweep/sweep_plan.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <sstream>

#include "particle/common/particle_system.hpp"
#include "validation/engines/engine.hpp"
#include "validation/scene/scene_table.hpp"
#include "validation/scene/value_range.hpp"

namespace aggkit {

namespace {

constexpr std::size_t max_values = 10'000;       // per key
constexpr std::size_t max_points = 1'000'000;    // in all
constexpr std::size_t max_checked_points = 1000;  // points read and built before anything runs

std::string toml_text(const toml::table& table) {
  std::ostringstream out;
  out << table;
  return out.str();
}

std::string quoted_key(const std::string& key) { return "sweep.\"" + key + "\""; }

// Where a sweep key points: an engine (index into [[engine]]) or the root, and the table path below it.
struct KeyPath {
  bool engine = false;
  std::size_t engine_index = 0;
  std::vector<std::string> path;  // the last component is the value's own name
};

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, '.')) parts.push_back(part);
  if (!text.empty() && text.back() == '.') parts.push_back("");
  return parts;
}

KeyPath resolve_key(const std::string& key, const toml::table& document) {
  const std::string forms =
      "a dotted scene key: \"particles.count\", \"engine.damping\" (the only engine), \"engine[1].damping\" (by "
      "index) or \"engine[label].damping\" (by label)";
  KeyPath resolved;
  std::vector<std::string> parts = split(key);
  if (parts.empty()) throw InputError(quoted_key(key), "", forms);
  for (const auto& p : parts)
    if (p.empty()) throw InputError(quoted_key(key), "(the key)", forms);
  const std::string& head = parts.front();
  if (head == "engine" || head.rfind("engine[", 0) == 0) {
    resolved.engine = true;
    const toml::array* engines = document.get("engine") ? document.get("engine")->as_array() : nullptr;
    const std::size_t count = engines ? engines->size() : 0;
    if (head == "engine") {
      if (count != 1)
        throw InputError(quoted_key(key), "(the key)",
                         "\"engine.X\" names the only engine, but the scene has " + std::to_string(count) +
                             ": name one as \"engine[i].X\" (0-based) or \"engine[label].X\"");
      resolved.engine_index = 0;
    } else {
      const std::size_t close = head.find(']');
      if (close == std::string::npos || close + 1 != head.size() || close == 7)
        throw InputError(quoted_key(key), "(the key)", forms);
      const std::string inside = head.substr(7, close - 7);
      const bool number = inside.find_first_not_of("0123456789") == std::string::npos;
      bool found = false;
      for (std::size_t i = 0; i < count && !found; ++i) {
        const toml::table* engine = engines->get(i)->as_table();
        std::string label;
        if (engine && engine->get("label") && engine->get("label")->is_string()) label = engine->get("label")->as_string()->get();
        else if (engine && engine->get("name") && engine->get("name")->is_string()) label = engine->get("name")->as_string()->get();
        if (number ? std::to_string(i) == inside : label == inside) resolved.engine_index = i, found = true;
      }
      if (!found)
        throw InputError(quoted_key(key), "(the key)",
                         number ? "engine index " + inside + " is beyond the scene's " + std::to_string(count) + " engines"
                                : "no engine of the scene has the label \"" + inside + "\"");
    }
    parts.erase(parts.begin());
    if (parts.empty()) throw InputError(quoted_key(key), "(the key)", "an engine option after the engine: " + forms);
  }
  resolved.path = parts;
  return resolved;
}

toml::table* engine_table(toml::table& document, std::size_t index) {
  return document.get("engine")->as_array()->get(index)->as_table();
}

// The node at `path` below `table`, or nullptr.
const toml::node* find_node(const toml::table& table, const std::vector<std::string>& path) {
  const toml::table* t = &table;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const toml::node* next = t->get(path[i]);
    if (!next || !next->is_table()) return nullptr;
    t = next->as_table();
  }
  return t->get(path.back());
}

// Writes `value` at the key, creating missing tables (the scene parser then refuses unknown keys by name).
void set_value(toml::table& document, const KeyPath& key, const std::string& written, const nlohmann::json& value) {
  toml::table* t = key.engine ? engine_table(document, key.engine_index) : &document;
  for (std::size_t i = 0; i + 1 < key.path.size(); ++i) {
    toml::node* next = t->get(key.path[i]);
    if (!next) next = t->insert(key.path[i], toml::table{}).first->second.as_table();
    if (!next->is_table())
      throw InputError(quoted_key(written), sweep_value_text(value),
                       "\"" + key.path[i] + "\" holds a value, not a table of keys (the key is too long)");
    t = next->as_table();
  }
  const std::string& leaf = key.path.back();
  if (value.is_boolean()) t->insert_or_assign(leaf, value.get<bool>());
  else if (value.is_number_integer()) t->insert_or_assign(leaf, value.get<std::int64_t>());
  else if (value.is_number()) t->insert_or_assign(leaf, value.get<double>());
  else t->insert_or_assign(leaf, value.get<std::string>());
}

std::int64_t integer_or(const toml::node* node, std::int64_t fallback) {
  return node && node->is_integer() ? node->as_integer()->get() : fallback;
}

// Realization r: every seed of the scene increased by r (particles.seed; an engine's `seed` option).
bool offset_seeds(toml::table& document, std::size_t r) {
  bool any = false;
  if (toml::node* particles = document.get("particles"); particles && particles->is_table()) {
    toml::table& p = *particles->as_table();
    const std::int64_t fallback = find_option(particle_system_option_rows().table(), "seed")->fallback.get<std::int64_t>();
    p.insert_or_assign("seed", integer_or(p.get("seed"), fallback) + std::int64_t(r));
    any = true;
  }
  if (toml::node* engines = document.get("engine"); engines && engines->is_array())
    for (auto& node : *engines->as_array()) {
      toml::table* engine = node.as_table();
      if (!engine || !engine->get("name") || !engine->get("name")->is_string()) continue;
      const EngineType* type = find_engine_type(engine->get("name")->as_string()->get());
      if (!type) continue;
      for (const OptionSpec& option : type->options)
        if (option.key == "seed") {
          const std::int64_t fallback = option.fallback.get<std::int64_t>();  // the engine's default seed
          engine->insert_or_assign("seed", integer_or(engine->get("seed"), fallback) + std::int64_t(r));
          any = true;
        }
    }
  return any;
}

// A scene read and its engines built, as `aggkit run` does before it runs anything.
Scene checked_scene(const std::string& text, const std::string& source, const std::filesystem::path& folder) {
  Scene scene = parse_scene(text, source, folder);
  build_engines(scene);
  return scene;
}

std::vector<nlohmann::json> read_values(const SceneTable& sweep, const std::string& key, const toml::node* current,
                                        bool& log) {
  const toml::node& node = *sweep.find(key);
  const std::string forms = "a list of values or { from = .., to = .., count = .. (, spacing = \"log\") }";
  std::vector<nlohmann::json> values;
  log = false;
  if (const toml::array* list = node.as_array()) {
    if (list->empty()) throw InputError(quoted_key(key), "[]", "at least one value (an empty list sweeps nothing)");
    if (list->size() > max_values) throw InputError(quoted_key(key), scene_text(node), "at most " + std::to_string(max_values) + " values");
    for (std::size_t i = 0; i < list->size(); ++i) {
      const toml::node& v = *list->get(i);
      if (v.is_integer()) values.emplace_back(v.as_integer()->get());
      else if (v.is_floating_point()) values.emplace_back(v.as_floating_point()->get());
      else if (v.is_string()) values.emplace_back(v.as_string()->get());
      else if (v.is_boolean()) values.emplace_back(v.as_boolean()->get());
      else throw InputError(quoted_key(key) + "[" + std::to_string(i) + "]", scene_text(v), "a number, string or boolean");
    }
    return values;
  }
  if (!node.is_table()) throw InputError(quoted_key(key), scene_text(node), forms);
  const SceneTable range(*node.as_table(), quoted_key(key));
  // An integer key (particles.count) takes integers where the range gives them.
  const bool integer = current && current->is_integer();
  for (double v : read_value_range(range, max_values, log)) {
    if (integer && v == std::floor(v) && std::abs(v) < 9e15) values.emplace_back(std::int64_t(v));
    else values.emplace_back(v);
  }
  return values;
}

std::string point_words(const SweepPlan& plan, std::size_t p) {
  std::string words;
  const auto values = plan.point(p);
  for (std::size_t a = 0; a < plan.axes.size(); ++a)
    words += (a ? ", " : "") + plan.axes[a].key + " = " + sweep_value_text(values[a]);
  return words;
}

// group_by: each entry a swept key or a list of them (each once), each grouping once.
void read_groupings(const SceneTable& sweep, SweepPlan& plan) {
  if (!sweep.contains("group_by")) return;
  const std::string forms = "a list of groupings, each a swept key or a list of swept keys: [\"engine.damping\", [\"engine.damping\", ...]]";
  const toml::array* list = sweep.find("group_by")->as_array();
  if (!list || list->empty()) sweep.fail("group_by", forms);
  for (std::size_t g = 0; g < list->size(); ++g) {
    const std::string key = sweep.key("group_by") + "[" + std::to_string(g) + "]";
    const toml::node& entry = *list->get(g);
    std::vector<const toml::node*> names;
    if (entry.is_string()) names.push_back(&entry);
    else if (const toml::array* keys = entry.as_array(); keys && !keys->empty())
      for (std::size_t k = 0; k < keys->size(); ++k) names.push_back(keys->get(k));
    else throw InputError(key, scene_text(entry), forms);
    std::vector<std::size_t> grouping;
    for (const toml::node* name : names) {
      std::size_t axis = plan.axes.size();
      if (name->is_string())
        for (std::size_t a = 0; a < plan.axes.size(); ++a)
          if (plan.axes[a].key == name->as_string()->get()) axis = a;
      std::string swept;
      for (const auto& a : plan.axes) swept += (swept.empty() ? "" : ", ") + a.key;
      if (axis == plan.axes.size()) throw InputError(key, scene_text(*name), "a swept key: one of " + swept);
      if (std::find(grouping.begin(), grouping.end(), axis) != grouping.end())
        throw InputError(key, scene_text(entry), "each swept key once in a grouping");
      grouping.push_back(axis);
    }
    if (std::find(plan.groupings.begin(), plan.groupings.end(), grouping) != plan.groupings.end())
      throw InputError(key, scene_text(entry), "each grouping once");
    plan.groupings.push_back(grouping);
  }
}

// where_not_aggregated: { column = value }, each column an observe.final observable of the scene or one of
// its values; the scene's only engine is dem with gravity (whose runs have aggregation_time).
void read_not_aggregated(const SceneTable& sweep, SweepPlan& plan) {
  if (!sweep.contains("where_not_aggregated")) return;
  const toml::node& node = *sweep.find("where_not_aggregated");
  if (!node.is_table() || node.as_table()->empty())
    sweep.fail("where_not_aggregated", "a table { column = value }, e.g. { fractal_dimension_com = 0.0 }");
  const Scene& scene = plan.scene;
  if (scene.engines.size() != 1 || scene.engines[0].name != "dem" || !scene.engines[0].options.contains("gravity"))
    sweep.fail("where_not_aggregated", "a scene whose only engine is dem with gravity (its runs have aggregation_time)");
  const SceneTable fill(*node.as_table(), sweep.key("where_not_aggregated"));
  for (auto&& [name, value] : *node.as_table()) {
    const std::string column(name.str());
    bool known = false;
    for (const std::string& observable : scene.observe.final_state)
      known = known || column.rfind(observable, 0) == 0;
    if (!known)
      throw InputError(fill.key(column), scene_text(value),
                       "a column of an observe.final observable (" + join(scene.observe.final_state) + ") as its key");
    plan.not_aggregated.emplace_back(column, fill.number(column, Bound::finite));
  }
}

}  // namespace

std::string sweep_value_text(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  if (value.is_number_integer()) return std::to_string(value.get<std::int64_t>());
  if (value.is_number()) return shortest_text(value.get<double>());
  return value.dump();
}

std::size_t SweepPlan::point_count() const {
  std::size_t count = 1;
  for (const auto& axis : axes) count *= axis.values.size();
  return count;
}

std::vector<nlohmann::json> SweepPlan::point(std::size_t p) const {
  std::vector<nlohmann::json> values(axes.size());
  for (std::size_t a = axes.size(); a-- > 0;) {
    values[a] = axes[a].values[p % axes[a].values.size()];
    p /= axes[a].values.size();
  }
  return values;
}

std::string SweepPlan::point_text(std::size_t p, std::size_t r) const {
  toml::table document = parse_toml_text(text, source);
  const std::vector<nlohmann::json> values = point(p);
  for (std::size_t a = 0; a < axes.size(); ++a) set_value(document, resolve_key(axes[a].key, document), axes[a].key, values[a]);
  if (r > 0) offset_seeds(document, r);
  return toml_text(document);
}

Scene SweepPlan::point_scene(std::size_t p, std::size_t r) const {
  Scene scene = parse_scene(point_text(p, r), source, folder);
  scene.path = this->scene.path;
  return scene;
}

namespace {

// The swept keys in the order they are written (toml++ keeps a table's keys sorted), each with its values;
// at least one, at most max_points points in all.
void read_axes(const SceneTable& sweep, const toml::table& sweep_table, toml::table& document, SweepPlan& plan) {
  std::vector<std::pair<toml::source_position, std::string>> written;
  for (auto&& [name, node] : sweep_table)
    if (name.str() != "realizations" && name.str() != "maps" && name.str() != "group_by" && name.str() != "where_not_aggregated")
      written.emplace_back(name.source().begin, std::string(name.str()));
  std::sort(written.begin(), written.end(), [](const auto& x, const auto& y) {
    return std::tie(x.first.line, x.first.column) < std::tie(y.first.line, y.first.column);
  });
  for (const auto& [position, key] : written) {
    SweepAxis axis;
    axis.key = key;
    const KeyPath path = resolve_key(key, document);
    toml::table* base = path.engine ? engine_table(document, path.engine_index) : &document;
    axis.values = read_values(sweep, key, find_node(*base, path.path), axis.log);
    plan.axes.push_back(std::move(axis));
  }
  if (plan.axes.empty())
    sweep.fail("realizations", "at least one swept key in [sweep]: \"engine.damping\" = [..] or { from, to, count }");
  double points = 1;
  for (const auto& axis : plan.axes) points *= double(axis.values.size());
  if (points > double(max_points))
    throw InputError("sweep", shortest_text(points) + " points", "at most " + std::to_string(max_points) + " points in all");
}

// Every value of every key alone, then every point (a few): read and built as `aggkit run` would.
void check_points(const toml::table& document, const SweepPlan& plan, const std::string& source,
                  const std::filesystem::path& folder) {
  for (const auto& axis : plan.axes)
    for (const auto& value : axis.values) {
      toml::table one = document;
      set_value(one, resolve_key(axis.key, one), axis.key, value);
      try {
        checked_scene(toml_text(one), source, folder);
      } catch (const InputError& e) {
        throw InputError(quoted_key(axis.key), sweep_value_text(value), std::string("the scene refuses it: ") + e.what());
      }
    }
  const std::size_t checked = std::min(plan.point_count(), max_checked_points);
  for (std::size_t p = 0; p < checked; ++p) {
    try {
      checked_scene(plan.point_text(p, 0), source, folder);
    } catch (const InputError& e) {
      throw InputError("sweep", "the point " + point_words(plan, p), std::string("the scene refuses it: ") + e.what());
    }
  }
}

}  // namespace

SweepPlan parse_sweep_plan(std::string_view text, const std::string& source, const std::filesystem::path& folder) {
  toml::table document = parse_toml_text(text, source);
  SweepPlan plan;
  plan.source = source;
  plan.folder = folder;
  plan.scene = checked_scene(std::string(text), source, folder);  // the base point, as `aggkit run` reads it
  const SceneTable root(document, "");
  if (!root.contains("sweep"))
    root.fail("sweep", "required by aggkit sweep: [sweep] with \"key\" = [values] or { from, to, count } entries");
  const toml::table sweep_table = *document.get("sweep")->as_table();
  document.erase("sweep");
  plan.text = toml_text(document);

  const SceneTable sweep(sweep_table, "sweep");
  plan.realizations = sweep.optional_count("realizations", 1).value_or(1);
  if (plan.realizations > 100000) sweep.fail("realizations", "at most 100000 runs per point");
  read_axes(sweep, sweep_table, document, plan);
  if (plan.realizations > 1) {
    toml::table probe = document;
    if (!offset_seeds(probe, 1))
      sweep.fail("realizations", "1: the scene has no seed to vary ([particles] seed or an engine's seed option)");
  }

  // The columns drawn: by default what the scene asks to observe at the end.
  if (sweep.contains("maps")) plan.maps = sweep.strings("maps");
  else plan.maps = plan.scene.observe.final_state;
  if (!sweep.contains("maps") && plan.maps.empty())
    for (const auto& o : plan.scene.observe.series) plan.maps.push_back(o.name());

  read_groupings(sweep, plan);
  read_not_aggregated(sweep, plan);
  check_points(document, plan, source, folder);

  // Results depend on the scene (its name aside) and on which keys are swept; the values are matched per run.
  toml::table fingerprint = document;
  fingerprint.erase("name");
  fingerprint.erase("tier");
  toml::array keys;
  for (const auto& axis : plan.axes) keys.push_back(axis.key);
  fingerprint.insert("sweep_keys", keys);
  plan.fingerprint = toml_text(fingerprint);
  return plan;
}

SweepPlan load_sweep_plan(const std::filesystem::path& path) {
  SweepPlan plan = parse_sweep_plan(read_scene_file(path), path.string(), path.parent_path());
  plan.scene.path = path;
  return plan;
}

}  // namespace aggkit
