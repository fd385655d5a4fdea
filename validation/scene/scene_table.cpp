#include "validation/scene/scene_table.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

constexpr std::size_t max_value_text = 80;

std::string type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date or time";
  }
}

void render(std::ostream& out, const toml::node& node) {
  if (auto s = node.as_string()) {
    out << '"' << printable_text(s->get()) << '"';
  } else if (auto i = node.as_integer()) {
    out << i->get();
  } else if (auto f = node.as_floating_point()) {
    out << float_text(f->get());
  } else if (auto b = node.as_boolean()) {
    out << (b->get() ? "true" : "false");
  } else if (auto a = node.as_array()) {
    out << '[';
    for (std::size_t i = 0; i < a->size(); ++i) {
      if (i) out << ", ";
      render(out, *a->get(i));
    }
    out << ']';
  } else if (auto t = node.as_table()) {
    out << '{';
    bool first = true;
    for (auto&& [k, v] : *t) {
      out << (first ? " " : ", ") << k.str() << " = ";
      render(out, v);
      first = false;
    }
    out << (first ? "}" : " }");
  } else {
    node.visit([&](const auto& v) { out << v; });
  }
}

double as_number(const toml::node& node) {
  if (auto i = node.as_integer()) return double(i->get());
  return node.as_floating_point()->get();
}

bool is_number(const toml::node& node) { return node.is_integer() || node.is_floating_point(); }

std::string bound_text(Bound bound) {
  switch (bound) {
    case Bound::any: return "a number";
    case Bound::finite: return "a finite number";
    case Bound::non_negative: return "a finite number >= 0";
    case Bound::positive: return "a finite number > 0";
  }
  return "a number";
}

// What `bound` allows, if `value` is outside it.
std::optional<std::string> violates(double value, Bound bound) {
  const bool ok = bound == Bound::any || (std::isfinite(value) && (bound == Bound::finite ||
                                                                  (bound == Bound::non_negative && value >= 0) ||
                                                                  (bound == Bound::positive && value > 0)));
  if (ok) return std::nullopt;
  return bound_text(bound);
}

}  // namespace

std::string scene_text(const toml::node& node) {
  std::ostringstream out;
  render(out, node);
  std::string text = out.str();
  if (text.size() > max_value_text) text = text.substr(0, max_value_text - 3) + "...";
  return text;
}

InputError rekeyed(const InputError& error, const std::string& scene_key) {
  // what() is "<key> = <value>: <allowed>" (analysis/input_error.hpp); keep everything after the key.
  const std::string what = error.what();
  const std::string rest = what.compare(0, error.key().size(), error.key()) == 0 ? what.substr(error.key().size()) : " = " + what;
  const std::size_t equals = rest.rfind(" = ", 0) == 0 ? 3 : 0;
  const std::size_t colon = rest.find(": ", equals);
  if (colon == std::string::npos) return InputError(scene_key, rest.substr(equals), "");
  return InputError(scene_key, rest.substr(equals, colon - equals), rest.substr(colon + 2));
}

std::string leaf_key(const std::string& key) {
  const std::size_t dot = key.rfind('.');
  return dot == std::string::npos ? key : key.substr(dot + 1);
}

SceneTable::SceneTable(const toml::table& table, std::string path) : table_(&table), path_(std::move(path)) {}

std::string SceneTable::key(std::string_view name) const {
  return path_.empty() ? std::string(name) : path_ + "." + std::string(name);
}

void SceneTable::allow_only(const std::vector<std::string>& allowed) const {
  for (auto&& [k, v] : *table_) {
    bool known = false;
    for (const auto& a : allowed) known = known || a == k.str();
    if (!known)
      throw InputError(key(k.str()), scene_text(v),
                       "unknown key" + (path_.empty() ? std::string() : " in [" + path_ + "]") +
                           "; allowed keys: " + join(allowed));
  }
}

void SceneTable::fail(std::string_view name, const std::string& allowed) const {
  const toml::node* node = find(name);
  throw InputError(key(name), node ? scene_text(*node) : "(missing)", allowed);
}

const toml::node& SceneTable::require(std::string_view name, const std::string& expected) const {
  const toml::node* node = find(name);
  if (!node) throw InputError(key(name), "(missing)", "required: " + expected);
  return *node;
}

std::string SceneTable::string(std::string_view name) const {
  const auto& node = require(name, "a string");
  if (!node.is_string()) fail(name, "a string, not " + type_name(node));
  return node.as_string()->get();
}

double SceneTable::number(std::string_view name, Bound bound) const {
  const auto& node = require(name, bound_text(bound));
  if (!is_number(node)) fail(name, bound_text(bound) + ", not " + type_name(node));
  const double value = as_number(node);
  if (auto allowed = violates(value, bound)) fail(name, *allowed);
  return value;
}

nlohmann::json toml_json(const toml::node& node, const std::string& key) {
  if (const auto* t = node.as_table()) {
    nlohmann::json object = nlohmann::json::object();
    for (auto&& [k, v] : *t) object[std::string(k.str())] = toml_json(v, key + "." + std::string(k.str()));
    return object;
  }
  if (const auto* a = node.as_array()) {
    nlohmann::json array = nlohmann::json::array();
    for (std::size_t i = 0; i < a->size(); ++i) array.push_back(toml_json(*a->get(i), key + "[" + std::to_string(i) + "]"));
    return array;
  }
  if (const auto* s = node.as_string()) return s->get();
  if (const auto* i = node.as_integer()) return i->get();
  if (const auto* f = node.as_floating_point()) return f->get();
  if (const auto* b = node.as_boolean()) return b->get();
  throw InputError(key, scene_text(node), "a number, string, boolean, array or table");
}

std::size_t SceneTable::count(std::string_view name, std::size_t minimum) const {
  const std::string expected = "an integer >= " + std::to_string(minimum);
  const auto& node = require(name, expected);
  if (!node.is_integer()) fail(name, expected + ", not " + type_name(node));
  const std::int64_t value = node.as_integer()->get();
  if (value < 0 || std::uint64_t(value) < minimum) fail(name, expected);
  return std::size_t(value);
}

bool SceneTable::boolean(std::string_view name) const {
  const auto& node = require(name, "true or false");
  if (!node.is_boolean()) fail(name, "true or false, not " + type_name(node));
  return node.as_boolean()->get();
}

std::vector<double> SceneTable::numbers(std::string_view name, Bound bound) const {
  const std::string expected = "an array of numbers (each " + bound_text(bound) + ")";
  const auto& node = require(name, expected);
  const toml::array* array = node.as_array();
  if (!array) fail(name, expected + ", not " + type_name(node));
  std::vector<double> values;
  values.reserve(array->size());
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = *array->get(i);
    const std::string item_key = key(name) + "[" + std::to_string(i) + "]";
    if (!is_number(item)) throw InputError(item_key, scene_text(item), bound_text(bound) + ", not " + type_name(item));
    values.push_back(as_number(item));
    if (auto allowed = violates(values.back(), bound)) throw InputError(item_key, scene_text(item), *allowed);
  }
  return values;
}

std::vector<std::string> SceneTable::strings(std::string_view name) const {
  const auto& node = require(name, "an array of strings");
  const toml::array* array = node.as_array();
  if (!array) fail(name, "an array of strings, not " + type_name(node));
  std::vector<std::string> values;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = *array->get(i);
    if (!item.is_string())
      throw InputError(key(name) + "[" + std::to_string(i) + "]", scene_text(item), "a string, not " + type_name(item));
    values.push_back(item.as_string()->get());
  }
  return values;
}

SceneTable SceneTable::table(std::string_view name) const {
  const auto& node = require(name, "a table");
  if (!node.is_table()) fail(name, "a table, not " + type_name(node));
  return SceneTable(*node.as_table(), key(name));
}

std::vector<SceneTable> SceneTable::tables(std::string_view name) const {
  const auto& node = require(name, "an array of tables ([[" + std::string(name) + "]])");
  const toml::array* array = node.as_array();
  if (!array) fail(name, "an array of tables ([[" + std::string(name) + "]]), not " + type_name(node));
  std::vector<SceneTable> result;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = *array->get(i);
    const std::string item_key = key(name) + "[" + std::to_string(i) + "]";
    if (!item.is_table()) throw InputError(item_key, scene_text(item), "a table, not " + type_name(item));
    result.emplace_back(*item.as_table(), item_key);
  }
  return result;
}

std::optional<std::string> SceneTable::optional_string(std::string_view name) const {
  if (!contains(name)) return std::nullopt;
  return string(name);
}

std::optional<double> SceneTable::optional_number(std::string_view name, Bound bound) const {
  if (!contains(name)) return std::nullopt;
  return number(name, bound);
}

std::optional<std::size_t> SceneTable::optional_count(std::string_view name, std::size_t minimum) const {
  if (!contains(name)) return std::nullopt;
  return count(name, minimum);
}

std::optional<bool> SceneTable::optional_boolean(std::string_view name) const {
  if (!contains(name)) return std::nullopt;
  return boolean(name);
}

std::optional<SceneTable> SceneTable::optional_table(std::string_view name) const {
  if (!contains(name)) return std::nullopt;
  return table(name);
}

namespace {

// toml++ 3.3 parses nesting by recursion: a header or dotted key tens of thousands of levels deep overflows
// the stack. Scenes need a handful of levels, so the text is measured before the parser sees it: bracket
// depth ([ and {) and the components of one dotted key or table header, outside strings and comments.
constexpr std::size_t max_nesting = 64;

void check_nesting(std::string_view text, const std::string& source) {
  std::size_t depth = 0, dots = 0, line = 1;
  const auto fail = [&](const std::string& what) {
    throw InputError("scene", source,
                     what + " at line " + std::to_string(line) + ": at most " + std::to_string(max_nesting) +
                         " levels (a scene needs a few)");
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (c == '#') {  // comment: to the end of the line
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {  // basic or literal string, single- or multi-line
      const bool triple = text.substr(i, 3) == std::string(3, c);
      const std::string_view close = triple ? std::string_view(c == '"' ? "\"\"\"" : "'''") : std::string_view(&text[i], 1);
      for (i += triple ? 3 : 1; i < text.size() && text.substr(i, close.size()) != close; ++i) {
        if (text[i] == '\n') ++line;
        if (c == '"' && text[i] == '\\') ++i;  // an escape: skip the escaped character
      }
      if (triple) i += 2;
    } else if (c == '[' || c == '{') {
      if (++depth > max_nesting) fail("arrays or tables nested deeper");
      dots = 0;
    } else if (c == ']' || c == '}') {
      if (depth > 0) --depth;
      dots = 0;
    } else if (c == '.') {
      if (++dots > max_nesting) fail("a dotted key or table header with more components");
    } else if (c == '=' || c == ',' || c == '\n') {
      dots = 0;
    }
  }
}

}  // namespace

toml::table parse_toml_text(std::string_view text, const std::string& source) {
  check_nesting(text, source);
  try {
    return toml::parse(text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw InputError("scene", source,
                     "malformed TOML at line " + std::to_string(where.line) + ", column " + std::to_string(where.column) +
                         ": " + std::string(e.description()));
  }
}

std::string read_scene_file(const std::filesystem::path& path) {
  const std::string shown = path.string();
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw InputError("scene", shown, "a TOML file, not a folder");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError("scene", shown, std::string("a readable TOML file (") + std::strerror(errno) + ")");
  // A scene is a few kilobytes; reading stops past 4 MiB (e.g. /dev/zero, or a data file given by mistake).
  constexpr std::size_t max_bytes = std::size_t(4) << 20;
  std::string text(max_bytes + 1, '\0');
  file.read(text.data(), std::streamsize(text.size()));
  if (file.bad()) throw InputError("scene", shown, std::string("a readable TOML file (") + std::strerror(errno) + ")");
  text.resize(std::size_t(file.gcount()));
  if (text.size() > max_bytes) throw InputError("scene", shown, "a scene file of at most 4 MiB (this one is larger)");
  return text;
}

}  // namespace aggkit
