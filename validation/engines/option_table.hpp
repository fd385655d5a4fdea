#pragma once
// The options of one [[engine]] table. Each engine kind's table is the rows of the settings it configures
// (analysis/option_rows.hpp: key, type, range, doc and the field each sets, declared with the physics in
// solvers/ or particle/<engine>/); the table drives the check of a scene's [[engine]] table (unknown keys,
// types and ranges refused with the dotted key `engine[i].key`, the value and what is allowed), the reading
// of the values into the settings, the engines section of `aggkit run --help`, and the keyword arguments
// (and their defaults) of the Python module.
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "analysis/option_rows.hpp"

namespace aggkit {

// The options given to one engine, checked against its table. Values are JSON (a scene's TOML table, or
// the keyword arguments of a Python call).
class EngineOptions {
 public:
  // Throws InputError for a key not in `table`, a value of the wrong type or out of range; `path` names
  // the table in messages ("engine[1]").
  EngineOptions(const OptionTable& table, const nlohmann::json& given, std::string path);

  bool has(std::string_view key) const { return given_.contains(std::string(key)); }
  const nlohmann::json& value(std::string_view key) const { return given_.at(std::string(key)); }
  // Sets the fields of `settings` for every given key that `rows` bind.
  template <class S>
  void read(const OptionRows<S>& rows, S& settings) const { rows.apply(given_, settings, path_); }

  std::string key(std::string_view name) const { return path_ + "." + std::string(name); }
  const std::string& path() const { return path_; }
  // InputError for option `name` with its value as given.
  [[noreturn]] void fail(std::string_view name, const std::string& allowed) const;

 private:
  nlohmann::json given_;
  std::string path_;
};

// An engine's table: the rows of each settings type it configures, in order.
template <class... S>
OptionTable option_table(const OptionRows<S>&... rows) {
  OptionTable table;
  const auto add = [&table](const OptionTable& part) { table.insert(table.end(), part.begin(), part.end()); };
  (add(rows.table()), ...);
  return table;
}

}  // namespace aggkit
