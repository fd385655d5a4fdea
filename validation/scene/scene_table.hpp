#pragma once
// Strict reading of one TOML table of a scene: keys are checked against the allowed
// set, values against their type and range, and every failure is an InputError that names the full
// dotted key (e.g. `engine[1].rtol`), the value as written and what is allowed.
// Internal to the scene parser and the engine parsers; needs toml++.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <filesystem>
#include <string>

#include <toml++/toml.h>

#include <nlohmann/json.hpp>

#include "analysis/input_error.hpp"
#include "analysis/option_rows.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

// Range constraints for numbers read from a scene.
enum class Bound {
  any,           // any number, NaN and inf included (the caller validates)
  finite,        // finite
  non_negative,  // finite and >= 0
  positive,      // finite and > 0
};

// Parses TOML text (a scene file's contents; `source` names it in messages); malformed TOML is an InputError
// naming the line and column.
toml::table parse_toml_text(std::string_view text, const std::string& source);
// The text of a scene file; InputError (key "scene") for a folder, a missing or an unreadable file.
std::string read_scene_file(const std::filesystem::path& path);

// A TOML value as JSON, the form option rows read; dates and times, which no option takes, are refused
// under `key`.
nlohmann::json toml_json(const toml::node& node, const std::string& key);

class SceneTable {
 public:
  // `path` is the dotted key of the table itself: "" for the root, "model", "engine[0]".
  SceneTable(const toml::table& table, std::string path);

  // Throws InputError naming the first key that is not in `allowed`, listing the allowed keys.
  void allow_only(const std::vector<std::string>& allowed) const;

  const std::string& path() const { return path_; }
  std::string key(std::string_view name) const;  // full dotted key of an entry
  bool contains(std::string_view name) const { return table_->contains(name); }
  const toml::node* find(std::string_view name) const { return table_->get(name); }
  const toml::table& raw() const { return *table_; }

  // Required entries: a missing key or a value of the wrong type throws InputError.
  std::string string(std::string_view name) const;
  double number(std::string_view name, Bound bound = Bound::finite) const;
  std::size_t count(std::string_view name, std::size_t minimum) const;  // an integer >= minimum
  bool boolean(std::string_view name) const;
  std::vector<double> numbers(std::string_view name, Bound bound = Bound::finite) const;
  std::vector<std::string> strings(std::string_view name) const;
  SceneTable table(std::string_view name) const;
  std::vector<SceneTable> tables(std::string_view name) const;  // an array of tables ([[engine]])

  // Optional entries: std::nullopt when the key is absent; a present value is checked as above.
  std::optional<std::string> optional_string(std::string_view name) const;
  std::optional<double> optional_number(std::string_view name, Bound bound = Bound::finite) const;
  std::optional<std::size_t> optional_count(std::string_view name, std::size_t minimum) const;
  std::optional<bool> optional_boolean(std::string_view name) const;
  std::optional<SceneTable> optional_table(std::string_view name) const;

  // The entries of this table that `rows` declare (analysis/option_rows.hpp), each checked against its row
  // (type, range) and set in `settings`; entries the rows do not declare are left to the caller.
  template <class S>
  void read_rows(const OptionRows<S>& rows, S& settings) const {
    nlohmann::json given = nlohmann::json::object();
    for (const OptionRow<S>& row : rows.rows())
      if (const toml::node* node = find(row.spec.key)) {
        nlohmann::json& value = given[row.spec.key] = toml_json(*node, key(row.spec.key));
        check_option(row.spec, value, key(row.spec.key));
      }
    rows.apply(given, settings, path_);
  }
  // Entry `name` as a sub-table of the keys `rows` declare: unknown keys refused, required ones demanded,
  // each value checked against its row and set in `settings`. False (nothing read) when it is absent.
  template <class S>
  bool read_table(std::string_view name, const OptionRows<S>& rows, S& settings) const {
    const toml::node* node = find(name);
    if (!node) return false;
    OptionSpec spec;
    spec.key = std::string(name), spec.type = OptionSpec::Type::table, spec.rows = rows.table();
    const nlohmann::json value = toml_json(*node, key(name));
    check_option(spec, value, key(name));
    rows.apply(value, settings, key(name));
    return true;
  }

  // Throws InputError for entry `name` with its value as written.
  [[noreturn]] void fail(std::string_view name, const std::string& allowed) const;

 private:
  const toml::node& require(std::string_view name, const std::string& expected) const;
  const toml::table* table_;
  std::string path_;
};

// The value of a node as a reader would write it (strings quoted, numbers shortest), cut to a sane length.
std::string scene_text(const toml::node& node);
// Library validators may name keys in their own terms (IntegratorOptions says "engine.rtol", not
// "engine[1].rtol"); the scene re-throws their InputError under the scene's dotted key. `scene_key` receives the
// library's key and returns the scene's; the rest of the message (value and what is allowed) is kept.
InputError rekeyed(const InputError& error, const std::string& scene_key);
template <class F>
auto under_key(const std::function<std::string(const std::string&)>& scene_key, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) {
    throw rekeyed(e, scene_key(e.key()));
  }
}
// The last component of a dotted key ("engine[0].rtol" -> "rtol").
std::string leaf_key(const std::string& key);

}  // namespace aggkit
